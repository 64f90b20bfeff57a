#!/usr/bin/env bash
# End-to-end tests of the apiclab command line (docs/architecture.md, Command line and Diagnostics
# CSV).
# Usage: APICLAB=/path/to/apiclab cli_tests.sh SOURCE_DIR
# Bad input must give exit code 2 and exactly one line on stderr naming the cause (for scene
# errors: the file and the JSON key); a signal or abort is always a failure.
set -u
APICLAB=${APICLAB:?set APICLAB to the apiclab executable}
SRC=${1:?usage: cli_tests.sh SOURCE_DIR}
DISK="$SRC/assets/scenes/rotating-disk.json"
TMP=$(mktemp -d "${TMPDIR:-/tmp}/apiclab-cli.XXXXXX")
trap 'rm -rf "$TMP"' EXIT
mkdir -p "$TMP/cwd"  # commands run here, so default outputs never land in the source tree

pass=0
fail=0
ok() { pass=$((pass + 1)); echo "PASS: $1"; }
nok() {
  fail=$((fail + 1))
  echo "FAIL: $1"
  shift
  for line in "$@"; do echo "      $line"; done
}

# run_cli ARGS...: runs apiclab in $TMP/cwd; sets RC, OUT and ERR (files).
run_cli() {
  OUT="$TMP/stdout" ERR="$TMP/stderr"
  (cd "$TMP/cwd" && exec "$APICLAB" "$@") >"$OUT" 2>"$ERR"
  RC=$?
}

