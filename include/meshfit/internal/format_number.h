// meshfit internal: numbers in messages with significant digits (1.2e-17, 0.25, 3e+08), never
// fixed decimals that print a small residual as 0.000000.
#ifndef MESHFIT_INTERNAL_FORMAT_NUMBER_H
#define MESHFIT_INTERNAL_FORMAT_NUMBER_H

#include <cstdio>
#include <string>

namespace meshfit {
namespace internal {

/// `v` with `digits` significant digits, as printf's %g ("nan" and "inf" as printf writes them).
inline std::string format_number(double v, int digits = 3) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  return buf;
}

}  // namespace internal
}  // namespace meshfit

#endif  // MESHFIT_INTERNAL_FORMAT_NUMBER_H
