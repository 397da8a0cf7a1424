#!/usr/bin/env bash
# Builds meshfit and runs it on the embedded example (examples/data), writing to out/example/.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/scripts/install-deps.sh"
"$root/scripts/build.sh" "$root/build"

out="$root/out/example"
mkdir -p "$out"
data="$root/examples/data"
# The full pipeline (meshfit fit) replaces these once it exists: the inputs checked, then stage 1
# (the template deformed onto the curves), stage 2 (the curves made edges, regions labelled) and
# stage 3 (smoothed with the curves fixed).
"$root/build/meshfit" check --template "$data/template.off" --curves "$data/curves.polylines.txt" \
  --correspondences "$data/pairs.txt" | tee "$out/check.txt"
"$root/build/meshfit" deform --template "$data/template.off" --curves "$data/curves.polylines.txt" \
  --correspondences "$data/pairs.txt" --output "$out/deformed.ply" --report "$out/deform-report.json"
"$root/build/meshfit" partition --template "$out/deformed.ply" --curves "$data/curves.polylines.txt" \
  --output "$out/partitioned.ply" --report "$out/partition-report.json"
"$root/build/meshfit" smooth --template "$out/partitioned.ply" --curves "$data/curves.polylines.txt" \
  --output "$out/smoothed.ply" --report "$out/smooth-report.json"
echo "meshfit: outputs written to $out" >&2
