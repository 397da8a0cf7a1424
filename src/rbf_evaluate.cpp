// The RBF inner loop. Points are the inner loop (independent accumulators, no reduction), so it
// vectorises without reassociating floating-point sums; this file is compiled with
// -fno-math-errno so that sqrt vectorises, and cloned for AVX-512, AVX2 and baseline x86-64.
#include "rbf_evaluate.h"

#include <cmath>

namespace meshfit {
namespace internal {

namespace {

template <bool Cubic>
inline void sum_block(const Rbf_arrays& a, const double* __restrict px, const double* __restrict py,
                      const double* __restrict pz, std::size_t count, double* __restrict sx,
                      double* __restrict sy, double* __restrict sz) {
  for (std::size_t i = 0; i < count; ++i) sx[i] = sy[i] = sz[i] = 0.0;
  for (std::size_t j = 0; j < a.n; ++j) {
    const double cx = a.cx[j], cy = a.cy[j], cz = a.cz[j];
    const double ax = a.ax[j], ay = a.ay[j], az = a.az[j];
#pragma GCC ivdep
    for (std::size_t i = 0; i < count; ++i) {
      const double dx = px[i] - cx, dy = py[i] - cy, dz = pz[i] - cz;
      double w = std::sqrt(dx * dx + dy * dy + dz * dz);
      if (Cubic) w = w * w * w;
      sx[i] += ax * w;
      sy[i] += ay * w;
      sz[i] += az * w;
    }
  }
}

}  // namespace

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && !defined(__SANITIZE_ADDRESS__)
__attribute__((target_clones("avx512f", "avx2", "default")))
#endif
void rbf_sum_block(const Rbf_arrays& a, const double* px, const double* py, const double* pz,
                   std::size_t count, double* sx, double* sy, double* sz) {
  if (a.kernel == Rbf_kernel::cubic) sum_block<true>(a, px, py, pz, count, sx, sy, sz);
  else sum_block<false>(a, px, py, pz, count, sx, sy, sz);
}

}  // namespace internal
}  // namespace meshfit
