#!/usr/bin/env bash
# Every scheme in the registry reaches the sweep's error-against-cost chart.
#   coarse (default tests): tests/sweeps/all-schemes.json, rotating-disk for 0.1 s at two
#     resolutions: runs.csv has one completed run per scheme and resolution, the chart's CSV a
#     point for every scheme;
#   full (slow): the shipped assets/sweeps/transfers-cost.json, the chart in README: every
#     scheme has points on both scenes' charts.
# The scheme list is the registry's, read from `apiclab run --help`, not written here.
# Usage: APICLAB=/path/to/apiclab all_schemes_sweep.sh SOURCE_DIR coarse|full
set -u
APICLAB=${APICLAB:?set APICLAB to the apiclab executable}
SRC=${1:?usage: all_schemes_sweep.sh SOURCE_DIR coarse|full}
WHICH=${2:?usage: all_schemes_sweep.sh SOURCE_DIR coarse|full}
TMP=$(mktemp -d "${TMPDIR:-/tmp}/apiclab-all-schemes.XXXXXX")
trap 'rm -rf "$TMP"' EXIT
source "$(dirname "${BASH_SOURCE[0]}")/../check_lib.sh"

schemes=$("$APICLAB" run --help | sed -n 's/.*--scheme TEXT *transfer scheme: \([a-z|]*\).*/\1/p' |
  tr '|' ' ')
count=$(echo "$schemes" | wc -w)
if [ "$count" -ge 9 ]; then ok "registry lists $count schemes: $schemes"; else
  nok "scheme list from run --help ($count)" "$schemes"
fi

case $WHICH in
coarse) spec=$SRC/tests/sweeps/all-schemes.json charts="rotating-disk" ;;
full) spec=$SRC/assets/sweeps/transfers-cost.json charts="rotating-disk skew-impact" ;;
*) echo "unknown check '$WHICH'" && exit 2 ;;
esac
if ! "$APICLAB" sweep "$spec" --out "$TMP/out" --jobs 2 --quiet >"$TMP/log" 2>&1; then
  nok "apiclab sweep $spec" "$(cat "$TMP/log")"
  finish all_schemes_sweep
  exit 1
fi

# column CSV NAME: the values of column NAME, one per line.
column() {
  awk -F, -v name="$2" 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == name) c = i; next }
                        { print $c }' "$1"
}
for s in $schemes; do
  runs=$(column "$TMP/out/runs.csv" solver.scheme | grep -cx "$s")
  if [ "$WHICH" = coarse ]; then
    done_runs=$(paste -d, <(column "$TMP/out/runs.csv" solver.scheme) \
      <(column "$TMP/out/runs.csv" outcome) | grep -cE "^$s,(completed|noisy)$")
    if [ "$runs" -eq 2 ] && [ "$done_runs" -eq 2 ]; then ok "$s: 2 runs, both ran to the end"; else
      nok "$s: $runs runs, $done_runs ran to the end" "$(cat "$TMP/out/runs.csv")"
    fi
  elif [ "$runs" -gt 0 ]; then ok "$s: $runs runs"; else nok "$s: not in runs.csv"; fi
  for c in $charts; do
    csv=$TMP/out/error_vs_cost_$c.csv
    points=$(column "$csv" series | grep -cx "$s")
    if [ "$points" -gt 0 ]; then ok "$s: $points points on the $c chart"; else
      nok "$s: no point on the $c chart" "$(cat "$csv")"
    fi
  done
done
for c in $charts; do
  if [ -s "$TMP/out/error_vs_cost_$c.png" ]; then ok "chart error_vs_cost_$c.png"; else
    nok "no error_vs_cost_$c.png" "$(ls "$TMP/out")"
  fi
done
finish all_schemes_sweep
