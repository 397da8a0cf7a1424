#!/usr/bin/env bash
# Issue 12's scale benchmark: `meshfit fit` per stage on icosphere templates of 81 920, 327 680 and
# 1 310 720 faces (under a random rotation) onto the bumpy blob with latitude/longitude networks of
# about 2 000, 6 000 and 20 000 vertices (cases from `make_battery --scale`), side by side in one run
# with the thesis's fine level (`--fine-level thesis`, up to --thesis-up-to faces, each run cut at
# --timeout seconds) and a do-it-yourself SciPy script (diy_scipy.py: the two RBF levels only).
# Prints one table (seconds, peak MB, verified or why not, and what the battery's independent scorer,
# score_fit, finds in each meshfit output) and the growth factor between sizes.
# Installs SciPy when missing (bench/install-peers.sh).
#   bench/scale/run.sh [--build DIR] [--work DIR] [--timeout S] [--thesis-up-to FACES] [--no-build]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="$root/build" work="" timeout_s=600 thesis_max=400000 do_build=1
while [ $# -gt 0 ]; do
  case "$1" in
    --build) build="$2"; shift 2 ;;
    --work) work="$2"; shift 2 ;;
    --timeout) timeout_s="$2"; shift 2 ;;
    --thesis-up-to) thesis_max="$2"; shift 2 ;;
    --no-build) do_build=0; shift ;;
    *) echo "usage: bench/scale/run.sh [--build DIR] [--work DIR] [--timeout S] [--thesis-up-to FACES] [--no-build]" >&2; exit 2 ;;
  esac
done
if [ -z "$work" ]; then work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT; fi
"$root/bench/install-peers.sh"
py=/usr/bin/python3   # Debian's python, where python3-scipy lives
if [ "$do_build" = 1 ]; then
  cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build "$build" --parallel "$(nproc)" --target meshfit_cli make_battery score_fit >/dev/null
fi
meshfit="$build/meshfit"
[ -d "$work/cases" ] || "$build/bench/battery/make_battery" --scale "$work/cases" 2>/dev/null

field() { sed -n "s/^$2 //p" "$1/case.txt"; }
# run_fit CASE_DIR [meshfit fit options]: sets seconds, mb, stages (the report's per-stage times), verdict,
# and scored: score_fit's regions / inverted / folded / self-intersections / Hausdorff % / smallest angle / result.
run_fit() {
  local dir="$1"; shift
  local out="$work/out.off" rep="$work/report.json" status=0
  rm -f "$out" "$rep"
  /usr/bin/time -f "%e %M" -o "$work/time.txt" timeout "$timeout_s" "$meshfit" fit --quiet \
    --template "$dir/template.off" --curves "$dir/curves.polylines.txt" --correspondences "$dir/pairs.txt" \
    --output "$out" --report "$rep" "$@" 2>"$work/stderr.txt" || status=$?
  read -r seconds kb < <(tail -1 "$work/time.txt")
  mb=$((kb / 1024))
  stages="-"
  if [ -s "$rep" ]; then
    stages=$("$py" -c 'import json,sys; t=json.load(open(sys.argv[1]))["timings_s"]; print(" / ".join("%.1f" % t.get(k, 0) for k in ("deform","partition","smooth","verify")))' "$rep")
  fi
  case $status in
    0) verdict="verified" ;;
    124) verdict="timeout ${timeout_s} s" ;;
    *) verdict="exit $status: $(grep -m1 -o 'failed: .*' "$work/stderr.txt" | cut -c9-90 || true)" ;;
  esac
  scored="-"
  if [ "$status" = 0 ]; then
    scored=$("$build/bench/battery/score_fit" "$dir" "$out" 0 "$seconds" "$work/stderr.txt" x |
      awk -F'|' '{gsub(/ /, "", $7); gsub(/ /, "", $8); gsub(/ /, "", $9); gsub(/ /, "", $10); gsub(/ /, "", $11); gsub(/ /, "", $12);
                  sub(/^ +/, "", $14); sub(/ +$/, "", $14); print $7 " / " $8 " / " $9 " / " $10 " / " $11 " / " $12 " / " $14}' || true)
  fi
}

echo "meshfit $("$meshfit" --version 2>/dev/null | head -1), $(nproc) cores, $(date -u +%F)"
echo
echo "| case | faces | network V | method | s | peak MB | deform / partition / smooth / verify s | result | score_fit: regions / inverted / folded / self-int. / Hausdorff % / min angle / result |"
echo "|---|--:|--:|---|--:|--:|---|---|---|"
declare -a sizes ours thesis diy
while read -r name; do
  dir="$work/cases/$name"
  faces=$(field "$dir" template_faces) nv=$(field "$dir" network_vertices)
  run_fit "$dir"
  echo "| $name | $faces | $nv | meshfit (surface) | $seconds | $mb | $stages | $verdict | $scored |"
  sizes+=("$faces") ours+=("$seconds")
  if [ "$faces" -le "$thesis_max" ]; then
    run_fit "$dir" --fine-level thesis
    echo "| | | | meshfit --fine-level thesis | $seconds | $mb | $stages | $verdict | $scored |"
    thesis+=("$seconds")
  else
    echo "| | | | meshfit --fine-level thesis | - | - | - | not run (above --thesis-up-to $thesis_max faces) | - |"
    thesis+=("-")
  fi
  line=$(timeout "$timeout_s" "$py" "$root/bench/scale/diy_scipy.py" "$dir" 2>&1 | tail -1 || true)
  s=$(echo "$line" | sed -n 's/.*seconds \([0-9.]*\).*/\1/p') m=$(echo "$line" | sed -n 's/.*peak_mb \([0-9]*\).*/\1/p')
  if [ -n "$s" ]; then verdict="not verified (no flip prevention, partition nor smoothing)"; else verdict="failed: $line"; fi
  echo "| | | | SciPy do-it-yourself (coarse + fine RBF only) | ${s:--} | ${m:--} | - | $verdict | - |"
  diy+=("${s:--}")
done < "$work/cases/cases.txt"

echo
echo "| method | growth of the time per step (faces ×4 each) |"
echo "|---|---|"
growth() {
  local label="$1"; shift
  local -a t=("$@") g=()
  for ((i = 1; i < ${#t[@]}; i++)); do
    if [ "${t[i]}" = - ] || [ "${t[i-1]}" = - ]; then g+=("-"); else g+=("$(awk -v a="${t[i-1]}" -v b="${t[i]}" 'BEGIN{printf "%.1f", b / (a > 0 ? a : 1e-9)}')x"); fi
  done
  echo "| $label | ${g[*]} |"
}
growth "meshfit (surface)" "${ours[@]}"
growth "meshfit --fine-level thesis" "${thesis[@]}"
growth "SciPy do-it-yourself" "${diy[@]}"
echo
echo "| size | meshfit (surface) / SciPy do-it-yourself, time ratio |"
echo "|---|---|"
for ((i = 0; i < ${#ours[@]}; i++)); do
  [ "${diy[i]}" = - ] && continue
  echo "| ${sizes[i]} faces | $(awk -v a="${ours[i]}" -v b="${diy[i]}" 'BEGIN{printf "%.2f", a / b}') |"
done
