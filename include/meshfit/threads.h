// meshfit: how many threads meshfit's computations use.
//
// Two pools of threads work inside the compiled core: OpenMP's (the RBF evaluation in `deform` and
// `fit`, the smoothing flows of `smooth.h`, Eigen's products) and OpenBLAS's (the LU of the RBF
// system, through LAPACK; CHOLMOD's factorisation always runs OpenBLAS on one thread). By default
// both take every core. Either limit them before the program starts, with the environment variables
// OMP_NUM_THREADS and OPENBLAS_NUM_THREADS (read once, when each library loads), or call
// set_number_of_threads() (what `meshfit --threads N` does).
#ifndef MESHFIT_THREADS_H
#define MESHFIT_THREADS_H

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

}  // namespace meshfit

#endif  // MESHFIT_THREADS_H
