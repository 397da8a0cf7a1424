// Private: the blocked, vectorised RBF sum used by Rbf_interpolant::evaluate.
#ifndef MESHFIT_SRC_RBF_EVALUATE_H
#define MESHFIT_SRC_RBF_EVALUATE_H

#include <meshfit/rbf.h>

#include <algorithm>
#include <cstddef>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace meshfit {
namespace internal {

struct Rbf_arrays {
  Rbf_kernel kernel;
  const double *cx, *cy, *cz, *ax, *ay, *az;
  std::size_t n;
};

/// Number of points evaluated together: their coordinates and sums (6 arrays) stay in L1.
constexpr std::size_t rbf_block = 256;

/// s[i] = Σ_j a_j φ(‖p_i − c_j‖) for the `count` ≤ rbf_block points of a block. Compiled for
/// several instruction sets and chosen at run time.
void rbf_sum_block(const Rbf_arrays& a, const double* px, const double* py, const double* pz,
                   std::size_t count, double* sx, double* sy, double* sz);

/// Evaluates `count` points in blocks on `threads` threads (0: all): `load(i, x, y, z)` gives the
/// normalised point i, `store(i, x, y, z, sx, sy, sz)` receives it with its RBF sums. All points of
/// a block are loaded before any of them is stored, so the output may overwrite the input.
template <typename Load, typename Store>
void rbf_evaluate_blocks(const Rbf_arrays& a, std::size_t count, unsigned threads, Load load, Store store) {
  const std::ptrdiff_t blocks = static_cast<std::ptrdiff_t>((count + rbf_block - 1) / rbf_block);
  int nt = 1;
#ifdef _OPENMP
  nt = threads == 0 ? omp_get_max_threads() : static_cast<int>(threads);
  nt = static_cast<int>(std::min<std::ptrdiff_t>(nt, std::max<std::ptrdiff_t>(blocks, 1)));
#else
  (void)threads;
#endif
#pragma omp parallel for schedule(dynamic, 4) num_threads(nt)
  for (std::ptrdiff_t b = 0; b < blocks; ++b) {
    alignas(64) double px[rbf_block], py[rbf_block], pz[rbf_block], sx[rbf_block], sy[rbf_block],
        sz[rbf_block];
    const std::size_t first = static_cast<std::size_t>(b) * rbf_block;
    const std::size_t m = std::min(rbf_block, count - first);
    for (std::size_t i = 0; i < m; ++i) load(first + i, px[i], py[i], pz[i]);
    rbf_sum_block(a, px, py, pz, m, sx, sy, sz);
    for (std::size_t i = 0; i < m; ++i) store(first + i, px[i], py[i], pz[i], sx[i], sy[i], sz[i]);
  }
}

}  // namespace internal
}  // namespace meshfit

#endif  // MESHFIT_SRC_RBF_EVALUATE_H
