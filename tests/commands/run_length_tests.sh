#!/usr/bin/env bash
# Runs and plans that can end (docs/cli.md, docs/sweeps.md): a run whose time-step rule must take
# more steps than --max-steps, more frames than --max-frames, or whose first steps predict more
# steps, exits 2 at once with the numbers, and the flags raise the caps; a sweep above
# --max-runs is refused before planning, with its count, and plans in linear time with the flag.
# Usage: APICLAB=/path/to/apiclab run_length_tests.sh
set -u
APICLAB=${APICLAB:?set APICLAB to the apiclab executable}
TMP=$(mktemp -d "${TMPDIR:-/tmp}/apiclab-length.XXXXXX")
trap 'rm -rf "$TMP"' EXIT
source "$(dirname "${BASH_SOURCE[0]}")/../check_lib.sh"

now() { date +%s.%N; }
# refused NAME NEEDLE... -- ARGS: exit 2 within 10 s, one stderr line holding every needle, and
# no CSV written.
refused() {
  local name=$1 needles=()
  shift
  while [ "$1" != "--" ]; do needles+=("$1") && shift; done
  shift
  rm -f "$TMP/out.csv"
  local t0 t1
  t0=$(now)
  timeout 10 "$APICLAB" "$@" --csv "$TMP/out.csv" --quiet >/dev/null 2>"$TMP/err"
  local rc=$? lines good=1
  t1=$(now)
  lines=$(wc -l <"$TMP/err")
  for n in "${needles[@]}"; do grep -qF -- "$n" "$TMP/err" || good=0; done
  if [ $rc -eq 2 ] && [ "$lines" -eq 1 ] && [ $good = 1 ] && [ ! -s "$TMP/out.csv" ]; then
    ok "$name ($(awk -v a="$t0" -v b="$t1" 'BEGIN {printf "%.2f", b - a}') s)"
  else
    nok "$name (rc $rc, $lines lines, wanted: ${needles[*]})" "$(cat "$TMP/err")"
  fi
}

refused "a fixed step of 1e-30 s" "a fixed step of 1e-30 s" "2e+30 steps" "--max-steps 1e+08" -- \
  run rotating-disk --dt 1e-30
refused "E = 1e308 (the elastic rule's step)" "the elastic rule's step" "--max-steps 1e+08" -- \
  run rotating-disk --set materials.0.E=1e308 --set 'time.dt={"rule":"elastic","nu":0.3}'
refused "Courant number 1e-12 (elastic rule)" "the elastic rule's step" "--max-steps" -- \
  run rotating-disk --set 'time.dt={"rule":"elastic","nu":1e-12}'
refused "fps = 1e9" "2e+09 frames" -- run rotating-disk --fps 1e9
refused "fps = 1e9 to 0.1 s" "1e+08 frames (time.end x time.fps = 1e+08), more than --max-frames 1e+06" -- \
  run rotating-disk --fps 1e9 --t-end 0.1
refused "the EoL solver with E = 1e308" "the elastic rule's step" "--max-steps" -- \
  run eol-drop --set materials.0.E=1e308
refused "the EoL solver at fps 1e9" "--max-frames" -- run eol-drop --fps 1e9 --t-end 0.1
refused "render with a fixed step of 1e-30 s" "2e+30 steps" -- render rotating-disk --dt 1e-30 \
  --out "$TMP/render"
refused "--max-steps lowered below a short run" "a fixed step of 0.0001 s" "100 steps" \
  "--max-steps 50" -- run rotating-disk --t-end 0.01 --dt 1e-4 --max-steps 50
refused "--max-frames lowered below a short run" "3 frames (time.end x time.fps = 3), more than --max-frames 2" -- \
  run rotating-disk --t-end 0.125 --max-frames 2

# The cfl rule reads the speeds, known once the run starts: its first step predicts the count.
rm -f "$TMP/cfl.csv"
timeout 10 "$APICLAB" run rotating-disk --set time.dt.nu=1e-9 --csv "$TMP/cfl.csv" --quiet \
  >/dev/null 2>"$TMP/err"