# expect_error NAME NEEDLE... -- ARGS...: exit 2, one stderr line holding every needle.
expect_error() {
  local name=$1
  shift
  local needles=()
  while [ "$1" != "--" ]; do needles+=("$1"); shift; done
  shift
  run_cli "$@"
  local lines problems=()
  lines=$(wc -l <"$ERR")
  if [ "$RC" -ge 128 ]; then problems+=("crashed with signal $((RC - 128))")
  elif [ "$RC" -ne 2 ]; then problems+=("exit code $RC, expected 2"); fi
  [ "$lines" -eq 1 ] || problems+=("stderr has $lines lines, expected 1")
  if grep -q $'\r' "$ERR"; then problems+=("stderr contains carriage returns"); fi
  local n
  for n in "${needles[@]}"; do grep -qF -- "$n" "$ERR" || problems+=("stderr lacks '$n'"); done
  if [ ${#problems[@]} -eq 0 ]; then
    ok "$name"
  else
    nok "$name" "apiclab $*" "${problems[@]}" "stderr: $(head -c 600 "$ERR")"
  fi
}

# variant NAME SED_EXPR: f = a copy of the rotating disk with one textual edit (must apply).
variant() {
  f="$TMP/$1.json"
  sed -e "$2" "$DISK" >"$f"
  if cmp -s "$f" "$DISK"; then
    nok "variant $1" "sed expression '$2' did not change the scene; test setup is stale"
  fi
}

[ -x "$APICLAB" ] || { echo "FAIL: $APICLAB is not executable"; echo "cli_tests: 0 passed, 1 failed"; exit 1; }
[ -f "$DISK" ] || { echo "FAIL: $DISK missing"; echo "cli_tests: 0 passed, 1 failed"; exit 1; }

# ---- bad input: files ----------------------------------------------------------------------
expect_error "missing scene file" "$TMP/nope.json" -- run "$TMP/nope.json" --t-end 0.01
expect_error "missing shipped scene name" "no-such-scene" -- run no-such-scene --t-end 0.01

printf '{"dim": 2,\n "domain": {"min": [0, 0],' >"$TMP/truncated.json"
expect_error "malformed JSON (truncated)" "$TMP/truncated.json" "JSON" -- run "$TMP/truncated.json"
printf '{"dim": 2,, "domain": {}}' >"$TMP/comma.json"
expect_error "malformed JSON (syntax)" "$TMP/comma.json" "JSON" -- run "$TMP/comma.json"

variant top-typo 's/"gravity"/"gravty"/'
expect_error "unknown top-level key" "$f" "'gravty'" -- run "$f" --t-end 0.01
variant nested-typo 's/"E": 1000/"Ee": 5, "E": 1000/'
expect_error "unknown nested key materials.0.Ee" "$f" "'materials.0.Ee'" -- run "$f" --t-end 0.01
variant shape-typo 's/"radius": 0.3/"radius": 0.3, "radus": 0.3/'
expect_error "unknown nested key objects.0.shape.radus" "$f" "'objects.0.shape.radus'" -- run "$f"

variant scheme 's/"scheme": "apic"/"scheme": "apicc"/'
expect_error "unknown scheme" "$f" "'solver.scheme'" "apicc" -- run "$f"
variant kernel 's/"kernel": "quadratic"/"kernel": "quintic"/'
expect_error "unknown kernel" "$f" "'solver.kernel'" "quintic" -- run "$f"
variant model 's/"model": "neo-hookean"/"model": "mooney-rivlin"/'
expect_error "unknown material model" "$f" "'materials.0.model'" "mooney-rivlin" -- run "$f"
variant shape 's/"type": "ball"/"type": "blob"/'
expect_error "unknown shape" "$f" "'objects.0.shape.type'" "blob" -- run "$f"
variant sampling 's/"type": "ppc"/"type": "random"/'
expect_error "unknown sampling" "$f" "'objects.0.sampling.type'" "random" -- run "$f"
variant boundary 's/"boundary": "slip"/"boundary": "bouncy"/'
expect_error "unknown boundary" "$f" "'domain.boundary'" "bouncy" -- run "$f"

variant dx-zero 's/"dx": 0.03125/"dx": 0/'
expect_error "dx = 0" "$f" "'domain.dx'" -- run "$f"
variant dx-negative 's/"dx": 0.03125/"dx": -0.1/'
expect_error "dx < 0" "$f" "'domain.dx'" -- run "$f"
variant rho-zero 's/"rho": 2/"rho": 0/'
expect_error "density = 0" "$f" "'materials.0.rho'" -- run "$f"
variant E-negative 's/"E": 1000/"E": -1000/'
expect_error "Young's modulus < 0" "$f" "'materials.0.E'" -- run "$f"
variant E-zero 's/"E": 1000/"E": 0/'
expect_error "Young's modulus = 0" "$f" "'materials.0.E'" -- run "$f"
variant nu-half 's/"nu": 0.3, "rho"/"nu": 0.5, "rho"/'
expect_error "nu = 0.5" "$f" "'materials.0.nu'" -- run "$f"
variant nu-low 's/"nu": 0.3, "rho"/"nu": -1.2, "rho"/'
expect_error "nu < -1" "$f" "'materials.0.nu'" -- run "$f"
variant outside 's/"center": \[0.5, 0.5\]/"center": [0.9, 0.5]/'
expect_error "object outside the domain" "$f" "'objects.0.shape'" -- run "$f"

# ---- bad input: options --------------------------------------------------------------------
expect_error "--set on a missing path (solver.nope.x)" "$DISK" "solver.nope" -- run "$DISK" --set solver.nope.x=1
expect_error "--set on a missing index (materials.5.E)" "$DISK" "materials.5" -- run "$DISK" --set materials.5.E=1
expect_error "--set of an unknown key (materials.0.Ee)" "$DISK" "'materials.0.Ee'" -- run "$DISK" --set materials.0.Ee=5
expect_error "--set of an invalid value (materials.0.nu=0.7)" "$DISK" "'materials.0.nu'" -- run "$DISK" --set materials.0.nu=0.7
# Flags go through --set, so the registry's range and message apply (sim/parameters.hpp).
expect_error "--dt 0 (fixed step)" "$DISK" "'time.dt.value'" "(0, inf)" -- run "$DISK" --dt 0
expect_error "--flip-alpha 1.5" "$DISK" "'solver.flip_alpha'" "1.5" "[0, 1]" -- run "$DISK" --flip-alpha 1.5
expect_error "--set of a fractional CG cap" "'solver.cg_max_iterations'" -- run "$DISK" --set solver.cg_max_iterations=2.5
expect_error "--scheme unknown" "apicc" -- run "$DISK" --scheme apicc
expect_error "--kernel unknown" "quintic" -- run "$DISK" --kernel quintic
expect_error "unwritable --csv" "/proc/nope" -- run "$DISK" --t-end 0.01 --csv /proc/nope/x.csv
expect_error "unwritable --dump" "/proc/nope" -- run "$DISK" --t-end 0.01 --csv "$TMP/d.csv" --dump /proc/nope/dir
expect_error "roundtrip --scheme flip" "FLIP" -- roundtrip --scheme flip --res 16
expect_error "roundtrip --kernel unknown" "quintic" -- roundtrip --kernel quintic --res 16

# ---- --help: every numeric option shows its unit, allowed range and default ------------------
run_cli run --help
help_problems=()
[ "$RC" -eq 0 ] || help_problems+=("exit code $RC")
for needle in "allowed [0, 1]; default 1]" "materials.*.nu" "allowed (-1, 0.5)" "time.dt.value" "default: double"; do
  grep -qF -- "$needle" "$OUT" || help_problems+=("help lacks '$needle'")
done
flip_line=$(grep -F -- "--flip-alpha" "$OUT" | head -n 1)
case "$flip_line" in *allowed*default*) ;; *) help_problems+=("--flip-alpha line lacks range/default: $flip_line") ;; esac
if [ ${#help_problems[@]} -eq 0 ]; then ok "run --help shows ranges and defaults"; else nok "run --help" "${help_problems[@]}"; fi

# ---- run: diagnostics CSV and particle dumps -----------------------------------------------
CSV="$TMP/disk.csv"
run_cli run rotating-disk --t-end 0.05 --csv "$CSV" --dump "$TMP/dump" --quiet
if [ "$RC" -eq 0 ]; then ok "run rotating-disk --t-end 0.05 exits 0"; else nok "run rotating-disk exits 0" "exit $RC" "$(cat "$ERR")"; fi
want="step,t,dt,kinetic,kinetic_grid,potential,total,px,py,pz,Lx,Ly,Lz"
header=$(head -n 1 "$CSV" 2>/dev/null || true)
case "$header" in
  "$want" | "$want",*) ok "diagnostics CSV header" ;;
  *) nok "diagnostics CSV header" "got: $header" ;;
