#!/usr/bin/env bash
# solver.elasticity (docs/eol.md#the-time-step-sec-36): `explicit` is the default and the run it
# was; `implicit` (backward Euler on each object's grid) lifts the elastic cap, so only eq 33, the
# contact bound and 1/fps set the step: eol-spin (2 s) and eol-drop's fall (0.35 s, before it
# meets the floor) take frame-long steps; the key is refused for MPM scenes and with an unknown
# word, exit 2, one line.
# Usage: APICLAB=/path/to/apiclab eol_elasticity_tests.sh [full]
#   full: eol-drop for 2 s instead (it bounces, then rests on the floor).
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
  CLI_TIMEOUT=600 implicit eol-drop 24 2 1e-9
  finish eol_elasticity_tests
  exit
fi
implicit eol-spin 10 2 3e-4
# The drop through its first bounce (the floor's rows held inside the backward Euler solve).
implicit eol-drop 24 0.45 1e-9

# Two balls head-on under implicit (Fig 8's scene at Δx 0.025, no viscosity) through their
# collision: E never above E0, momentum drift below 1 % of Σ m|v0| (= 2 K0 at 1 m/s), and the
# balls part. With the QP after the backward Euler solve instead of inside it, E rose to 2.3 E0
# in the first step with pair rows.
two_balls() {
  local method=$1
  shift
  run_cli run eol-two-balls --t-end 0.3 --csv "balls-$method.csv" --quiet \
    --set solver.method="$method" --set solver.elasticity=implicit \
    --set materials.0.viscosity=0 --set domain.dx=0.025 "$@"
  if [ "$RC" -ne 0 ]; then
    nok "two balls under $method, implicit (rc $RC)" "$(cat "$ERR")"
    return
  fi
  local verdict
  verdict=$(python3 - "$TMP/cwd/balls-$method.csv" <<'EOF'
import csv, math, sys
rows = list(csv.DictReader(open(sys.argv[1])))
e0, k0 = float(rows[0]["total"]), float(rows[0]["kinetic"])
top = max(float(r["total"]) for r in rows[1:])
p0 = [float(rows[0][a]) for a in ("px", "py")]
drift = max(math.dist(p0, [float(r[a]) for a in ("px", "py")]) for r in rows[1:])
problems = []
if abs(float(rows[-1]["t"]) - 0.3) > 1e-9: problems.append(f"ended at t = {rows[-1]['t']}")
if top > e0 * (1 + 1e-9): problems.append(f"E = {top:.9g} above E0 = {e0:.9g}")
if drift > 0.01 * 2 * k0: problems.append(f"momentum drift {drift:.3g} above 1 % of {2 * k0:.4g}")
if float(rows[-1]["kinetic"]) < 0.2 * k0: problems.append("the balls did not bounce apart")
print("; ".join(problems) or
      f"{len(rows) - 1} steps, max E/E0 = {top / e0:.4f}, end E/E0 = "
      f"{float(rows[-1]['total']) / e0:.4f}, momentum drift {drift / (2 * k0):.2e} of 2 K0")
EOF
)
  case "$verdict" in
    *steps,*) ok "two balls under $method, implicit: $verdict" ;;
    *) nok "two balls under $method, implicit" "$verdict" ;;
  esac
}
two_balls eol

finish eol_elasticity_tests
