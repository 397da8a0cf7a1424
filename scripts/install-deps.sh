#!/usr/bin/env bash
# Installs the Debian 12 packages meshfit needs to build and test, skipping those already present.
# Idempotent; needs root (or sudo) only when something is missing.
set -euo pipefail

packages=(g++ cmake make libcgal-dev libeigen3-dev libboost-dev libgmp-dev libmpfr-dev catch2
          libcgal-demo libopenblas-dev liblapacke-dev
          # the fine level's untangling: L-BFGS (header-only, used inside the compiled library)
          liblbfgspp-dev
          # the fine level's thin-plate displacement: CHOLMOD's supernodal sparse Cholesky
          libsuitesparse-dev
          # the command line (CLI11) and its report (nlohmann-json)
          libcli11-dev nlohmann-json3-dev
          # round-trip tests of the outputs in another reader
          python3-meshio
          # pictures (scripts/render.sh and its test): f3d renders under a virtual X server
          f3d xvfb xauth libgl1-mesa-dri python3
          # meshfit view: three.js inlined into the page at build time; its tests in headless Chromium
          libjs-three chromium
          # the reference (the `doc` target and the doxygen_reference test)
          doxygen)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
[ ${#missing[@]} -eq 0 ] && exit 0

echo "meshfit: installing ${missing[*]}" >&2
sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then sudo_cmd=(sudo); fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
