#!/usr/bin/env bash
# The viewer's checkpoints (docs/viewer.md, "Checkpoints"): bad folders and options give one
# line and exit 2 before any window; under Xvfb, a pane saved after 6 frames (--save-checkpoint)
# resumes with `run --resume` to the same diagnostics as a run never stopped, and a run's own
# checkpoint opened in the viewer (--open-checkpoint), stepped and saved again, does too.
# Usage: APICLAB=... CHECK=path/to/gui_screenshot_check test_gui_checkpoint.sh OUTDIR
set -euo pipefail
out="${1:-/tmp/apiclab-gui-checkpoint}"
rm -rf "$out" && mkdir -p "$out"
cd "$out"
fail() { echo "FAIL: $*"; exit 1; }
export OMP_NUM_THREADS=1

expect_refusal() {  # WHAT PATTERN ARGS...
  local what="$1" pattern="$2"
  shift 2
  set +e
  "$APICLAB" gui "$@" >refusal.out 2>refusal.err
  local rc=$?
  set -e
  [ "$rc" = 2 ] || fail "$what: exit $rc, expected 2"
  [ "$(wc -l <refusal.err)" = 1 ] || fail "$what: not one line: $(cat refusal.err)"
  grep -q -- "$pattern" refusal.err || fail "$what: $(cat refusal.err)"
  echo "ok: $what: $(cat refusal.err)"
}
expect_refusal "no checkpoint" "no checkpoint.bin" --open-checkpoint no-such-folder
expect_refusal "checkpoint and scene" "give no" rotating-disk --open-checkpoint no-such-folder
expect_refusal "save without an end" "--screenshot or --frames" rotating-disk --save-checkpoint ck

if ! command -v xvfb-run >/dev/null; then
  echo "SKIP: xvfb-run not found (apt-get install xvfb xauth)"
  exit 0
fi
SCENE=(rotating-disk --t-end 0.5 --set time.dt.rule=elastic --set time.dt.nu=0.5)
# The CSV without wall_s (17th column) equals the uninterrupted run's.
same_csv() {
  cmp -s <(cut -d, -f1-16,18 "$1") <(cut -d, -f1-16,18 "$2") ||
    fail "$1 differs from $2: $(diff <(cut -d, -f1-16,18 "$1") <(cut -d, -f1-16,18 "$2") | head -3)"
}
"$APICLAB" run "${SCENE[@]}" --csv ref.csv --quiet >/dev/null 2>&1

# A pane saved after 6 frames, continued headless.
xvfb-run -a -s "-screen 0 1280x720x24" "$APICLAB" gui "${SCENE[@]}" --screenshot saved.png \
  --frames 6 --size 1280x720 --save-checkpoint ck >saved.log 2>&1 || {
  cat saved.log
  fail "gui --save-checkpoint exited non-zero"
}
grep -q "^checkpoint at t = .* (frame 6, " saved.log || fail "no checkpoint line: $(cat saved.log)"
"$APICLAB" run --resume ck 2>resume.err >/dev/null || fail "run --resume ck: $(cat resume.err)"
grep -q "at frame 6 .*bit for bit" resume.err || fail "resume: $(cat resume.err)"
same_csv ck/diagnostics.csv ref.csv
echo "ok: a pane saved at frame 6 ($(grep '^checkpoint' saved.log)) resumed headless: the same rows as a run never stopped"

# A run's checkpoint after 4 frames opened as the pane, 3 frames on, saved again, resumed.
"$APICLAB" run "${SCENE[@]}" --csv run.csv --quiet --checkpoint-every 4 --checkpoint-dir run.ck &
pid=$!
for i in $(seq 1 500); do
  [ -f run.ck/checkpoint.bin ] && break
  sleep 0.01
done
kill -TERM "$pid" 2>/dev/null || true
wait "$pid" 2>/dev/null || true
[ -f run.ck/checkpoint.bin ] || fail "run --checkpoint-every 4 wrote no checkpoint"
png=opened.png
APICLAB_PRINT_LAYOUT=1 xvfb-run -a -s "-screen 0 1280x720x24" "$APICLAB" gui --open-checkpoint run.ck \
  --screenshot "$png" --frames 3 --size 1280x720 --save-checkpoint ck2 >opened.log 2>&1 || {
  cat opened.log
  fail "gui --open-checkpoint exited non-zero"
}
grep '^pane ' opened.log | "$CHECK" "$png" 1
"$APICLAB" run --resume ck2 2>resume2.err >/dev/null || fail "run --resume ck2: $(cat resume2.err)"
same_csv ck2/diagnostics.csv ref.csv
echo "ok: a run's checkpoint opened in the viewer ($(sed -n 's/.* at frame \([0-9]*\) .*/frame \1/p' resume2.err)), saved again and resumed: the same rows as a run never stopped"
