#!/usr/bin/env bash
# Renders meshes and a curve network to PNG with f3d (Debian package f3d), under xvfb-run when
# there is no X display.
#
#   scripts/render.sh --curves C.polylines.txt --out DIR [--resolution W,H] MESH...
#       one DIR/<mesh name without extension>.png per MESH (.off, .obj or .ply)
#   scripts/render.sh --example [--meshfit PATH] [--meshes MDIR] --out DIR [--resolution W,H]
#       runs meshfit's stages on examples/data (PATH: default build/meshfit) and renders
#       template.png, deformed.png, partitioned.png and smoothed.png (the stage outputs are kept
#       in MDIR if given)
#
# Faces are coloured by region when the mesh has regions (PLY patch_id, OBJ g region_<k>), grey
# otherwise; the mesh's curve edges are drawn in black, or, for a mesh without curve edges (the
# template, deform's output), the curves of C. Every picture has the same camera (framing the
# curves and all the meshes, +Z up), so the stages line up.
# Needs f3d, xvfb (xvfb-run) and python3: scripts/install-deps.sh installs them.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"

usage() { sed -n '2,16p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//' >&2; exit 2; }

args=("$@")
curves="" out="" resolution="800,600" example=0 meshfit="$root/build/meshfit" mdir=""
meshes=()
while [ $# -gt 0 ]; do
  case "$1" in
    --curves) curves="$2"; shift 2 ;;
    --out) out="$2"; shift 2 ;;
    --resolution) resolution="$2"; shift 2 ;;
    --example) example=1; shift ;;
    --meshfit) meshfit="$2"; shift 2 ;;
    --meshes) mdir="$2"; shift 2 ;;
    -h|--help) usage ;;
    -*) echo "render.sh: unknown option $1" >&2; usage ;;
    *) meshes+=("$1"); shift ;;
  esac
done
[ -n "$out" ] || usage

python=/usr/bin/python3
[ -x "$python" ] || python=python3
for tool in f3d "$python"; do
  command -v "$tool" >/dev/null || { echo "render.sh: $tool not found (run scripts/install-deps.sh)" >&2; exit 127; }
done

# Without a display, run again under a virtual X server (one for all the pictures).
if [ -z "${DISPLAY:-}" ]; then
  command -v xvfb-run >/dev/null || { echo "render.sh: no DISPLAY and xvfb-run not found (run scripts/install-deps.sh)" >&2; exit 127; }
  width="${resolution%,*}" height="${resolution#*,}"
  exec xvfb-run -a -s "-screen 0 $((width + 64))x$((height + 64))x24" "${BASH_SOURCE[0]}" "${args[@]}"
fi

mkdir -p "$out"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
if [ $example = 1 ]; then
  data="$root/examples/data"
  curves="$data/curves.polylines.txt"
  m="${mdir:-$tmp/meshes}"
  mkdir -p "$m"
  cp "$data/template.off" "$m/template.off"
  "$meshfit" deform --quiet --template "$data/template.off" --curves "$curves" \
    --correspondences "$data/pairs.txt" --output "$m/deformed.ply"
  "$meshfit" partition --quiet --template "$m/deformed.ply" --curves "$curves" \
    --output "$m/partitioned.ply"
  "$meshfit" smooth --quiet --template "$m/partitioned.ply" --curves "$curves" \
    --output "$m/smoothed.ply"
  meshes=("$m/template.off" "$m/deformed.ply" "$m/partitioned.ply" "$m/smoothed.ply")
fi
[ ${#meshes[@]} -gt 0 ] || usage

read -r -a camera <<<"$("$python" "$root/scripts/mesh_to_vtk.py" --camera ${curves:+"$curves"} "${meshes[@]}")"

for mesh in "${meshes[@]}"; do
  name="$(basename "$mesh")"
  name="${name%.*}"
  "$python" "$root/scripts/mesh_to_vtk.py" "$mesh" "$tmp/$name.vtk" ${curves:+--curves "$curves"}
  # --dry-run: ignore any user f3d config; rgb is the per-cell colour array written above,
  # shown as direct colours (--comp=-2); --line-width thickens the curves; -a: anti-aliasing.
  f3d --dry-run --quiet --output="$out/$name.png" --resolution="$resolution" "${camera[@]}" \
    --scalars=rgb --cells --comp=-2 --line-width=5 --roughness=0.8 \
    --bg-color=1,1,1 -a "$tmp/$name.vtk"
  [ -s "$out/$name.png" ] || { echo "render.sh: f3d wrote no $out/$name.png" >&2; exit 1; }
  echo "render.sh: $out/$name.png" >&2
done
