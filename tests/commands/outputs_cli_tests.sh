#!/usr/bin/env bash
# What a run hands a person, end to end: --dt taken exactly with the frames' real
# times, the JSON run summary, the settings sidecar next to every CSV, compare's exit code when a
# pane blows up, "1 step", progress without \r or escape codes when stderr is not a terminal,
# --frames past the scene's end, the conservation ledger's columns.
# Usage: APICLAB=/path/to/apiclab outputs_cli_tests.sh
set -u
APICLAB=${APICLAB:?set APICLAB to the apiclab executable}
TMP=$(mktemp -d "${TMPDIR:-/tmp}/apiclab-outputs.XXXXXX")
trap 'rm -rf "$TMP"' EXIT
source "$(dirname "${BASH_SOURCE[0]}")/../check_lib.sh"
run_cli() {
  OUT="$TMP/stdout" ERR="$TMP/stderr"
  (cd "$TMP" && exec "$APICLAB" "$@") >"$OUT" 2>"$ERR"
  RC=$?
}
# json FILE PYTHON-EXPR: exit 0 when the expression (over j, the parsed file) is true.
json() { python3 -c "import json,sys; j=json.load(open(sys.argv[1])); sys.exit(0 if ($2) else 1)" "$1"; }

# ---- --dt is the step ------------------------------------------------------------------------
# 0.03 s at 24 fps: the old rule capped it at 1/24 and cut steps to land on frames (0.0208).
run_cli run rotating-disk --integrator midpoint --dt 0.03 --t-end 0.2 --csv "$TMP/dt.csv" \
  --dump "$TMP/dump" --summary "$TMP/summary.json"
if [ "$RC" -eq 0 ] && awk -F, 'NR > 2 && $3 != 0.03 { bad = 1 } NR > 2 { n++ } END { exit bad || n != 7 }' "$TMP/dt.csv"; then
  ok "--dt 0.03: all 7 step rows have dt = 0.03"
else
  nok "--dt 0.03 honoured exactly" "exit $RC" "$(cut -d, -f1-3 "$TMP/dt.csv" | head -12)" "$(head -c 400 "$ERR")"
fi
# frames.csv: every frame at or past f/24 and less than one step past it.
if [ "$(head -n 1 "$TMP/dump/frames.csv" 2>/dev/null)" = "frame,t,step" ] &&
  awk -F, 'NR > 1 { f = $1; t = $2; if (t < f / 24 - 1e-12 || t >= f / 24 + 0.03) bad = 1; n++ } END { exit bad || n != 6 }' "$TMP/dump/frames.csv"; then
  ok "frames.csv: 6 frames, each the step at or just past its time"
else
  nok "frames.csv real frame times" "$(cat "$TMP/dump/frames.csv" 2>/dev/null || echo '(no file)')"
fi
grep -q "at or just past" "$ERR" && ok "the run says frames are the step at or just past their time" ||
  nok "--dt note" "$(head -c 400 "$ERR")"
grep -qE "dt min/median/max = 0.03 / 0.03 / 0.03 s" "$ERR" && ok "summary line gives min/median/max dt" ||
  nok "dt statistics on the summary line" "$(tail -n 4 "$ERR")"

# ---- run --summary ---------------------------------------------------------------------------
s="$TMP/summary.json"
if [ -f "$s" ] && json "$s" "j['steps'] == 7 and j['dt']['min'] == j['dt']['median'] == j['dt']['max'] == 0.03 \
  and j['wall_seconds'] > 0 and j['cpu_seconds'] > 0 and j['particle_steps_per_second'] > 0 \
  and abs(j['t_final'] - 0.21) < 1e-12 and j['failure'] is None \
  and abs(j['energy_drift']['max_abs']) >= abs(j['energy_drift']['final']) \
  and j['angular_momentum_drift']['kind'] == 'relative' and 'apiclab_version' in j \
  and j['settings']['parameters']['time.dt.value'] == 0.03 and j['settings']['solver']['integrator'] == 'midpoint'"; then
  ok "--summary JSON has steps, dt stats, costs, drifts, settings"
else
  nok "--summary JSON fields" "$(head -c 1500 "$s" 2>/dev/null || echo '(no file)')"
fi
# A blow-up: exit 3, and the summary names step, time and quantity.
run_cli run rotating-disk --integrator symplectic --dt 0.05 --t-end 1 --csv "$TMP/blow.csv" \
  --summary "$TMP/blow.json" --quiet
if [ "$RC" -eq 3 ] && json "$TMP/blow.json" "j['failure']['step'] > 0 and j['failure']['t'] > 0 and j['failure']['quantity'] != ''"; then
  ok "blow-up: exit 3 and the summary's failure has step, t, quantity"
else
  nok "blow-up summary" "exit $RC" "$(head -c 800 "$TMP/blow.json" 2>/dev/null)"
fi

# ---- settings next to every CSV, CSVs stay plain ---------------------------------------------
if json "$TMP/dt.csv.json" "j['csv'] == 'dt.csv' and j['settings']['scene'] == 'rotating-disk'" &&
  [ "$(head -c 5 "$TMP/dt.csv")" = "step," ] && ! grep -q '^#' "$TMP/dt.csv"; then
  ok "run: dt.csv.json sidecar, CSV without comment lines"
else
  nok "run CSV sidecar" "$(head -c 300 "$TMP/dt.csv.json" 2>/dev/null || echo '(no sidecar)')"
fi

