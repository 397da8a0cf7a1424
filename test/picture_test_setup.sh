# Sourced by the picture tests (render_example, f3d_output): `picture_test_setup NAME` sets `python`
# (Debian's python3 first) and `offscreen` (xvfb-run with a screen when there is no DISPLAY, else
# nothing), or exits 77 (skipped, with the reason) when f3d, python3 or a display is missing.
picture_test_setup() {
  local name="$1" tool
  python=/usr/bin/python3
  [ -x "$python" ] || python="$(command -v python3 || true)"
  for tool in f3d "$python"; do
    command -v "$tool" >/dev/null 2>&1 || { echo "SKIPPED: $name: ${tool:-python3} not found (scripts/install-deps.sh installs it)"; exit 77; }
  done
  offscreen=()
  if [ -z "${DISPLAY:-}" ]; then
    command -v xvfb-run >/dev/null || { echo "SKIPPED: $name: no DISPLAY and no xvfb-run (scripts/install-deps.sh installs xvfb)"; exit 77; }
    offscreen=(xvfb-run -a -s "-screen 0 864x664x24")
  fi
}