rc=$?
if [ $rc -eq 2 ] && grep -q "step 1 took dt = .* which predicts .* steps to time.end = 2 s, more than --max-steps 1e+08" "$TMP/err"; then
  ok "the cfl rule's first step predicts more than --max-steps: exit 2"
else
  nok "cfl rule at nu = 1e-9 (rc $rc)" "$(cat "$TMP/err")"
fi

# The caps raised by the flags: the same runs go on.
if timeout 60 "$APICLAB" run rotating-disk --t-end 0.01 --dt 1e-4 --max-steps 100 \
  --csv "$TMP/ok.csv" --quiet 2>"$TMP/err" >/dev/null && [ "$(tail -n +2 "$TMP/ok.csv" | wc -l)" -eq 101 ]; then
  ok "--max-steps 100 runs the 100 steps"
else
  nok "--max-steps 100" "$(cat "$TMP/err")"
fi
rm -f "$TMP/ok.csv" "$TMP/ok.csv.json"  # another run's outputs are refused
if timeout 60 "$APICLAB" run rotating-disk --t-end 0.125 --max-frames 3 --csv "$TMP/ok.csv" \
  --quiet 2>"$TMP/err" >/dev/null; then
  ok "--max-frames 3 runs the 3 frames"
else
  nok "--max-frames 3" "$(cat "$TMP/err")"
fi

# Sweeps: the count first; above --max-runs refused before planning; planned in linear time.
# spec N1 N2 N3: an N1 x N2 x N3 sweep of rotating-disk (flip blend x modulus x end time).
spec() {
  awk -v a="$1" -v b="$2" -v c="$3" 'BEGIN {
    printf "{\"name\": \"big\", \"scene\": \"rotating-disk\", \"set\": {\"solver.scheme\": \"flip\"},\n"
    printf " \"axes\": {\"solver.flip_alpha\": ["; for (i = 0; i < a; i++) printf "%s%.6f", i ? "," : "", i / a
    printf "],\n  \"materials.0.E\": ["; for (i = 0; i < b; i++) printf "%s%d", i ? "," : "", 1000 + i
    printf "],\n  \"time.end\": ["; for (i = 0; i < c; i++) printf "%s%.4f", i ? "," : "", 0.1 + i / 1000
    printf "]}}\n"
  }'
}
spec 60 60 30 >"$TMP/big.json"  # 108,000 runs
t0=$(now)
timeout 20 "$APICLAB" sweep "$TMP/big.json" --out "$TMP/big" >"$TMP/out" 2>"$TMP/err"
rc=$?
t1=$(now)
secs=$(awk -v a="$t0" -v b="$t1" 'BEGIN {printf "%.2f", b - a}')
if [ $rc -eq 2 ] && grep -q "108000 runs, more than --max-runs 10000" "$TMP/err" &&
  awk -v s="$secs" 'BEGIN {exit !(s < 1)}' && [ ! -e "$TMP/big/runs" ]; then
  ok "a 108,000-run spec is refused in $secs s with its count"
else
  nok "108,000-run spec (rc $rc, $secs s)" "$(cat "$TMP/err")"
fi
spec 20 20 30 >"$TMP/mid.json"  # 12,000 runs: over the cap, planned with --max-runs
t0=$(now)
timeout 120 "$APICLAB" sweep "$TMP/mid.json" --out "$TMP/mid" --max-runs 12000 \
  --export-jobs "$TMP/mid.jobs" >"$TMP/out" 2>"$TMP/err"
rc=$?
t1=$(now)
secs=$(awk -v a="$t0" -v b="$t1" 'BEGIN {printf "%.2f", b - a}')
if [ $rc -eq 0 ] && [ "$(wc -l <"$TMP/mid.jobs")" -eq 12000 ] &&
  head -1 "$TMP/err" | grep -q "sweep big: 12000 runs; planning" &&
  awk -v s="$secs" 'BEGIN {exit !(s < 30)}'; then
  ok "a 12,000-run spec with --max-runs 12000: count first, planned in $secs s"
else
  nok "12,000-run spec with --max-runs (rc $rc, $secs s)" "$(cat "$TMP/err")"
fi

finish run_length_tests
