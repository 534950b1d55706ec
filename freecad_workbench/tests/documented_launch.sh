#!/bin/sh
# Runs the GUI launch command of docs/freecad.md verbatim (the line starting with
# THERMODEC_PYTHON_DIR= that opens start_thermodec.py) under Xvfb, from a folder laid out like a
# checkout (freecad_workbench/ and build/ as links), and checks that FreeCAD came up in the
# ThermoDec workbench with the thermodec module of the build tree.
# Usage: documented_launch.sh <source dir> <build dir> <scratch dir>
set -eu
src=$1 build=$2 out=$3
line=$(grep -m1 '^THERMODEC_PYTHON_DIR=.*freecad .*start_thermodec\.py' "$src/docs/freecad.md") || {
  echo "docs/freecad.md has no launch line (THERMODEC_PYTHON_DIR=... freecad .../start_thermodec.py ...)"; exit 1; }
rm -rf "$out"
mkdir -p "$out/checkout" "$out/home"
ln -s "$src/freecad_workbench" "$out/checkout/freecad_workbench"
ln -s "$build" "$out/checkout/build"
cd "$out/checkout"
export HOME="$out/home" THERMODEC_START_CHECK="$out/check.txt" QTWEBENGINE_DISABLE_SANDBOX=1
echo "documented: $line"
"$src/scripts/with_xvfb" --screen 1600x1000x24 sh -c "$line" > "$out/freecad.log" 2>&1 || {
  tail -20 "$out/freecad.log"; exit 1; }
cat "$out/check.txt"
grep -qx 'workbench ThermoDecWorkbench' "$out/check.txt"
grep -qx "thermodec module $out/checkout/build/python" "$out/check.txt"