esac
rows=$(($(wc -l <"$CSV" 2>/dev/null || echo 0) - 1))
# The scene runs the midpoint rule at CFL 1, capped by the frame time 1/24 s: steps land on
# t = 1/24 and t = 0.05, so at least 2 step rows follow the t = 0 row and the last is at 0.05.
last_t=$(tail -n 1 "$CSV" | cut -d, -f2)
if [ "$rows" -ge 3 ] && awk -v t="$last_t" 'BEGIN { exit !(t == 0.05) }'; then
  ok "diagnostics CSV has $rows rows ending at t = $last_t"
else
  nok "diagnostics CSV rows" "$rows rows, last t = $last_t"
fi
last_t=$(tail -n 1 "$CSV" | cut -d, -f2)
if awk -v t="$last_t" 'BEGIN { exit !(t > 0.0499 && t < 0.0501) }'; then ok "last row at t = $last_t"; else nok "last row time" "t = $last_t, expected 0.05"; fi
if awk -F, 'NR > 1 { for (i = 1; i <= 13; ++i) if ($i !~ /^-?[0-9.]+([eE][-+]?[0-9]+)?$/) bad = 1 } END { exit bad }' "$CSV"; then
  ok "diagnostics CSV values are finite numbers"
else
  nok "diagnostics CSV values are finite numbers" "$(awk -F, 'NR == 2' "$CSV")"
fi
dump="$TMP/dump/frame_0000.csv"
want_dump="id,object,x,y,vx,vy,mass,volume0,F00,F01,F10,F11,C00,C01,C10,C11"
if [ -f "$dump" ] && [ "$(head -n 1 "$dump")" = "$want_dump" ]; then ok "--dump frame_0000.csv header"; else
  nok "--dump frame_0000.csv header" "got: $(head -n 1 "$dump" 2>/dev/null || echo '(no file)')"; fi
if [ -f "$TMP/dump/frame_0001.csv" ]; then ok "--dump writes frame_0001.csv"; else nok "--dump writes frame_0001.csv"; fi
n0=$(($(wc -l <"$dump" 2>/dev/null || echo 0) - 1))
ids=$(awk -F, 'NR > 1 && $1 != NR - 2 { bad = 1 } END { print bad ? "bad" : "ok" }' "$dump" 2>/dev/null)
if [ "$n0" -gt 1000 ] && [ "$ids" = ok ]; then ok "dump has $n0 particles in id order"; else nok "dump rows" "$n0 rows, ids $ids"; fi

