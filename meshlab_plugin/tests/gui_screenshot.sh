#!/usr/bin/env bash
# Starts the staged MeshLab GUI under Xvfb with a model loaded, optionally drives it with
# synthetic keyboard/mouse input (xkeys.py: e.g. search a filter with Ctrl+F, click Apply),
# and saves a screenshot of the main window. Used by CTest (meshlab.gui_*) and to make
# docs/img/meshlab.png.
#
#   gui_screenshot.sh MESHLAB OUT.png [--expect-log REGEX]... [--reject-log REGEX]... FILE [-- XKEYS-STEP...]
#     FILE: a mesh or a .mlp project; XKEYS-STEP: see xkeys.py (screen pixels of a fresh
#     1280x800 Xvfb screen without a window manager, MeshLab's default layout).
# Re-executes itself through scripts/with_xvfb (a server of its own) unless THERMODEC_IN_XVFB is set.
set -euo pipefail
if [ -z "${THERMODEC_IN_XVFB:-}" ]; then
  THERMODEC_IN_XVFB=1 exec "$(dirname "$0")/../../scripts/with_xvfb" --screen 1280x800x24 "$0" "$@"
fi
here=$(cd "$(dirname "$0")" && pwd)
meshlab=$1 out=$2
shift 2
expect_logs=() reject_logs=()
while :; do
  case "${1:-}" in
    --expect-log) expect_logs+=("$2"); shift 2 ;;
    --reject-log) reject_logs+=("$2"); shift 2 ;;
    *) break ;;
  esac
done
file=$1
shift
[ "${1:-}" = "--" ] && shift
steps=("$@")

tmp=$(mktemp -d)
pid=""
trap '[ -n "$pid" ] && { kill "$pid" 2>/dev/null || true; wait "$pid" 2>/dev/null || true; }; rm -rf "$tmp"' EXIT

# A fresh HOME: MeshLab's saved window layout and recent files must not change the picture.
HOME=$tmp "$meshlab" "$file" >"$tmp/meshlab.log" 2>&1 &
pid=$!

# Wait for the main window (titled "MeshLab <version> - [file]"), then for the first frames.
for _ in $(seq 1 60); do
  if xwininfo -root -tree 2>/dev/null | grep -q '"MeshLab [0-9]'; then break; fi
  if ! kill -0 "$pid" 2>/dev/null; then
    echo "FAIL: meshlab exited before showing a window" >&2
    cat "$tmp/meshlab.log" >&2
    exit 1
  fi
  sleep 0.5
done
xwininfo -root -tree | grep -q '"MeshLab [0-9]' || { echo "FAIL: no MeshLab window after 30 s" >&2; exit 1; }
sleep 2
if [ ${#steps[@]} -gt 0 ]; then
  XKEYS_LOG="$tmp/meshlab.log" /usr/bin/python3 "$here/xkeys.py" "${steps[@]}"
fi
sleep "${THERMODEC_SCREENSHOT_DELAY:-2}"
# The main window only (there is no window manager to size it to the screen).
window=$(xwininfo -root -tree | grep '"MeshLab [0-9]' | head -1 | awk '{print $1}')
# THERMODEC_SCREENSHOT_ROOT=1: the whole screen instead (an open dialog is a window of its own).
[ -n "${THERMODEC_SCREENSHOT_ROOT:-}" ] && window=root
import -window "$window" "$tmp/shot.png"
mv "$tmp/shot.png" "$out"

grep -E "^LOG: .*(thermodec|Thermal)" "$tmp/meshlab.log" || true
# A rendered scene has many colours; a blank or black screen has a handful.
colours=$(identify -format '%k' "$out")
echo "screenshot $out: $(identify -format '%wx%h' "$out"), $colours colours"
if [ "$colours" -lt 50 ]; then
  echo "FAIL: the screenshot looks empty ($colours colours)" >&2
  exit 1
fi
for re in "${expect_logs[@]}"; do
  if ! grep -Eq -- "$re" "$tmp/meshlab.log"; then
    echo "FAIL: MeshLab's log does not match '$re'" >&2
    tail -20 "$tmp/meshlab.log" >&2
    exit 1
  fi
done
for re in "${reject_logs[@]}"; do
  if grep -Eq -- "$re" "$tmp/meshlab.log"; then
    echo "FAIL: MeshLab's output matches '$re':" >&2
    grep -E -m3 -- "$re" "$tmp/meshlab.log" >&2
    exit 1
  fi
done
