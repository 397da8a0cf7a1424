#!/usr/bin/env bash
# Time-boxed fuzzing of every target (libFuzzer, clang-14, ASan + UBSan), not part of CI:
#   scripts/fuzz.sh [seconds per target, default 30] [target...]
# New interesting inputs go to build-fuzz/corpus/<target> (the committed corpus in fuzz/corpus is
# only read); a crash is written to fuzz/reproducers/<target>/ so that, once fixed, it is
# committed and replayed by every test run.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
seconds="${1:-30}"
shift || true
"$root/scripts/install-deps.sh"
need=()
for p in clang-14 libclang-rt-14-dev; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || need+=("$p")
done
if [ ${#need[@]} -gt 0 ]; then
  sudo_cmd=(); [ "$(id -u)" -ne 0 ] && sudo_cmd=(sudo)
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${need[@]}" >/dev/null
fi
build="$root/build-fuzz"
CC=clang-14 CXX=clang++-14 cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DMESHFIT_FUZZ=ON \
  -DMESHFIT_BUILD_TESTS=OFF -DMESHFIT_BUILD_EXAMPLES=OFF -DMESHFIT_BUILD_BATTERY=OFF >/dev/null
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(off obj ply stl polylines correspondences check flip rbf deform fit)
cmake --build "$build" --parallel "$(nproc)" --target "${targets[@]/#/fuzz_}" >/dev/null
# A unit may take 60 s: the stage targets' untangling runs 30-200 times slower under the coverage
# instrumentation and the sanitizers (fuzz/reproducers/deform/slow-untangle-539b164f: 0.17 s in
# release, 4.5 s under GCC's ASan, 34 s here); with 10 s, deform and fit stopped at their first
# such input after 2 and 11 units.
for t in "${targets[@]}"; do
  mkdir -p "$build/corpus/$t" "$root/fuzz/reproducers/$t"
  echo "== $t ($seconds s)"
  UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 ASAN_OPTIONS=detect_leaks=1 \
    "$build/fuzz/fuzz_$t" -max_total_time="$seconds" -timeout=60 -rss_limit_mb=2048 -max_len=65536 \
    -artifact_prefix="$root/fuzz/reproducers/$t/" -print_final_stats=1 \
    "$build/corpus/$t" "$root/fuzz/corpus/$t" 2>&1 | grep -E "stat::number_of_executed_units|Done|ERROR|SUMMARY|crash-|timeout-|oom-" || true
done
