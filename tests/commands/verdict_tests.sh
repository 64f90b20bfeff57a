#!/usr/bin/env bash
# The verdicts a run gives against runs where they are known to be true or false:
#   not converged  rotating-disk as shipped, and PIC with the midpoint rule at a quarter of the
#                  explicit limit (its velocities decay towards round-off), converge at every
#                  step: no "did not converge", unconverged_implicit_steps 0 in run --summary;
#   blown up       a body at rest under eol and eulerian is not; a spinning one 10x past the
#                  explicit limit is;
#   the integrator --lambda runs the lambda integrator and its label says lambda(L); beside
#                  --integrator symplectic, midpoint or backward it is an error naming both
#                  options (exit 2, one line), and so is solver.lambda beside them in a scene;
#                  a step past the member's stability limit is warned about, with the reason.
# Usage: APICLAB=/path/to/apiclab verdict_tests.sh SOURCE_DIR
set -u
APICLAB=${APICLAB:?set APICLAB to the apiclab executable}
SRC=${1:?usage: verdict_tests.sh SOURCE_DIR}
TMP=$(mktemp -d "${TMPDIR:-/tmp}/apiclab-verdicts.XXXXXX")
trap 'rm -rf "$TMP"' EXIT
mkdir -p "$TMP/cwd"

source "$(dirname "${BASH_SOURCE[0]}")/../check_lib.sh"

CLI_TIMEOUT=300  # run_cli's limit (check_lib.sh)

# summary_field FILE KEY: a top-level number of a run --summary JSON.
summary_field() {
  grep -oE "\"$2\": *[-0-9.e+]+" "$1" | head -1 | sed -E 's/.*: *//'
}

