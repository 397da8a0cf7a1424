// meshfit: OpenBLAS's thread count set for a scope (threads.h's Scoped_number_of_threads holds one,
// and so do the CHOLMOD solves of src/displacement.cpp); compiled in src/threads.cpp.
#ifndef MESHFIT_INTERNAL_OPENBLAS_THREADS_H
#define MESHFIT_INTERNAL_OPENBLAS_THREADS_H

namespace meshfit {
namespace internal {
/// Sets OpenBLAS's thread count (only; OpenMP's is left) to `n` for its own lifetime: the
/// destructor puts it back as it was. Scoped_number_of_threads holds one; the CHOLMOD solves of
/// displacement.cpp hold one with `n` = 1 around their factorisation.
class Scoped_openblas_threads {
 public:
  explicit Scoped_openblas_threads(int n);  ///< sets the count to `n` (at least 1)
  ~Scoped_openblas_threads();               ///< puts it back
  Scoped_openblas_threads(const Scoped_openblas_threads&) = delete;
  Scoped_openblas_threads& operator=(const Scoped_openblas_threads&) = delete;

 private:
  int m_previous;  // the count to put back
};
}  // namespace internal
}  // namespace meshfit

#endif  // MESHFIT_INTERNAL_OPENBLAS_THREADS_H
