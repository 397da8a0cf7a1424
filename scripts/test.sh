#!/usr/bin/env bash
# Builds meshfit and runs the whole test suite: once in a release build, then once more with
# AddressSanitizer and UndefinedBehaviorSanitizer (build-asan/). Set MESHFIT_SKIP_SANITIZE=1 to
# run the release build only.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/scripts/install-deps.sh"

jobs="$(nproc)"
# OpenBLAS picks its kernels by CPU; results that hang on a last bit then differ between machines
# (on an AMD EPYC with AVX-512, the SkylakeX kernels leave one segment of the pig example not
# embedded where Haswell's and Zen's embed all). The tests run on one kernel everywhere.
export OPENBLAS_CORETYPE="${OPENBLAS_CORETYPE:-Haswell}"
"$root/scripts/build.sh" "$root/build"
(cd "$root/build" && ctest --output-on-failure --parallel "$jobs")

if [ "${MESHFIT_SKIP_SANITIZE:-0}" != 1 ]; then
  # -O1 and line tables only (-g1): the sanitizers' usual level, and compiles 2.5 times faster than
  # RelWithDebInfo's -O2 -g (fit_test.cpp: 158 s against 400 s, 2.0 against 3.0 GB).
  "$root/scripts/build.sh" "$root/build-asan" -DMESHFIT_SANITIZE=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" -DMESHFIT_BUILD_EXAMPLES=OFF -DMESHFIT_BUILD_BATTERY=OFF
  # The tests of other programs reading meshfit's outputs (a browser, f3d, meshio), of the
  # installed package and of the reference run in the release build only: under the sanitizers
  # they would check the same meshfit code again (the command-line tests cover it) at several
  # times the cost, or nothing compiled at all (the reference). The example translated by 1e15
  # (a whole fit and deform on faces of no area: 16 s in release, 8 min under the sanitizers)
  # runs in the release build only, and so does the command line's second-start test (two deforms
  # of ico2562-onto-pig, about 3 min under the sanitizers), whose library code the deform test of
  # the same case checks there.
  (cd "$root/build-asan" && ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 \
     UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
     ctest --output-on-failure --parallel "$jobs" \
       -E "install_and_consume|doxygen_reference|view_browser|render_example|meshio_roundtrip|f3d_output|far from the origin: fit and deform end|cli: deform makes the second start")
fi
