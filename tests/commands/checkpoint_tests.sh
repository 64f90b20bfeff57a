#!/usr/bin/env bash
# Checkpoints and resume (docs/outputs.md, "Checkpoints"): a run killed (SIGKILL, or SIGTERM,
# which writes a checkpoint where it stops) and resumed ends with every output byte for byte
# that of a run never stopped (the CSV without its wall_s column), for MPM explicit with APIC,
# XPIC and PolyPIC and for the implicit midpoint rule; corrupt, truncated and foreign
# checkpoints are refused with one line and exit 2.
# Usage: APICLAB=/path/to/apiclab checkpoint_tests.sh
set -u
APICLAB=${APICLAB:?set APICLAB to the apiclab executable}
TMP=$(mktemp -d "${TMPDIR:-/tmp}/apiclab-checkpoint.XXXXXX")
trap 'rm -rf "$TMP"' EXIT
mkdir -p "$TMP/cwd"
source "$(dirname "${BASH_SOURCE[0]}")/../check_lib.sh"

# Every output of run A equals run B's: frame files, frames.csv, series.pvd and sidecars with
# cmp, the CSV without its wall_s column (17th). Prints the first difference.
same_outputs() {
  local a=$1 b=$2 f
  for f in $(cd "$a/dump" && ls); do
    cmp -s "$a/dump/$f" "$b/dump/$f" || {
      echo "dump/$f differs"
      return 1
    }
  done
  [ "$(ls "$a/dump")" = "$(ls "$b/dump")" ] || {
    echo "dump files differ: $(ls "$b/dump" | tr '\n' ' ')"
    return 1
  }
  cmp -s "$a/run.csv.json" "$b/run.csv.json" || {
    echo "run.csv.json differs"
    return 1
  }
  cmp -s <(cut -d, -f1-16,18 "$a/run.csv") <(cut -d, -f1-16,18 "$b/run.csv") || {
    echo "run.csv differs: $(diff <(cut -d, -f1-16,18 "$a/run.csv") <(cut -d, -f1-16,18 "$b/run.csv") | head -3)"
    return 1
  }
}

# killed_and_resumed NAME SIGNAL ARGS...: runs ARGS uninterrupted into $TMP/NAME/a, then with
# --checkpoint-every 1 into $TMP/NAME/b, sends SIGNAL once the first checkpoint is written,
# resumes with `run --resume DIR` alone and compares every output.
killed_and_resumed() {
  local name=$1 signal=$2 pid i
  shift 2
  local a="$TMP/$name/a" b="$TMP/$name/b"
  mkdir -p "$a" "$b"
  "$APICLAB" run "$@" --csv "$a/run.csv" --dump "$a/dump" --quiet >/dev/null 2>"$a/err" ||
    nok "$name: the uninterrupted run" "$(tail -n 2 "$a/err")"
  "$APICLAB" run "$@" --csv "$b/run.csv" --dump "$b/dump" --quiet --checkpoint-every 1 \
    --checkpoint-dir "$b/ck" >/dev/null 2>"$b/err" &
  pid=$!
  for i in $(seq 1 600); do
    [ -f "$b/ck/checkpoint.bin" ] && break
    sleep 0.02
  done
  kill "-$signal" "$pid" 2>/dev/null
  local killed
  { wait "$pid"; } 2>/dev/null
  killed=$?
  run_cli run --resume "$b/ck"
  local frame
  frame=$(sed -n 's/.* at frame \([0-9]*\) .*/\1/p' "$ERR" | head -n 1)
  local last
  last=$(tail -n 1 "$a/dump/frames.csv" | cut -d, -f1)
  if [ "$RC" -eq 0 ] && [ -n "$frame" ] && [ "$frame" -lt "$last" ] &&
    grep -q "bit for bit" "$ERR" && why=$(same_outputs "$a" "$b"); then
    ok "$name: killed by SIG$signal (exit $killed) after frame $frame of $last, resumed: every output the same"
  else
    nok "$name: resumed run equals the uninterrupted one" "resume exit $RC, killed exit $killed, frame '$frame' of $last" \
      "${why:-}" "$(head -c 600 "$ERR")"
  fi
}

