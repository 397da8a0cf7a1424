// meshfit: how many threads meshfit's computations use.
//
// Two pools of threads work inside the compiled core: OpenMP's (the RBF evaluation in `deform` and
// `fit`, the smoothing flows of `smooth.h`, Eigen's products) and OpenBLAS's (the LU of the RBF
// system, through LAPACK; CHOLMOD's factorisation always runs OpenBLAS on one thread). By default
// both take every core. Either limit them before the program starts, with the environment variables
// OMP_NUM_THREADS and OPENBLAS_NUM_THREADS (read once, when each library loads), or call
// set_number_of_threads() (what `meshfit --threads N` does), or pass the named parameter
// `number_of_threads(n)` to a stage, which limits them for that call only (Scoped_number_of_threads).
#ifndef MESHFIT_THREADS_H
#define MESHFIT_THREADS_H

#include <meshfit/internal/openblas_threads.h>

#include <optional>

namespace meshfit {

/// Limits meshfit's computations to `n` threads: `omp_set_num_threads(n)` and
/// `openblas_set_num_threads(n)`. OpenMP's setting belongs to the calling thread: call it from the
/// thread that will run the stages, before it runs them. It applies to everything else in the
/// process that uses OpenMP on that thread, or OpenBLAS, too (these settings are process-wide).
/// \throws Invalid_input when `n` is less than 1.
void set_number_of_threads(int n);

/// The number of threads an OpenMP loop of meshfit started from the calling thread would use now
/// (`omp_get_max_threads()`; 1 in a build without OpenMP).
int number_of_threads();

/// Limits meshfit's threads to `n` as set_number_of_threads() does, for its own lifetime: the
/// destructor puts OpenMP's (on the calling thread) and OpenBLAS's counts back as they were.
/// `n` = 0 changes nothing. What the named parameter `number_of_threads` does around a stage.
/// \throws Invalid_input when `n` is negative.
class Scoped_number_of_threads {
 public:
  /// Sets the counts to `n` (0: leaves them).
  explicit Scoped_number_of_threads(int n);
  /// Puts the counts back.
  ~Scoped_number_of_threads();
  /// Not copyable.
  Scoped_number_of_threads(const Scoped_number_of_threads&) = delete;
  /// Not copyable.
  Scoped_number_of_threads& operator=(const Scoped_number_of_threads&) = delete;

 private:
  int m_openmp = 0;  // the count to put back; 0: nothing was changed
  std::optional<internal::Scoped_openblas_threads> m_openblas;
};

}  // namespace meshfit

#endif  // MESHFIT_THREADS_H
