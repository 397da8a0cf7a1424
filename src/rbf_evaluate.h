// Private: the blocked, vectorised RBF sum used by Rbf_interpolant::evaluate.
#ifndef MESHFIT_SRC_RBF_EVALUATE_H
#define MESHFIT_SRC_RBF_EVALUATE_H

#include <meshfit/rbf.h>

#include <cstddef>

namespace meshfit {
namespace internal {

struct Rbf_arrays {
  Rbf_kernel kernel;
  const double *cx, *cy, *cz, *ax, *ay, *az;
  std::size_t n;
};

/// Number of points evaluated together: their coordinates and sums (6 arrays) stay in L1.
constexpr std::size_t rbf_block = 256;

/// s[i] = Σ_j a_j φ(‖p_i − c_j‖) for the `count` ≤ rbf_block points of a block, with the fastest
/// kernel the CPU runs.
void rbf_sum_block(const Rbf_arrays& a, const double* px, const double* py, const double* pz,
                   std::size_t count, double* sx, double* sy, double* sz);
/// The same with the portable kernel (exact IEEE sqrt), for tests and CPUs without AVX-512.
void rbf_sum_block_portable(const Rbf_arrays& a, const double* px, const double* py, const double* pz,
                   std::size_t count, double* sx, double* sy, double* sz);

}  // namespace internal
}  // namespace meshfit

#endif  // MESHFIT_SRC_RBF_EVALUATE_H
