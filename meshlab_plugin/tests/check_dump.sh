#!/usr/bin/env bash
# The staged meshlabserver's filter dump (-d) must list every thermodec filter built in.
#   check_dump.sh MESHLABSERVER WORKDIR "filter name" ...
set -euo pipefail
server=$1 work=$2
with_xvfb=$(cd "$(dirname "$0")/../../scripts" && pwd)/with_xvfb
shift 2
mkdir -p "$work"
cd "$work"
rm -f filters.txt
"$with_xvfb" "$server" -d filters.txt >dump.log 2>&1 || { cat dump.log >&2; exit 1; }
grep -q "^Loading Plugins" dump.log || { echo "FAIL: no plugin loading in dump.log" >&2; exit 1; }
status=0
for name in "$@"; do
  if grep -Fq "\\section" filters.txt && grep -F "\\section" filters.txt | grep -Fq " $name "; then
    echo "listed: $name"
  else
    echo "FAIL: '$name' is not in the filter dump" >&2
    status=1
  fi
done
exit $status
