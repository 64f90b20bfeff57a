#!/usr/bin/env bash
# Long runs (docs/testing.md): every shipped 2D scene to 20x its end time with APIC (MPM scenes, the
# scene's own integrator) or its own method (EoL scenes). Each must finish (exit 0, no blow-up),
# never gain more than 1 % of its initial energy (none of these scenes is driven), and keep its
# resident memory flat: RSS at the end within 5 % of RSS a quarter of the way in.
# Usage: APICLAB=/path/to/apiclab long_runs.sh SOURCE_DIR [FACTOR]   (slow; prints a table)
set -u
APICLAB=${APICLAB:?set APICLAB to the apiclab executable}
SRC=${1:?usage: long_runs.sh SOURCE_DIR [FACTOR]}
FACTOR=${2:-20}
source "$(dirname "${BASH_SOURCE[0]}")/../check_lib.sh"
TMP=$(mktemp -d "${TMPDIR:-/tmp}/apiclab-long.XXXXXX")
trap 'rm -rf "$TMP"' EXIT
echo "| scene | t_end | steps | wall s | max energy gain | final dE/E | RSS 25% / end (MB) |"
echo "|---|---|---|---|---|---|---|"
for scene in cylinder-rebound ring-collision ringing rotating-disk skew-impact eol-drop eol-translation; do
  json="$SRC/assets/scenes/$scene.json"
  [ "$(/usr/bin/python3 -c "import json; print(json.load(open('$json'))['dim'])")" = 2 ] || continue
  end=$(/usr/bin/python3 -c "import json; print(json.load(open('$json'))['time']['end'] * $FACTOR)")
  method=$(/usr/bin/python3 -c "import json; print(json.load(open('$json')).get('solver', {}).get('method', 'mpm'))")
  scheme=()
  [ "$method" = mpm ] && scheme=(--scheme apic)
  "$APICLAB" run "$scene" "${scheme[@]}" --t-end "$end" --quiet --csv "$TMP/$scene.csv" \
    --summary "$TMP/$scene.json" >/dev/null 2>"$TMP/$scene.err" &
  pid=$!
  : >"$TMP/$scene.rss"
  while kill -0 "$pid" 2>/dev/null; do
    awk '/VmRSS/ { print $2 }' "/proc/$pid/status" 2>/dev/null >>"$TMP/$scene.rss"
    sleep 0.2
  done
  wait "$pid"
  rc=$?
  if [ "$rc" -ne 0 ]; then
    nok "$scene to t = $end: exit $rc" "$(cat "$TMP/$scene.err")"
    continue
  fi
  # Energy gain over the run from the CSV (total column), relative to |E0| + max kinetic.
  read -r gain final <<<"$(awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
    NR == 2 { e0 = $c["total"] } { if ($c["total"] - e0 > g) g = $c["total"] - e0; last = $c["total"] }
    END { s = (e0 < 0 ? -e0 : e0); printf "%.3g %.3g\n", g / s, (last - e0) / s }' "$TMP/$scene.csv")"
  n=$(wc -l <"$TMP/$scene.rss")
  early=$(sed -n "$((n / 4 + 1))p" "$TMP/$scene.rss")
  late=$(tail -n 1 "$TMP/$scene.rss")
  steps=$(/usr/bin/python3 -c "import json; d=json.load(open('$TMP/$scene.json')); print(d['steps'], round(d['wall_seconds'], 1))")
  echo "| $scene | $end | ${steps% *} | ${steps#* } | $gain | $final | $((early / 1024)) / $((late / 1024)) |"
  if awk -v g="$gain" 'BEGIN { exit !(g <= 0.01) }'; then ok "$scene: no energy gain over 1 %" >/dev/null; else nok "$scene: energy gain $gain"; fi
  if [ "$n" -lt 8 ] || awk -v a="$early" -v b="$late" 'BEGIN { exit !(b <= 1.05 * a) }'; then
    ok "$scene: RSS flat" >/dev/null
  else
    nok "$scene: RSS grew from $early to $late kB"
  fi
done
finish long_runs
