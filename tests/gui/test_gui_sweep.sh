#!/usr/bin/env bash
# The viewer on a sweep folder (gui --sweep): bad folders give one line and exit 2 before any
# window; under Xvfb, the folder made by the fixture sweep_view.setup opens with one of its runs
# beside its reference, and the screenshot shows particles in both panes.
# Usage: APICLAB=... CHECK=path/to/gui_screenshot_check test_gui_sweep.sh SWEEP_DIR OUTDIR
set -euo pipefail
sweep="$1"
out="${2:-/tmp/apiclab-gui-sweep}"
mkdir -p "$out"
fail() { echo "FAIL: $*"; exit 1; }

# One line and exit 2: a missing folder, a folder that is not a sweep, an unknown run id.
expect_refusal() {  # WHAT PATTERN ARGS...
  local what="$1" pattern="$2"
  shift 2
  set +e
  "$APICLAB" gui "$@" >"$out/refusal.out" 2>"$out/refusal.err"
  local rc=$?
  set -e
  [ "$rc" = 2 ] || fail "$what: exit $rc, expected 2"
  [ "$(wc -l <"$out/refusal.err")" = 1 ] || fail "$what: not one line: $(cat "$out/refusal.err")"
  grep -q -- "$pattern" "$out/refusal.err" || fail "$what: $(cat "$out/refusal.err")"
  echo "ok: $what: $(cat "$out/refusal.err")"
}
expect_refusal "missing folder" "no such folder" --sweep "$out/no-such-sweep"
mkdir -p "$out/not-a-sweep"
expect_refusal "not a sweep" "not a sweep" --sweep "$out/not-a-sweep"
expect_refusal "unknown run" "no run with id" --sweep "$sweep" --sweep-run 0123456789abcdef
expect_refusal "scene and sweep" "give no SCENE" rotating-disk --sweep "$sweep"
expect_refusal "run without sweep" "needs --sweep" --sweep-run 0123456789abcdef

# An older folder (no spec.json) is refused; `sweep SPEC --collect DIR` adds the spec, and the
# folder then opens (it gets as far as looking up the run id).
old="$out/older"
rm -rf "$old" && cp -r "$sweep" "$old" && rm "$old/spec.json"
expect_refusal "older folder" "not a sweep" --sweep "$old"
"$APICLAB" sweep "$(dirname "$0")/../sweeps/view.json" --collect "$old" --quiet >/dev/null
cmp "$old/spec.json" "$(dirname "$0")/../sweeps/view.json" || fail "--collect did not keep the spec"
expect_refusal "collected folder opens" "no run with id" --sweep "$old" --sweep-run 0123456789abcdef

if ! command -v xvfb-run >/dev/null; then
  echo "SKIP: xvfb-run not found (apt-get install xvfb xauth)"
  exit 0
fi
# A run that is not its own reference: column `reference` of runs.csv names each row's reference.
id=$(awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == "reference") r = i; next }
              $1 != $r { print $1; exit }' "$sweep/runs.csv")
[ -n "$id" ] || fail "no non-reference run in $sweep/runs.csv"
png="$out/gui-sweep.png"
rm -f "$png"
APICLAB_PRINT_LAYOUT=1 xvfb-run -a -s "-screen 0 1600x900x24" "$APICLAB" gui --sweep "$sweep" \
  --sweep-run "$id" --screenshot "$png" --frames 2 --size 1600x900 >"$out/gui-sweep.log" 2>&1 || {
  cat "$out/gui-sweep.log"
  fail "gui --sweep exited non-zero"
}
cat "$out/gui-sweep.log"
grep '^pane ' "$out/gui-sweep.log" | "$CHECK" "$png" 2
# The stability map: every column's header inside the map's box (the panel clipped it at 3 of 5
# columns behind a scroll bar), and the map inside the window.
awk '/^window: / { W = $4; H = $5 }
     /^widget stability map: / { split($0, p, ": "); split(p[2], m, " ") }
     /^widget stability column / { split($0, p, ": "); n++; cols[n] = p[2] }
     END { if (n < 2) { print "FAIL: " n " stability columns reported"; exit 1 }
           if (m[1] + m[3] > W || m[2] + m[4] > H) { print "FAIL: the map runs out of the window"; exit 1 }
           for (i = 1; i <= n; i++) { split(cols[i], c, " ");
             if (c[1] < m[1] || c[1] + c[3] > m[1] + m[3]) { print "FAIL: column " i " at " cols[i] " outside the map " m[1] " " m[3]; exit 1 } }
           print "stability map: " n " columns, all inside" }' "$out/gui-sweep.log"
