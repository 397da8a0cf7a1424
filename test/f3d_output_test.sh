#!/usr/bin/env bash
# CTest f3d_output: fits the embedded example to .vtp, .vtk, .ply and .obj and renders each with f3d (offscreen,
# under xvfb-run), coloured by the output's own cell data `region` (the curve lines, region -1,
# come out black); the pictures are checked by check_pictures.py (decode, size, not blank, curves
# drawn, at least 4 region hues). A rainbow colour map (f3d's default runs black-red-yellow, too few
# hues to tell 12 regions apart) keeps black for region -1, the lines.
#   f3d_output_test.sh MESHFIT OUT_DIR
# Exits 77 (skipped) when f3d, python3, or xvfb-run without a display is missing.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
meshfit="$1" out="$2"
source "$root/test/picture_test_setup.sh"
picture_test_setup f3d_output
rm -rf "$out"
mkdir -p "$out"
data="$root/examples/data"
pictures=()
for ext in vtp vtk; do
  "$meshfit" fit --quiet --template "$data/template.off" --curves "$data/curves.polylines.txt" \
    --correspondences "$data/pairs.txt" --output "$out/fit.$ext"
  "${offscreen[@]}" f3d --dry-run --quiet --output="$out/fit-$ext.png" --resolution=800,600 \
    --scalars=region --cells --line-width=4 --bg-color=1,1,1 \
    --colormap=0,0,0,0,0.08,1,0,0,0.3,1,1,0,0.5,0,1,0,0.7,0,1,1,0.85,0,0,1,1,1,0,1 "$out/fit.$ext"
  pictures+=("$out/fit-$ext.png")
done
# .ply: f3d reads no patch_id; it shows the region colours written beside it (the faces' red green
# blue, as direct colours). The curves are beside that file, not in it: no black to expect.
"$meshfit" fit --quiet --template "$data/template.off" --curves "$data/curves.polylines.txt" \
  --correspondences "$data/pairs.txt" --output "$out/fit.ply"
"${offscreen[@]}" f3d --dry-run --quiet --output="$out/fit-ply.png" --resolution=800,600 \
  --scalars --cells --comp=-2 --bg-color=1,1,1 "$out/fit.ply"
pictures+=("$out/fit-ply.png")
# .obj: its groups take the materials of the library beside it (fit.obj.mtl), one colour per region.
"$meshfit" fit --quiet --template "$data/template.off" --curves "$data/curves.polylines.txt" \
  --correspondences "$data/pairs.txt" --output "$out/fit.obj"
"${offscreen[@]}" f3d --dry-run --quiet --output="$out/fit-obj.png" --resolution=800,600 --bg-color=1,1,1 "$out/fit.obj"
pictures+=("$out/fit-obj.png")
"$python" "$root/test/check_pictures.py" --size 800,600 --regions fit-vtp.png,fit-vtk.png,fit-ply.png,fit-obj.png \
  --no-curves fit-ply.png,fit-obj.png "${pictures[@]}"
