#!/usr/bin/env bash
# solver.elasticity (docs/eol.md#the-time-step-sec-36): `explicit` is the default and the run it
# was; `implicit` (backward Euler on each object's grid) lifts the elastic cap, so only eq 33, the
# contact bound and 1/fps set the step: eol-spin (2 s) and eol-drop's fall (0.35 s, before it
# meets the floor) take frame-long steps; the key is refused for MPM scenes and with an unknown
# word, exit 2, one line.
# Usage: APICLAB=/path/to/apiclab eol_elasticity_tests.sh [full]
#   full: eol-drop for 2 s instead (three bounces; solver.alpha 0.1, as docs/eol.md says).
set -u
APICLAB=${APICLAB:?set APICLAB to the apiclab executable}
TMP=$(mktemp -d "${TMPDIR:-/tmp}/apiclab-elasticity.XXXXXX")
trap 'rm -rf "$TMP"' EXIT
mkdir -p "$TMP/cwd"
source "$(dirname "${BASH_SOURCE[0]}")/../check_lib.sh"

# refused NAME NEEDLE -- ARGS: exit 2, one stderr line holding NEEDLE.
refused() {
  local name=$1 needle=$2
  shift 3
  run_cli "$@" --quiet
  if [ "$RC" -eq 2 ] && [ "$(wc -l <"$ERR")" -eq 1 ] && grep -qF -- "$needle" "$ERR"; then
    ok "$name"
  else
    nok "$name (rc $RC, wanted one line with: $needle)" "$(cat "$ERR")"
  fi
}

refused "an MPM scene refuses solver.elasticity" "read by solver.method eol or eulerian only" -- \
  run rotating-disk --t-end 0.01 --set solver.elasticity=implicit
refused "an unknown elasticity word" "explicit" -- \
  run eol-spin --t-end 0.01 --set solver.elasticity=semi

# The default is explicit: the same CSV as naming it, every column but wall_s.
same_rows() {
  python3 - "$1" "$2" <<'EOF'
import csv, sys
a, b = ([{k: v for k, v in r.items() if k != "wall_s"} for r in csv.DictReader(open(p))]
        for p in sys.argv[1:])
sys.exit(0 if a == b and len(a) > 1 else 1)
EOF
}
run_cli run eol-drop --t-end 0.02 --csv default.csv --quiet
run_cli run eol-drop --t-end 0.02 --csv explicit.csv --quiet --set solver.elasticity=explicit
if [ "$RC" -eq 0 ] && same_rows "$TMP/cwd/default.csv" "$TMP/cwd/explicit.csv"; then
  ok "solver.elasticity explicit is the default"
else
  nok "solver.elasticity explicit is the default (rc $RC)" "$(cat "$ERR")"
fi

# implicit SCENE FPS END RISE [--set ...]: runs to END; no step set by an elastic cap; E never
# above E0 by more than RISE × |E0|; some steps 1/fps long.
implicit() {
  local scene=$1 fps=$2 END=$3 rise=$4
  shift 4
  run_cli run "$scene" --t-end "$END" --csv "$scene.csv" --quiet --set solver.elasticity=implicit "$@"
  if [ "$RC" -ne 0 ]; then
    nok "$scene implicit to t = $END (rc $RC)" "$(cat "$ERR")"
    return
  fi
  local verdict
  verdict=$(python3 - "$TMP/cwd/$scene.csv" "$fps" "$END" "$rise" <<'EOF'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
fps, end, rise = float(sys.argv[2]), float(sys.argv[3]), float(sys.argv[4])
e0 = float(rows[0]["total"])
top = max(float(r["total"]) for r in rows[1:])
limits = {r["dt_limit"] for r in rows[1:]}
frame = sum(1 for r in rows[1:] if abs(float(r["dt"]) - 1 / fps) < 1e-9)
problems = []
if abs(float(rows[-1]["t"]) - end) > 1e-9: problems.append(f"ended at t = {rows[-1]['t']}")
if top > e0 + rise * abs(e0): problems.append(f"E = {top:.9g} above E0 = {e0:.9g}")
if "elastic" in limits: problems.append("a step set by the elastic cap")
if frame == 0: problems.append("no step of 1/fps")
print("; ".join(problems) or
      f"{len(rows) - 1} steps, {frame} of 1/fps, bounds {sorted(limits)}, E0 = {e0:.6g}, max E = {top:.6g}")
EOF
)
  case "$verdict" in
    *steps,*) ok "$scene implicit to t = $END: $verdict" ;;
    *) nok "$scene implicit to t = $END" "$verdict" ;;
  esac
}
# eol-spin's first step (0.05 s from rest) raises E by 2.8e-4 of E0: f_qvv stays explicit.
if [ "${1:-}" = full ]; then
  CLI_TIMEOUT=600 implicit eol-drop 24 2 1e-9 --set solver.alpha=0.1
  finish eol_elasticity_tests
  exit
fi
implicit eol-spin 10 2 3e-4
implicit eol-drop 24 0.35 1e-9

finish eol_elasticity_tests