DISK=(rotating-disk --t-end 0.75 --dump-format csv,vtk-raw)
killed_and_resumed apic KILL "${DISK[@]}" --scheme apic
killed_and_resumed xpic TERM "${DISK[@]}" --scheme xpic --set solver.xpic_order=3
killed_and_resumed polypic KILL "${DISK[@]}" --scheme polypic
killed_and_resumed implicit TERM rotating-disk --t-end 0.5 --integrator midpoint --scheme apic

# ---- --checkpoint-seconds, and SCENE with the same options --------------------------------------
c="$TMP/seconds"
mkdir -p "$c"
run_cli run rotating-disk --t-end 0.25 --csv "$c/run.csv" --quiet --checkpoint-seconds 0.001
if [ "$RC" -eq 0 ] && [ -f "$c/run.checkpoint/checkpoint.bin" ]; then
  ok "--checkpoint-seconds writes CSV.checkpoint/checkpoint.bin"
else
  nok "--checkpoint-seconds writes a checkpoint" "exit $RC" "$(ls "$c")" "$(head -c 300 "$ERR")"
fi
cp "$c/run.csv" "$c/whole.csv"
run_cli run rotating-disk --t-end 0.25 --csv "$c/run.csv" --resume "$c/run.checkpoint"
if [ "$RC" -eq 0 ] && cmp -s <(cut -d, -f1-16,18 "$c/whole.csv") <(cut -d, -f1-16,18 "$c/run.csv"); then
  ok "resume with SCENE and the same options: the same CSV"
else
  nok "resume with SCENE and the same options" "exit $RC" "$(head -c 300 "$ERR")"
fi

# ---- refusals: one line, exit 2 --------------------------------------------------------------------
CK="$c/run.checkpoint"
# refused NAME EXPECTED ARGS...: exit 2 and one stderr line containing EXPECTED.
refused() {
  local name=$1 expected=$2
  shift 2
  run_cli "$@"
  if [ "$RC" -eq 2 ] && [ "$(wc -l <"$ERR")" -eq 1 ] && grep -qF -- "$expected" "$ERR"; then
    ok "$name: exit 2, '$(cut -c 1-110 "$ERR")'"
  else
    nok "$name refused" "exit $RC, want '$expected'" "$(head -c 400 "$ERR")"
  fi
}
refused "another scene" "belongs to scene 'rotating-disk', not 'ringing'" \
  run ringing --csv "$c/run.csv" --resume "$CK"
refused "other settings" "was written with other settings: parameters.time.end is 0.25 there, 0.5 here" \
  run rotating-disk --t-end 0.5 --csv "$c/run.csv" --resume "$CK"
refused "another CSV" "belongs to the run whose CSV is" \
  run rotating-disk --t-end 0.25 --csv "$c/other.csv" --resume "$CK"
refused "options without SCENE" "leave out --t-end" run --t-end 1 --resume "$CK"
refused "no checkpoint" "no checkpoint.bin in it" run --resume "$TMP/cwd"
cp -r "$CK" "$c/cut"
head -c 2000 "$CK/checkpoint.bin" >"$c/cut/checkpoint.bin"
refused "truncated" "checkpoint.bin is truncated" run --resume "$c/cut"
cp -r "$CK" "$c/flip"
printf '\x55' | dd of="$c/flip/checkpoint.bin" bs=1 seek=3000 conv=notrunc 2>/dev/null
refused "corrupt" "its checksum does not match" run --resume "$c/flip"
cp -r "$CK" "$c/version"
printf '\x07' | dd of="$c/version/checkpoint.bin" bs=1 seek=16 conv=notrunc 2>/dev/null
refused "another format version" "has format version 7, this build reads version 1" \
  run --resume "$c/version"
refused "eol has none yet" "has no checkpoints yet" run eol-spin --t-end 0.01 --checkpoint-every 1 \
  --csv "$c/eol.csv"

finish checkpoint_tests
