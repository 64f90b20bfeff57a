#!/usr/bin/env bash
# Outputs are whole or absent (docs/outputs.md, "Whole or absent"): a full disk (a file size
# limit, `ulimit -f`, makes writes fail with EFBIG) stops run, render, compare and a gui
# screenshot with exit 2 and one line "apiclab: cannot write FILE: REASON", leaving no partial
# frame, PNG or CSV row; SIGINT and SIGTERM stop run, render and compare with 130 / 143 and
# every index consistent with the files present.
# Usage: APICLAB=/path/to/apiclab outputs_whole_tests.sh
set -u
APICLAB=${APICLAB:?set APICLAB to the apiclab executable}
TMP=$(mktemp -d "${TMPDIR:-/tmp}/apiclab-whole.XXXXXX")
trap 'rm -rf "$TMP"' EXIT
# Past the size limit a write fails with EFBIG instead of the process being killed.
trap '' XFSZ
source "$(dirname "${BASH_SOURCE[0]}")/../check_lib.sh"

# limited KIB ARGS...: apiclab with a file size limit of KIB KiB; sets RC, ERR.
limited() {
  local kib=$1
  shift
  ERR="$TMP/stderr"
  (ulimit -f "$kib" && exec "$APICLAB" "$@") >"$TMP/stdout" 2>"$ERR"
  RC=$?
}
# The last non-empty stderr line.
last_line() { grep -v '^[[:space:]]*$' "$ERR" | tail -n 1 | tr -d '\r'; }
# Every row of the CSV has 18 fields and the file ends with a newline.
csv_whole() {
  [ -s "$1" ] && [ -z "$(tail -c 1 "$1")" ] && awk -F, 'NF != 18 { bad = 1 } END { exit bad }' "$1"
}
# A frame file exists iff frames.csv lists it (frame_NNNN.EXT for the given extension).
index_consistent() {
  local dir=$1 ext=$2 listed present
  [ -f "$dir/frames.csv" ] || return 1
  listed=$(awk -F, -v e="$ext" 'NR > 1 { printf "frame_%04d.%s\n", $1, e }' "$dir/frames.csv" | sort)
  present=$(cd "$dir" && ls frame_*."$ext" 2>/dev/null | grep -E '^frame_[0-9]{4}\.' | sort)
  [ "$listed" = "$present" ]
}
no_part_files() { [ -z "$(find "$1" -name '*.part' -print -quit)" ]; }

# ---- a frame that does not fit -------------------------------------------------------------------
# 100 KiB holds the diagnostics CSV, not a frame of rotating-disk (about 170 kB).
limited 100 run rotating-disk --t-end 1 --csv "$TMP/a/run.csv" --dump "$TMP/a/dump" --quiet
if [ "$RC" -eq 2 ] && last_line | grep -Eq "^apiclab: cannot write $TMP/a/[^ ]*: File too large$"; then
  ok "file size limit: exit 2 and 'apiclab: cannot write FILE: File too large'"
else
  nok "file size limit stops the run" "exit $RC" "$(tail -n 3 "$ERR")"
fi
if index_consistent "$TMP/a/dump" csv && no_part_files "$TMP/a"; then
  ok "file size limit: every frame file whole and listed, no .part file left"
else
  nok "no partial frame file" "$(ls -l "$TMP/a/dump" | head -20)" "$(cat "$TMP/a/dump/frames.csv")"
fi
csv_whole "$TMP/a/run.csv" && ok "file size limit: the diagnostics CSV ends with a whole row" ||
  nok "diagnostics CSV whole" "$(tail -c 300 "$TMP/a/run.csv")"

# ---- a diagnostics CSV that does not fit ---------------------------------------------------------
# 4 KiB: the settings sidecar fits, the CSV's rows run out part-way through a row.
limited 4 run rotating-disk --t-end 2 --csv "$TMP/b/run.csv" --quiet
if [ "$RC" -eq 2 ] && [ "$(last_line)" = "apiclab: cannot write $TMP/b/run.csv: File too large" ]; then
  ok "full diagnostics CSV: exit 2 and the message names it"
else
  nok "full diagnostics CSV stops the run" "exit $RC" "$(tail -n 3 "$ERR")"
fi
csv_whole "$TMP/b/run.csv" && ok "full diagnostics CSV: it ends with a whole row, 18 fields each" ||
  nok "diagnostics CSV cut at a row" "$(tail -c 300 "$TMP/b/run.csv")"

