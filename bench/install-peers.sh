#!/usr/bin/env bash
# Installs the Debian 12 packages the benchmarks' peers need (SciPy on OpenBLAS, for
# bench/rbf_scipy.py and bench/scale/diy_scipy.py), skipping those already present.
# Called by bench/run_benchmarks.sh and bench/scale/run.sh; needs root (or sudo) only when
# something is missing.
set -euo pipefail
need=()
for p in python3-scipy python3-numpy python3-threadpoolctl libopenblas0-pthread; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || need+=("$p")
done
[ ${#need[@]} -eq 0 ] && exit 0
echo "meshfit benchmarks: installing ${need[*]}" >&2
sudo_cmd=(); [ "$(id -u)" -ne 0 ] && sudo_cmd=(sudo)
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${need[@]}" >/dev/null