# ---- roundtrip -----------------------------------------------------------------------------
run_cli roundtrip --res 16,32
if [ "$RC" -eq 0 ] && [ "$(head -n 1 "$OUT")" = "resolution,dx,l2_error" ] && [ "$(wc -l <"$OUT")" -eq 3 ] &&
  awk -F, 'NR == 2 && $1 == 16 { a = 1 } NR == 3 && $1 == 32 && $3 > 0 { b = 1 } END { exit !(a && b) }' "$OUT"; then
  ok "roundtrip --res 16,32: header and 2 rows"
else
  nok "roundtrip --res 16,32" "exit $RC" "$(cat "$OUT")" "$(cat "$ERR")"
fi

# ---- bench ---------------------------------------------------------------------------------
run_cli bench --particles 2000 --steps 5
last=$(tail -n 1 "$OUT")
if [ "$RC" -eq 0 ] && [[ "$last" =~ ^particle-steps/s:\ [0-9]+(\.[0-9]+)?([eE][-+]?[0-9]+)?$ ]]; then
  ok "bench ends with '$last'"
else
  nok "bench --particles 2000 --steps 5" "exit $RC" "last line: $last" "$(cat "$ERR")"
fi

# ---- blow-up -------------------------------------------------------------------------------
expect_blowup() {
  local name=$1
  shift
  run_cli "$@"
  local problems=()
  if [ "$RC" -ge 128 ]; then problems+=("crashed with signal $((RC - 128))")
  elif [ "$RC" -eq 0 ]; then problems+=("exit code 0: the blow-up went unreported"); fi
  grep -qE "step [0-9]+" "$ERR" || problems+=("message lacks the step")
  grep -qE "t = [0-9]" "$ERR" || problems+=("message lacks the time")
  grep -qiE "energy|non-finite|NaN" "$ERR" || problems+=("message lacks the quantity")
  if [ ${#problems[@]} -eq 0 ]; then ok "$name (exit $RC)"; else nok "$name" "apiclab $*" "${problems[@]}" "stderr: $(head -c 600 "$ERR")"; fi
}
expect_blowup "blow-up at --dt 0.05" run rotating-disk --integrator symplectic --dt 0.05 --t-end 1 --csv "$TMP/blow.csv" --quiet
expect_blowup "blow-up with E = 1e9 at a fixed dt" run rotating-disk --integrator symplectic --set materials.0.E=1e9 --dt 0.001 --t-end 1 --csv "$TMP/blow2.csv" --quiet

# ---- Eulerian-on-Lagrangian methods (sim/eol/) ----------------------------------------------
ECSV="$TMP/eol-drop.csv"
run_cli run eol-drop --t-end 0.05 --csv "$ECSV" --quiet
last_t=$(tail -n 1 "$ECSV" 2>/dev/null | cut -d, -f2)
limit=$(tail -n 1 "$ECSV" 2>/dev/null | awk -F, '{print $NF}')
if [ "$RC" -eq 0 ] && [ "$last_t" = "0.050000000000000003" ] && head -n 1 "$ECSV" | grep -q ",dt_limit$" &&
  [ -n "$limit" ]; then
  ok "run eol-drop lands on t = 0.05 with a dt_limit column ($limit)"
else
  nok "run eol-drop" "exit $RC, last t '$last_t', limit '$limit'" "$(head -c 400 "$ERR")"
fi
expect_error "EoL key in an MPM scene" "'solver.alpha'" "unknown key" -- run rotating-disk --set solver.alpha=0.5
expect_error "MPM key in an EoL scene" "'solver.scheme'" "unknown key" -- run eol-spin --set solver.scheme=apic
expect_error "rest shape outside its EoL grid" "'objects.0.shape'" "solver.grid_extent" -- run eol-spin --set solver.grid_extent=0.3
expect_error "EoL has no particles to dump" "--dump" "eol" -- run eol-spin --t-end 0.01 --dump "$TMP/eoldump"

echo "cli_tests: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