# ---- a summary that does not fit is absent, not empty ---------------------------------------------
# 2 KiB: the CSV and its sidecar fit (about 1 kB each), the summary (about 2.3 kB) does not.
limited 2 run rotating-disk --t-end 0.1 --csv "$TMP/c/run.csv" --summary "$TMP/c/summary.json" --quiet
if [ "$RC" -eq 2 ] && [ ! -e "$TMP/c/summary.json" ] && no_part_files "$TMP/c"; then
  ok "run summary too large: exit 2, no partial summary"
else
  nok "partial run summary" "exit $RC" "$(ls -l "$TMP/c")" "$(tail -n 2 "$ERR")"
fi

# ---- render: a PNG frame that does not fit is absent, not empty --------------------------------
if "$APICLAB" render --help >/dev/null 2>&1; then
  # 16 KiB holds the CSV, not a 320x240 frame (about 34 kB).
  limited 16 render rotating-disk --out "$TMP/r" --t-end 0.1 --size 320x240 --quiet
  if [ "$RC" -eq 2 ] && [ "$(last_line)" = "apiclab: cannot write $TMP/r/frame_0000.png: File too large" ] &&
    [ -z "$(cd "$TMP/r" && ls frame_*.png* 2>/dev/null)" ]; then
    ok "render: a PNG that does not fit stops with exit 2, no partial or empty PNG"
  else
    nok "render PNG whole or absent" "exit $RC" "$(ls -l "$TMP/r")" "$(tail -n 2 "$ERR")"
  fi
fi

# ---- render and compare: a diagnostics CSV that does not fit ------------------------------------
if "$APICLAB" render --help >/dev/null 2>&1; then
  # 4 KiB holds a 16x16 PNG, frames.csv and the sidecars, not two seconds of CSV rows.
  limited 4 render rotating-disk --out "$TMP/rc" --t-end 2 --size 16x16 --quiet
  if [ "$RC" -eq 2 ] && [ "$(last_line)" = "apiclab: cannot write $TMP/rc/apic.csv: File too large" ] &&
    csv_whole "$TMP/rc/apic.csv" && index_consistent "$TMP/rc" png && no_part_files "$TMP/rc"; then
    ok "render: a full CSV stops with exit 2, the CSV ends with a whole row, frames.csv lists the PNGs present"
  else
    nok "render CSV whole" "exit $RC" "$(tail -n 2 "$ERR")" "$(tail -c 200 "$TMP/rc/apic.csv")"
  fi
  limited 4 compare rotating-disk --schemes pic,apic --out "$TMP/cc" --t-end 2 --size 32x16 --quiet
  if [ "$RC" -eq 2 ] && last_line | grep -Eq "^apiclab: cannot write $TMP/cc/(pic|apic).csv: File too large$" &&
    csv_whole "$TMP/cc/pic.csv" && csv_whole "$TMP/cc/apic.csv" && index_consistent "$TMP/cc" png; then
    ok "compare: a full CSV stops with exit 2, every CSV ends with a whole row, frames.csv lists the PNGs present"
  else
    nok "compare CSV whole" "exit $RC" "$(tail -n 2 "$ERR")"
  fi
fi

# ---- gui --screenshot that does not fit ----------------------------------------------------------
if ! command -v xvfb-run >/dev/null; then
  echo "SKIP: gui --screenshot under a file size limit (no xvfb-run)"
elif "$APICLAB" gui --help >/dev/null 2>&1; then
  ERR="$TMP/stderr-gui"
  # The limit applies to apiclab alone, not to the X server.
  xvfb-run -a -s "-screen 0 800x600x24" bash -c 'ulimit -f 4 && exec "$0" gui rotating-disk --screenshot "$1" --frames 2 --size 400x300' \
    "$APICLAB" "$TMP/shot.png" >"$TMP/stdout" 2>"$ERR"
  RC=$?
  if [ "$RC" -eq 2 ] && grep -qx "apiclab: cannot write $TMP/shot.png: File too large" "$ERR" &&
    [ ! -e "$TMP/shot.png" ] && [ ! -e "$TMP/shot.png.part" ]; then
    ok "gui --screenshot too large: exit 2 naming the file, no partial PNG"
  else
    nok "gui --screenshot whole or absent" "exit $RC" "$(tail -n 3 "$ERR")" "$(ls -l "$TMP" | grep shot)"
  fi
fi

