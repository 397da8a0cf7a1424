#!/usr/bin/env bash
# CTest render_example: renders the embedded example's stages with scripts/render.sh and checks
# the pictures (exist, decode, 800x600, not blank, regions coloured).
#   render_example_test.sh MESHFIT OUT_DIR
# Exits 77 (skipped) when f3d, or xvfb-run without a display, or python3 is missing.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
meshfit="$1" out="$2"
source "$root/test/picture_test_setup.sh"
picture_test_setup render_example
rm -rf "$out"
"$root/scripts/render.sh" --example --meshfit "$meshfit" --out "$out" --resolution 800,600
"$python" "$root/test/check_pictures.py" --size 800,600 --regions partitioned.png,smoothed.png \
  "$out/template.png" "$out/deformed.png" "$out/partitioned.png" "$out/smoothed.png"
