#!/usr/bin/env bash
# Runs the staged meshlabserver on one input and one .mlx script under Xvfb (meshlabserver always
# creates a GL context; QT_QPA_PLATFORM=offscreen aborts), then checks the result.
#
#   run_meshlabserver.sh MESHLABSERVER WORKDIR INPUT SCRIPT.mlx OUT.ply [options] [-- check_ply args]
#     INPUT: one mesh, or several separated by commas (one layer each: a multi-layer document),
#            or a MeshLab project (.mlp)
#     --expect-log REGEX   the run's output must match REGEX (grep -E); repeatable
#     --expect-fail REGEX  the script must fail (non-zero exit, no OUT.ply) with REGEX in the output
#     --save-mask "fq fc"  meshlabserver -m mask (default "fq fc": face quality and colour)
#     --expect-file PATH   the run must have written PATH (non-empty); repeatable
# check_ply args go to check_ply.py (run with Debian's python3, which has numpy).
set -euo pipefail
server=$1 work=$2 input=$3 script=$4 out=$5
shift 5
expect_logs=() expect_files=() expect_fail="" mask="fq fc"
while [ $# -gt 0 ]; do
  case $1 in
    --expect-log) expect_logs+=("$2"); shift 2 ;;
    --expect-fail) expect_fail=$2; shift 2 ;;
    --expect-file) expect_files+=("$2"); shift 2 ;;
    --save-mask) mask=$2; shift 2 ;;
    --) shift; break ;;
    *) echo "run_meshlabserver.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
here=$(cd "$(dirname "$0")" && pwd)

mkdir -p "$work"
cd "$work"
rm -f "$out"
for f in "${expect_files[@]}"; do rm -f "$f"; done  # a stale file from an earlier run proves nothing
log=$work/$(basename "$out").log
# shellcheck disable=SC2086  # the mask is a list of words
set +e
IFS=',' read -ra inputs <<<"$input"
in_args=()
for i in "${inputs[@]}"; do
  case $i in *.mlp) in_args+=(-p "$i") ;; *) in_args+=(-i "$i") ;; esac
done
"$here/../../scripts/with_xvfb" "$server" "${in_args[@]}" -o "$out" -m $mask -s "$script" >"$log" 2>&1
rc=$?
set -e
sed -n '/^LOG:/p' "$log"

for re in "${expect_logs[@]}"; do
  if ! grep -Eq -- "$re" "$log"; then
    echo "FAIL: output does not match '$re' (full output: $log)" >&2
    exit 1
  fi
done
if [ -n "$expect_fail" ]; then
  if [ "$rc" -eq 0 ] || [ -e "$out" ]; then
    echo "FAIL: the script was expected to fail but succeeded (exit $rc)" >&2
    exit 1
  fi
  if ! grep -Eq -- "$expect_fail" "$log"; then
    echo "FAIL: the failure does not say '$expect_fail' (full output: $log)" >&2
    exit 1
  fi
  echo "failed as expected: $(grep -E -m1 -- "$expect_fail" "$log")"
  exit 0
fi
if [ "$rc" -ne 0 ] || [ ! -s "$out" ]; then
  echo "FAIL: meshlabserver exited with $rc (full output: $log)" >&2
  tail -20 "$log" >&2
  exit 1
fi
for f in "${expect_files[@]}"; do
  if [ ! -s "$f" ]; then
    echo "FAIL: $f was not written" >&2
    exit 1
  fi
  echo "wrote $f"
done
exec /usr/bin/python3 "$here/check_ply.py" "$out" "$@"