# ---- sweep: a chart PNG that does not fit ----------------------------------------------------------
TINY="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)/../sweeps/tiny.json"
if "$APICLAB" sweep "$TINY" --out "$TMP/sw" --jobs 2 --quiet >/dev/null 2>&1 &&
  ls "$TMP/sw"/*.png >/dev/null 2>&1; then
  rm -f "$TMP/sw"/*.png
  # 16 KiB holds runs.csv and the chart CSVs, not a 900x520 chart.
  limited 16 sweep "$TINY" --collect "$TMP/sw" --quiet
  if [ "$RC" -eq 2 ] && last_line | grep -Eq "^apiclab: cannot write $TMP/sw/[^ ]+\.png: File too large$" &&
    [ -z "$(cd "$TMP/sw" && ls ./*.png ./*.part 2>/dev/null)" ]; then
    ok "sweep: a chart PNG that does not fit stops with exit 2 and one line, no partial PNG"
  else
    nok "sweep chart PNG whole or absent" "exit $RC" "$(tail -n 2 "$ERR")" "$(ls "$TMP/sw")"
  fi
fi

# ---- SIGINT and SIGTERM --------------------------------------------------------------------------
# stopped SIGNAL CODE: a long run with dumps, stopped after about a second.
stopped() {
  local sig=$1 code=$2 dir="$TMP/$1"
  ERR="$TMP/stderr-$sig"
  "$APICLAB" run rotating-disk --t-end 5 --csv "$dir/run.csv" --dump "$dir/dump" \
    --summary "$dir/summary.json" >"$TMP/stdout" 2>"$ERR" &
  local pid=$!
  sleep 1
  kill -s "$sig" "$pid"
  wait "$pid"
  RC=$?
  if [ "$RC" -eq "$code" ] &&
    last_line | grep -Eq "^apiclab: stopped by SIG$sig at step [0-9]+, t = [^ ]+ s; diagnostics in $dir/run.csv, frames 0\.\.[0-9]+ in $dir/dump"; then
    ok "SIG$sig: exit $code and one line saying where the run stopped"
  else
    nok "SIG$sig stops the run" "exit $RC" "$(tail -n 2 "$ERR")"
  fi
  csv_whole "$dir/run.csv" && ok "SIG$sig: every CSV row has 18 fields" ||
    nok "SIG$sig: CSV whole" "$(tail -c 300 "$dir/run.csv")"
  if index_consistent "$dir/dump" csv && no_part_files "$dir" && [ ! -e "$dir/summary.json" ]; then
    ok "SIG$sig: frames.csv lists exactly the frame files present, no .part file, no summary"
  else
    nok "SIG$sig: index consistent" "$(ls "$dir/dump" | tail -5)" "$(tail -3 "$dir/dump/frames.csv")"
  fi
}
stopped INT 130
stopped TERM 143

# stopped_render SIGNAL CODE COMMAND ARGS...: render or compare stopped after a second and a half.
stopped_render() {
  local sig=$1 code=$2 cmd=$3 dir="$TMP/$3-$1"
  shift 3
  ERR="$TMP/stderr-$cmd-$sig"
  "$APICLAB" "$cmd" rotating-disk "$@" --out "$dir" --t-end 60 --size 64x48 --quiet >"$TMP/stdout" 2>"$ERR" &
  local pid=$!
  sleep 1.5
  kill -s "$sig" "$pid"
  wait "$pid"
  RC=$?
  if [ "$RC" -eq "$code" ] &&
    last_line | grep -Eq "^apiclab: stopped by SIG$sig after frame [0-9]+, t = [^ ]+ s; frames 0\.\.[0-9]+ in $dir \(listed in $dir/frames.csv\), diagnostics in $dir/"; then
    ok "$cmd SIG$sig: exit $code and one line saying where it stopped"
  else
    nok "$cmd SIG$sig stops it" "exit $RC" "$(tail -n 2 "$ERR")"
  fi
  local csv whole=1
  for csv in "$dir"/*.csv; do
    [ "$(basename "$csv")" = frames.csv ] || csv_whole "$csv" || whole=0
  done
  if [ "$whole" = 1 ] && index_consistent "$dir" png && no_part_files "$dir"; then
    ok "$cmd SIG$sig: frames.csv lists exactly the PNGs present, CSVs end with whole rows"
  else
    nok "$cmd SIG$sig: index consistent" "$(ls "$dir" | tail -5)" "$(tail -3 "$dir/frames.csv")"
  fi
}
if "$APICLAB" render --help >/dev/null 2>&1; then
  stopped_render INT 130 render
  stopped_render TERM 143 compare --schemes pic,apic
fi

finish outputs_whole_tests
