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
echo "meshfit: outputs written to $out" >&2
