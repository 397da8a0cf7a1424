// meshfit: a bound on the largest allocations (the dense RBF systems; the command line also bounds
// reading its inputs), so that an input too large for the machine is refused with an estimate
// instead of being killed.
#ifndef MESHFIT_MEMORY_LIMIT_H
#define MESHFIT_MEMORY_LIMIT_H

#include <cstddef>
#include <string>

namespace meshfit {

/// The default of the `memory_limit` named parameter: an eighth of the machine's physical memory,
/// at most 2 GiB (2 GiB when it cannot be determined).
std::size_t default_memory_limit();

/// "3.8 GB" (decimal units, three significant digits).
std::string format_bytes(double bytes);

/// \throws Algorithm_failure for `stage` when `bytes` exceeds `limit` (0: default_memory_limit()),
///         saying what needs them (`what`: "the fine RBF's dense 15408×15408 system") and both sizes.
void check_memory_estimate(double bytes, std::size_t limit, const std::string& stage, const std::string& what);

}  // namespace meshfit

#endif  // MESHFIT_MEMORY_LIMIT_H
