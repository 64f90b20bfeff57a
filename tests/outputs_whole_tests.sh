#!/usr/bin/env bash
# run's outputs are whole or absent (docs/outputs.md, "Whole or absent"): a full disk (a file
# size limit, `ulimit -f`, makes writes fail with EFBIG) stops the run with exit 2 and one line
# "apiclab: cannot write FILE: REASON", leaving no partial frame and no partial CSV row; SIGINT
# and SIGTERM stop it with 130 / 143 and every index consistent with the files present.
# Usage: APICLAB=/path/to/apiclab outputs_whole_tests.sh
set -u
APICLAB=${APICLAB:?set APICLAB to the apiclab executable}
TMP=$(mktemp -d "${TMPDIR:-/tmp}/apiclab-whole.XXXXXX")
trap 'rm -rf "$TMP"' EXIT
# Past the size limit a write fails with EFBIG instead of the process being killed.
trap '' XFSZ
source "$(dirname "${BASH_SOURCE[0]}")/check_lib.sh"

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

finish outputs_whole_tests
