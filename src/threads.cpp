#include <meshfit/exceptions.h>
#include <meshfit/threads.h>

#include <string>

#ifdef _OPENMP
#include <omp.h>
#endif

// OpenBLAS (the BLAS CMake links, BLA_VENDOR OpenBLAS; Debian's pthread build has its own pool,
// which OpenMP's setting does not reach).
extern "C" void openblas_set_num_threads(int);
extern "C" int openblas_get_num_threads(void);

namespace meshfit {

void set_number_of_threads(int n) {
  if (n < 1) throw Invalid_input("the number of threads must be at least 1, not " + std::to_string(n));
#ifdef _OPENMP
  omp_set_num_threads(n);
#endif
  openblas_set_num_threads(n);
}

int number_of_threads() {
#ifdef _OPENMP
  return omp_get_max_threads();
#else
  return 1;
#endif
}

internal::Scoped_openblas_threads::Scoped_openblas_threads(int n) : m_previous(openblas_get_num_threads()) {
  openblas_set_num_threads(n);
}

internal::Scoped_openblas_threads::~Scoped_openblas_threads() { openblas_set_num_threads(m_previous); }

Scoped_number_of_threads::Scoped_number_of_threads(int n) {
  if (n < 0) throw Invalid_input("number_of_threads must be at least 1, not " + std::to_string(n));
  if (n == 0) return;
  const int openmp = number_of_threads();
#ifdef _OPENMP
  omp_set_num_threads(n);
#endif
  m_openmp = openmp;
  m_openblas.emplace(n);
}

// OpenMP's count here, OpenBLAS's in m_openblas's destructor, after.
Scoped_number_of_threads::~Scoped_number_of_threads() {
#ifdef _OPENMP
  if (m_openmp != 0) omp_set_num_threads(m_openmp);
#endif
}

}  // namespace meshfit
