#!/usr/bin/env bash
# Builds meshfit and runs it on the embedded example (examples/data), writing to out/example/.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/scripts/install-deps.sh"
"$root/scripts/build.sh" "$root/build"

out="$root/out/example"
mkdir -p "$out"
data="$root/examples/data"
# The inputs checked, then the whole pipeline in one command (out/example/fit.ply and its report).
"$root/build/meshfit" check --template "$data/template.off" --curves "$data/curves.polylines.txt" \
  --correspondences "$data/pairs.txt" | tee "$out/check.txt"
"$root/build/meshfit" fit --template "$data/template.off" --curves "$data/curves.polylines.txt" \
  --correspondences "$data/pairs.txt" --output "$out/fit.ply" --report "$out/fit-report.json"
# The same, stage by stage, to look at each stage's result.
"$root/build/meshfit" deform --quiet --template "$data/template.off" --curves "$data/curves.polylines.txt" \
  --correspondences "$data/pairs.txt" --output "$out/deformed.ply" --report "$out/deform-report.json"
"$root/build/meshfit" partition --quiet --template "$out/deformed.ply" --curves "$data/curves.polylines.txt" \
  --output "$out/partitioned.ply" --report "$out/partition-report.json"
"$root/build/meshfit" smooth --quiet --template "$out/partitioned.ply" --curves "$data/curves.polylines.txt" \
  --output "$out/smoothed.ply" --report "$out/smooth-report.json"
# Everything in one page (open it in a browser): the inputs, the pairs (pick new ones there), and
# each stage's result with its report.
"$root/build/meshfit" view --quiet --template "$data/template.off" --curves "$data/curves.polylines.txt" \
  --correspondences "$data/pairs.txt" \
  --result "$out/deformed.ply" --result-report "$out/deform-report.json" \
  --result "$out/partitioned.ply" --result-report "$out/partition-report.json" \
  --result "$out/smoothed.ply" --result-report "$out/smooth-report.json" \
  --result "$out/fit.ply" --result-report "$out/fit-report.json" --output "$out/view.html"
echo "meshfit: outputs written to $out (open $out/view.html in a browser)" >&2
