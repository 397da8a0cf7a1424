#include <meshfit/exceptions.h>
#include <meshfit/internal/format_number.h>
#include <meshfit/memory_limit.h>

#include <unistd.h>

namespace meshfit {

std::size_t default_memory_limit() {
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGESIZE);
  if (pages <= 0 || page <= 0) return std::size_t(2) << 30;
  return static_cast<std::size_t>(pages) / 8 * static_cast<std::size_t>(page);
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
                                       " (--max-memory, the named parameter memory_limit)");
}

}  // namespace meshfit
