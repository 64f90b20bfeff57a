#!/usr/bin/env bash
# Checkpoints and resume (docs/outputs.md, "Checkpoints"): a run killed (SIGKILL, or SIGTERM,
# which writes a checkpoint where it stops) and resumed ends with every output byte for byte
# that of a run never stopped (the CSV without its wall_s column), for MPM explicit with APIC,
# XPIC and PolyPIC, for the implicit midpoint rule, and for eol and eulerian (contact between
# objects, a moving body, 3D); a kill while a checkpoint is written leaves the one before; corrupt,
# truncated and foreign checkpoints are refused with one line and exit 2; a checkpoint that cannot
# be written stops the run with one line.
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
# EoL: object-object contact (one QP over both disks), a turning rod (a moving body), the
# Eulerian baseline, and 3D; their dumps are the grids and surfaces.
HEAD_ON=(eol-two-disks --set objects.0.velocity=[3,0] --set objects.1.velocity=[-3,0]
  --dump-format vtk-raw,obj)
DISKS=("${HEAD_ON[@]}" --t-end 0.17)
killed_and_resumed eol-contact KILL "${DISKS[@]}"
killed_and_resumed eol-paddle TERM eol-paddle --t-end 0.3 --dump-format vtk-raw,obj
killed_and_resumed eulerian TERM "${HEAD_ON[@]}" --t-end 0.09 --set solver.method=eulerian
killed_and_resumed eol-3d KILL eol-drop-3d --t-end 0.1 --dump-format vtk-raw

# ---- a kill while a checkpoint is written leaves the one before --------------------------------
# APICLAB_TEST_KILL_CHECKPOINT=N (app/checkpoint.cpp) kills the run by SIGKILL halfway through its
# N-th checkpoint write: checkpoint.bin is still the one before, whole, and resuming from it
# ends as the uninterrupted run of eol-contact above.
m="$TMP/midwrite"
mkdir -p "$m"
APICLAB_TEST_KILL_CHECKPOINT=3 "$APICLAB" run "${DISKS[@]}" --csv "$m/run.csv" --dump "$m/dump" \
  --quiet --checkpoint-every 1 --checkpoint-dir "$m/ck" >/dev/null 2>"$m/err" &
{ wait $!; } 2>/dev/null
killed=$?
part=$(stat -c %s "$m/ck/checkpoint.bin.part" 2>/dev/null || echo 0)
whole=$(stat -c %s "$m/ck/checkpoint.bin" 2>/dev/null || echo 0)
run_cli run --resume "$m/ck"
if [ "$killed" -eq 137 ] && [ "$part" -gt 0 ] && [ "$part" -lt "$whole" ] && [ "$RC" -eq 0 ] &&
  grep -q "at frame 2 .*bit for bit" "$ERR" && [ ! -e "$m/ck/checkpoint.bin.part" ] &&
  why=$(same_outputs "$TMP/eol-contact/a" "$m"); then
  ok "killed while writing checkpoint 3 (exit $killed, $part of $whole bytes in .part): resumed from checkpoint 2, every output the same"
else
  nok "a kill mid-write leaves the checkpoint before" "killed exit $killed, .part $part bytes, checkpoint.bin $whole, resume exit $RC" \
    "${why:-}" "$(head -c 600 "$ERR")"
fi

# ---- a checkpoint that cannot be written stops the run: one line, exit 2 ----------------------
# A state of 1 MiB or more (this disk at a third of its dx) is written on a thread of its own
# while the run goes on: its failure still ends the run, naming the file and the cause.
# (checkpoint.bin.part is a folder: the write cannot open it.)
w="$TMP/unwritable"
mkdir -p "$w/ck/checkpoint.bin.part"
run_cli run rotating-disk --t-end 0.25 --set domain.dx=0.0104 --csv "$w/run.csv" --quiet \
  --checkpoint-every 1 --checkpoint-dir "$w/ck"
last_t=$(awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next } { t = $c["t"] } END { print t }' "$w/run.csv")
if [ "$RC" -eq 2 ] && [ "$(wc -l <"$ERR")" -eq 1 ] &&
  grep -q "^apiclab: cannot write $w/ck/checkpoint.bin: Is a directory$" "$ERR" &&
  [ ! -e "$w/ck/checkpoint.bin" ] && awk -v t="$last_t" 'BEGIN { exit !(t > 0 && t < 0.125) }'; then
  ok "a checkpoint that cannot be written stops the run at t = $last_t: '$(cat "$ERR")', exit 2"
else
  nok "a failed checkpoint write stops the run" "exit $RC, the CSV ends at t = $last_t" "$(head -c 400 "$ERR")"
fi

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
run_cli run rotating-disk --t-end 0.25 --csv "$c/run.csv" --resume "$c/run.checkpoint" \
  --summary "$c/summary.json"
if [ "$RC" -eq 0 ] && cmp -s <(cut -d, -f1-16,18 "$c/whole.csv") <(cut -d, -f1-16,18 "$c/run.csv"); then
  ok "resume with SCENE and the same options: the same CSV"
else
  nok "resume with SCENE and the same options" "exit $RC" "$(head -c 300 "$ERR")"
fi
# The resumed process's rates count its own steps (none here: the last checkpoint is at the
# end), not the run's from t = 0.
rates=$(python3 -c 'import json,sys; j=json.load(open(sys.argv[1]))
timed=j["steps_per_second"]*j["wall_seconds"]
print("%d %.1f %d" % (j["steps"], timed, 0 <= timed < j["steps"] - 0.5))' "$c/summary.json" 2>&1)
if [ "${rates##* }" = 1 ]; then
  ok "a resumed run's steps/s counts the steps after its checkpoint (steps, steps timed: ${rates% *})"
else
  nok "a resumed run's rates count its own steps" "$rates"
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
refused "other settings" "was written with other settings: time.end is 0.25 there, 0.5 here" \
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
refused "another format version" "has format version 7, this build reads version 2" \
  run --resume "$c/version"

finish checkpoint_tests
