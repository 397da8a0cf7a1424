#include <meshfit/exceptions.h>
#include <meshfit/internal/format_number.h>
#include <meshfit/memory_limit.h>

#include <unistd.h>

#include <algorithm>

namespace meshfit {

std::size_t default_memory_limit() {
  // At most 2 GiB, so that what is refused does not depend on the machine: with RAM / 8 alone, a
  // 15 000-vertex network's thesis level (3.6 GB) was refused on 24 GB and ran out of time on 64 GB.
  const std::size_t most = std::size_t(2) << 30;
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGESIZE);
  if (pages <= 0 || page <= 0) return most;
  return std::min(most, static_cast<std::size_t>(pages) / 8 * static_cast<std::size_t>(page));
}

std::string format_bytes(double bytes) {
  const char* units[] = {"B", "kB", "MB", "GB", "TB", "PB"};
  int u = 0;
  while (bytes >= 1000 && u < 5) {
    bytes /= 1000;
    ++u;
  }
  return internal::format_number(bytes) + " " + units[u];
}

void check_memory_estimate(double bytes, std::size_t limit, const std::string& stage, const std::string& what) {
  if (limit == 0) limit = default_memory_limit();
  if (bytes > static_cast<double>(limit))
    throw Algorithm_failure(stage, what + " needs about " + format_bytes(bytes) + ", over the memory limit of " +
                                       format_bytes(static_cast<double>(limit)) +
                                       " (--max-memory, the named parameter memory_limit)",
                            {{"estimated_bytes", bytes}, {"memory_limit_bytes", static_cast<double>(limit)}});
}

}  // namespace meshfit
