#!/usr/bin/env bash
# Checkpoints of sweep runs (docs/sweeps.md, "Checkpoints of the runs"): a sweep killed with
# SIGKILL mid-run and run again with the same command resumes its unfinished run from its
# checkpoint (its log names the frame and step) and ends with the same records as a sweep never
# stopped, byte for byte except the wall and CPU times; --export-jobs lines carry the options.
# Usage: APICLAB=/path/to/apiclab sweep_checkpoint_tests.sh
set -u
APICLAB=${APICLAB:?set APICLAB to the apiclab executable}
TMP=$(mktemp -d "${TMPDIR:-/tmp}/apiclab-sweep-checkpoint.XXXXXX")
trap 'rm -rf "$TMP"' EXIT
mkdir -p "$TMP/cwd"
source "$(dirname "${BASH_SOURCE[0]}")/../check_lib.sh"
export OMP_NUM_THREADS=1

# Two runs of a rotating disk, 24 frames of about 70 steps each.
cat >"$TMP/spec.json" <<'EOF'
{
  "name": "ck",
  "scene": "rotating-disk",
  "set": {"time.end": 1, "solver.integrator": "symplectic", "time.dt.rule": "elastic",
          "time.dt.nu": 0.5},
  "axes": {"solver.scheme": ["pic", "apic"]}
}
EOF

# Every record of sweep A equals sweep B's: diagnostics without wall_s (17th column),
# frames.bin, result.json without its times, runs.csv without its time columns.
same_records() {
  local a=$1 b=$2 id
  for id in $(ls "$a/runs"); do
    [ -f "$b/runs/$id/result.json" ] || { echo "runs/$id missing"; return 1; }
    cmp -s <(cut -d, -f1-16,18 "$a/runs/$id/diagnostics.csv") \
      <(cut -d, -f1-16,18 "$b/runs/$id/diagnostics.csv") || { echo "runs/$id/diagnostics.csv differs"; return 1; }
    cmp -s "$a/runs/$id/frames.bin" "$b/runs/$id/frames.bin" || { echo "runs/$id/frames.bin differs"; return 1; }
    cmp -s <(grep -v -E '"(step_wall_s|total_wall_s|cpu_s|peak_rss_mb)"' "$a/runs/$id/result.json") \
      <(grep -v -E '"(step_wall_s|total_wall_s|cpu_s|peak_rss_mb)"' "$b/runs/$id/result.json") ||
      { echo "runs/$id/result.json differs"; return 1; }
  done
  [ "$(ls "$a/runs")" = "$(ls "$b/runs")" ] || { echo "run folders differ: $(ls "$b/runs" | tr '\n' ' ')"; return 1; }
  local cols
  cols=$(head -n 1 "$a/runs.csv" | tr ',' '\n' | grep -n -v -E 'wall|cpu|rss|per_s' | cut -d: -f1 | paste -sd,)
  cmp -s <(cut -d, -f"$cols" "$a/runs.csv") <(cut -d, -f"$cols" "$b/runs.csv") ||
    { echo "runs.csv differs: $(diff <(cut -d, -f"$cols" "$a/runs.csv") <(cut -d, -f"$cols" "$b/runs.csv") | head -3)"; return 1; }
}

run_cli sweep "$TMP/spec.json" --out "$TMP/a" --quiet
[ "$RC" -eq 0 ] || nok "the uninterrupted sweep" "exit $RC" "$(tail -n 3 "$ERR")"

# Killed (the sweep and its run processes, SIGKILL) once the first checkpoint is there.
(cd "$TMP/cwd" && exec setsid "$APICLAB" sweep "$TMP/spec.json" --out "$TMP/b" --quiet \
  --checkpoint-every 1 >/dev/null 2>&1) &
pid=$!
for i in $(seq 1 1000); do
  compgen -G "$TMP/b/runs/*.partial/checkpoint/checkpoint.bin" >/dev/null && break
  sleep 0.01
done
kill -KILL -- "-$pid" 2>/dev/null
{ wait "$pid"; } 2>/dev/null
left=$(ls -d "$TMP"/b/runs/*.partial 2>/dev/null | wc -l)
run_cli sweep "$TMP/spec.json" --out "$TMP/b" --checkpoint-every 1
log=$(grep -l "resuming" "$TMP"/b/logs/*.log 2>/dev/null | head -n 1)
line=$(grep -h "resuming" "$TMP"/b/logs/*.log 2>/dev/null | head -n 1)
step=$(sed -n 's/.*(step \([0-9]*\),.*/\1/p' <<<"$line")
if [ "$RC" -eq 0 ] && [ "$left" -ge 1 ] && [ -n "$step" ] && [ "$step" -gt 0 ] &&
  grep -q "unfinished runs resume from their checkpoints" "$ERR" && why=$(same_records "$TMP/a" "$TMP/b"); then
  ok "sweep killed by SIGKILL, rerun: $(basename "${log%.log}") resumed at step $step ($line); every record the same"
else
  nok "a killed sweep resumes from its checkpoints" "exit $RC, $left unfinished, step '$step'" "${why:-}" \
    "$(head -c 600 "$ERR")"
fi
if ! compgen -G "$TMP/b/runs/*.partial" >/dev/null && ! compgen -G "$TMP/b/runs/*/checkpoint" >/dev/null; then
  ok "finished records keep no checkpoint and no .partial folder"
else
  nok "finished records keep no checkpoint" "$(ls "$TMP/b/runs")"
fi

# --export-jobs: every line carries the options, its checkpoint folder DIR/ID absolute.
run_cli sweep "$TMP/spec.json" --out "$TMP/c" --export-jobs "$TMP/jobs.txt" --checkpoint-every 2 \
  --checkpoint-seconds 60 --checkpoint-dir ck
if [ "$RC" -eq 0 ] && [ "$(grep -c -- "--checkpoint-every 2 --checkpoint-seconds 60 --checkpoint-dir $TMP/cwd/ck/" "$TMP/jobs.txt")" -eq 2 ]; then
  ok "--export-jobs lines carry the checkpoint options"
else
  nok "--export-jobs lines carry the checkpoint options" "exit $RC" "$(head -n 1 "$TMP/jobs.txt")"
fi

run_cli sweep "$TMP/spec.json" --out "$TMP/d" --checkpoint-dir ck
if [ "$RC" -eq 2 ] && grep -q "needs --checkpoint-every" "$ERR" && [ "$(wc -l <"$ERR")" -eq 1 ]; then
  ok "--checkpoint-dir alone refused: $(cat "$ERR")"
else
  nok "--checkpoint-dir alone refused" "exit $RC" "$(cat "$ERR")"
fi

finish sweep_checkpoint_tests