# ---- "1 step", progress without \r on a pipe ---------------------------------------------------
run_cli run rotating-disk --integrator midpoint --dt 0.04 --t-end 0.04 --csv "$TMP/one.csv"
grep -q " in 1 step " "$ERR" && ok "'1 step', not '1 steps'" || nok "1 step" "$(tail -n 3 "$ERR")"
if ! grep -q $'\r' "$ERR" && ! grep -q $'\033' "$ERR"; then ok "progress on a pipe: no \\r or escape codes"; else
  nok "progress on a pipe" "$(od -c "$ERR" | head -5)"; fi

# ---- --frames past the scene's end ------------------------------------------------------------
run_cli run rotating-disk --frames 49 --integrator backward --set 'time.dt={"rule":"fixed","value":0.5}' --csv "$TMP/frames.csv"
grep -q "past the scene's end (time.end = 2 s)" "$ERR" && ok "--frames past the scene's end says so" ||
  nok "--frames past the end" "exit $RC" "$(head -c 400 "$ERR")"

# ---- render / compare ----------------------------------------------------------------------
if "$APICLAB" compare --help >/dev/null 2>&1; then
  run_cli compare rotating-disk --schemes pic,apic --out "$TMP/cmp" --t-end 0.1 --size 160x120 --quiet
  if [ "$RC" -eq 0 ] && json "$TMP/cmp/pic.csv.json" "j['settings']['solver']['scheme'] == 'pic'" &&
    json "$TMP/cmp/apic.csv.json" "j['settings']['solver']['scheme'] == 'apic'" &&
    [ "$(head -n 1 "$TMP/cmp/frames.csv")" = "frame,t,step_pic,step_apic" ]; then
    ok "compare: a sidecar per scheme CSV and frames.csv"
  else
    nok "compare sidecars" "exit $RC" "$(ls "$TMP/cmp" 2>&1 | head)" "$(head -c 400 "$ERR")"
  fi
  # One pane blows up, the other does not: symplectic Euler just past the disk's explicit limit
  # (dt = 0.0011 s; measured: FLIP blows up at t = 0.46, PIC's damping holds it to t = 1).
  run_cli compare rotating-disk --schemes pic,flip --integrator symplectic --dt 0.0011 --t-end 1 \
    --out "$TMP/blow" --size 160x120 --quiet
  frames=$(ls "$TMP/blow"/frame_*.png 2>/dev/null | wc -l)
  if [ "$RC" -eq 3 ] && [ "$frames" -eq 25 ] && grep -q "blew up" "$ERR"; then
    ok "compare: exit 3 when one pane blew up, after all 25 frames"
  elif [ "$RC" -eq 3 ]; then
    nok "compare exit 3 with all frames" "exit $RC, $frames frames" "$(tail -n 3 "$ERR")"
  else
    nok "compare exit code with a blown-up pane" "exit $RC, $frames frames" "$(tail -n 3 "$ERR")"
  fi
fi

# ---- solver.ledger: the conservation ledger's columns (docs/outputs.md) -----------------------
# 48 columns after dt_limit, row 0 zero, each row's stages adding up to its change of the total
# energy and L_z; the sidecar says so.
run_cli run rotating-disk --integrator symplectic --dt 0.0005 --t-end 0.0025 \
  --csv "$TMP/ledger.csv" --set solver.ledger=true --quiet
base_header='step,t,dt,kinetic,kinetic_grid,potential,total,px,py,pz,Lx,Ly,Lz,newton_iters,cg_iters,residual,wall_s,dt_limit'
header=$(head -n 1 "$TMP/ledger.csv" 2>/dev/null)
if [ "$RC" -eq 0 ] && [ "${header%%,p2g_dm,*}" = "$base_header" ] &&
  [ "${header#*,colliders_dE,}" = 'g2p_dm,g2p_dpx,g2p_dpy,g2p_dpz,g2p_dLx,g2p_dLy,g2p_dLz,g2p_dE,move_dm,move_dpx,move_dpy,move_dpz,move_dLx,move_dLy,move_dLz,move_dE' ] &&
  awk -F, 'NF != 66 { bad = 1 } END { exit bad || NR != 7 }' "$TMP/ledger.csv"; then
  ok "solver.ledger: 48 ledger columns after dt_limit, 66 in every row"
else
  nok "solver.ledger columns" "exit $RC" "$header" "$(head -c 400 "$ERR")"
fi
# Stage s's dLz is column 18 + 8 s + 7, its dE 18 + 8 s + 8.
if awk -F, 'NR == 2 { for (c = 19; c <= 66; c++) if ($c != 0) bad = 1 }
  NR > 2 { dE = 0; dL = 0; for (s = 0; s < 6; s++) { dL += $(25 + 8 * s); dE += $(26 + 8 * s) }
    e = dE - ($7 - E); l = dL - ($13 - L); if (e < 0) e = -e; if (l < 0) l = -l
    if (e > 1e-12 * (E < 0 ? -E : E) || l > 1e-12 * (L < 0 ? -L : L)) bad = 1 }
  NR > 1 { E = $7; L = $13 } END { exit bad }' "$TMP/ledger.csv" &&
  json "$TMP/ledger.csv.json" "j['settings']['solver']['ledger'] is True"; then
  ok "solver.ledger: row 0 zero, the stages add up to each step's change of E and L_z; the sidecar says ledger"
else
  nok "solver.ledger: the stages add up" "$(cut -d, -f7,13,25,26,57,58 "$TMP/ledger.csv" | head -4)"
fi

finish outputs_cli_tests
