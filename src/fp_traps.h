// Private: in the checked build (MESHFIT_FP_TRAPS, set with MESHFIT_SANITIZE), floating-point
// division by zero and invalid operations raise SIGFPE inside meshfit's own numeric code, so a
// NaN or an infinity fails where it arises instead of surfacing later. A no-op otherwise.
#ifndef MESHFIT_SRC_FP_TRAPS_H
#define MESHFIT_SRC_FP_TRAPS_H

#if defined(MESHFIT_FP_TRAPS) && defined(__GLIBC__)
#include <fenv.h>
#endif

namespace meshfit {
namespace internal {

class Fp_trap_scope {
 public:
#if defined(MESHFIT_FP_TRAPS) && defined(__GLIBC__)
  Fp_trap_scope() : m_old(fegetexcept()) {
    feclearexcept(FE_ALL_EXCEPT);
    feenableexcept(FE_DIVBYZERO | FE_INVALID);
  }
  ~Fp_trap_scope() {
    fedisableexcept(FE_ALL_EXCEPT);
    feenableexcept(m_old);
  }

 private:
  int m_old;
#else
  Fp_trap_scope() {}
#endif
  Fp_trap_scope(const Fp_trap_scope&) = delete;
  Fp_trap_scope& operator=(const Fp_trap_scope&) = delete;
};

}  // namespace internal
}  // namespace meshfit

#endif  // MESHFIT_SRC_FP_TRAPS_H