# expect_converged NAME ARGS...: exit 0, no non-convergence warning, no unconverged step.
expect_converged() {
  local name=$1
  shift
  CASE=$((${CASE:-0} + 1))  # each case its own outputs (another run's are refused)
  local summary="$TMP/summary-$CASE.json"
  run_cli run "$@" --summary "$summary" --csv "$TMP/run-$CASE.csv" --quiet
  local problems=() n
  [ "$RC" -eq 0 ] || problems+=("exit code $RC")
  if grep -q "did not converge\|non-converged" "$ERR" "$OUT"; then
    problems+=("a non-convergence warning: $(grep -h "converge" "$ERR" "$OUT" | head -2)")
  fi
  n=$(summary_field "$summary" unconverged_implicit_steps)
  [ "$n" = 0 ] || problems+=("unconverged_implicit_steps = '$n'")
  if [ ${#problems[@]} -eq 0 ]; then
    ok "$name ($(summary_field "$summary" steps) steps, all converged)"
  else
    nok "$name" "apiclab run $*" "${problems[@]}" "stderr: $(head -c 600 "$ERR")"
  fi
}

# expect_error NAME NEEDLE... -- ARGS...: exit 2 and one stderr line holding every needle.
expect_error() {
  local name=$1
  shift
  local needles=()
  while [ "$1" != "--" ]; do needles+=("$1"); shift; done
  shift
  run_cli "$@"
  local problems=() n
  [ "$RC" -eq 2 ] || problems+=("exit code $RC, expected 2")
  [ "$(wc -l <"$ERR")" -eq 1 ] || problems+=("stderr has $(wc -l <"$ERR") lines, expected 1")
  for n in "${needles[@]}"; do grep -qF -- "$n" "$ERR" || problems+=("stderr lacks '$n'"); done
  if [ ${#problems[@]} -eq 0 ]; then ok "$name"; else nok "$name" "apiclab $*" "${problems[@]}" "stderr: $(head -c 600 "$ERR")"; fi
}

[ -x "$APICLAB" ] || { echo "FAIL: $APICLAB is not executable"; exit 1; }

# ---- not converged ------------------------------------------------------------------------------
expect_converged "rotating-disk as shipped converges at every step" rotating-disk
# The stability map's 16x16 disk, PIC, a quarter of the explicit limit dx / (c + max|v0|).
expect_converged "PIC midpoint at small steps converges as its velocities decay" rotating-disk \
  --scheme pic --integrator midpoint --set domain.dx=0.0625 --dt 0.0006 --t-end 0.5

# ---- blown up -----------------------------------------------------------------------------------
for method in eol eulerian; do
  run_cli run eol-translation --set solver.method="$method" 'objects.0.velocity=[0,0]' \
    --t-end 0.1 --csv "$TMP/rest-$method.csv" --quiet
  if [ "$RC" -eq 0 ] && ! grep -q "blew up" "$ERR"; then
    ok "a body at rest under $method is not blown up"
  else
    nok "a body at rest under $method is not blown up" "exit $RC" "stderr: $(head -c 600 "$ERR")"
  fi
done
# eol-spin: dx / c = 0.03125 / 36.7 = 8.5e-4 s; ten times that.
run_cli run eol-spin --dt 0.0085 --t-end 0.5 --csv "$TMP/blow.csv" --quiet
if [ "$RC" -eq 3 ] && grep -q "blew up at step [0-9]*, t = " "$ERR"; then
  ok "eol 10x past the explicit limit is blown up ($(head -c 120 "$ERR"))"
else
  nok "eol 10x past the explicit limit is blown up" "exit $RC" "stderr: $(head -c 600 "$ERR")"
fi

# ---- the integrator and its lambda -----------------------------------------------------------------
run_cli run rotating-disk --lambda 0.3 --dt 0.0005 --t-end 0.05 --csv "$TMP/l.csv"
if [ "$RC" -eq 0 ] && grep -q "rotating-disk \[apic, lambda(0.3)," "$ERR" &&
  grep -q '"solver.lambda": *0.3' "$TMP/l.csv.json" && grep -q '"integrator": *"lambda"' "$TMP/l.csv.json"; then
  ok "--lambda 0.3 runs the lambda integrator labelled lambda(0.3)"
else
  nok "--lambda 0.3 runs the lambda integrator labelled lambda(0.3)" "exit $RC" \
    "stderr: $(head -c 400 "$ERR")" "sidecar: $(head -c 400 "$TMP/l.csv.json")"
fi
for integrator in symplectic midpoint backward; do
  expect_error "--lambda beside --integrator $integrator" "--lambda 0.5" "--integrator $integrator" \
    "--integrator lambda" -- run rotating-disk --integrator "$integrator" --lambda 0.5 --t-end 0.01
done
expect_error "solver.lambda beside the scene's midpoint" "'solver.lambda'" "solver.integrator lambda" \
  "midpoint" -- run rotating-disk --set solver.lambda=0.3 --t-end 0.01
expect_error "the lambda integrator without its lambda" "'solver.integrator'" "solver.lambda" -- \
  run rotating-disk --integrator lambda --t-end 0.01
# lambda = 0.6 on the disk (dx / c = 1.2e-3 s): warned past dx / (2 c |1 - 2 lambda|) = 3.0e-3 s.
run_cli run rotating-disk --lambda 0.6 --t-end 0.1 --csv "$TMP/l6.csv" --quiet
if grep -q "warning: .*lambda 0.6 is stable only for steps up to dx / (2 c |1 - 2 lambda|) = 0.00301 s" "$ERR"; then
  ok "--lambda 0.6 at the disk's steps (up to 1/24 s) is warned about"
else
  nok "--lambda 0.6 at the disk's steps (up to 1/24 s) is warned about" "stderr: $(head -c 600 "$ERR")"
fi
run_cli run rotating-disk --lambda 0.6 --dt 0.0025 --t-end 0.5 --csv "$TMP/l6s.csv" --quiet
if [ "$RC" -eq 0 ] && ! grep -q "warning" "$ERR"; then
  ok "--lambda 0.6 within its limit (dt 0.0025 s) runs without warning or blow-up"
else
  nok "--lambda 0.6 within its limit (dt 0.0025 s) runs without warning or blow-up" "exit $RC" \
    "stderr: $(head -c 600 "$ERR")"
fi

finish verdict_tests
