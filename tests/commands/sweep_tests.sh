#!/usr/bin/env bash
# `apiclab sweep` through the real executable (README, Sweeps): every bad-spec case fails before
# any run with exit 2 and one line naming the key; the tiny sweep (tests/sweeps/tiny.json) with
# --jobs 2 gives runs.csv, summary.md and charts; a sweep killed after its first run resumes,
# skips the complete run, ignores a half-written one and gives the same runs.csv; the exported
# job list run through GNU parallel and collected gives the same runs.csv (costs aside).
# Usage: APICLAB=/path/to/apiclab sweep_tests.sh SOURCE_DIR
set -u
APICLAB=${APICLAB:?set APICLAB to the apiclab executable}
SRC=${1:?usage: sweep_tests.sh SOURCE_DIR}
TINY="$SRC/tests/sweeps/tiny.json"
TMP=$(mktemp -d "${TMPDIR:-/tmp}/apiclab-sweep.XXXXXX")
trap 'rm -rf "$TMP"' EXIT

source "$(dirname "${BASH_SOURCE[0]}")/../check_lib.sh"

# bad_spec NAME NEEDLE JSON: exit 2, one stderr line naming the key, no run started.
bad_spec() {
  local name=$1 needle=$2 json=$3
  printf '%s\n' "$json" >"$TMP/bad.json"
  rm -rf "$TMP/bad-out"
  "$APICLAB" sweep "$TMP/bad.json" --out "$TMP/bad-out" >"$TMP/out" 2>"$TMP/err"
  local rc=$? lines
  lines=$(wc -l <"$TMP/err")
  if [ $rc -eq 2 ] && [ "$lines" -eq 1 ] && grep -qF -- "$needle" "$TMP/err" &&
    [ ! -e "$TMP/bad-out/runs" ]; then
    ok "bad spec: $name"
  else
    nok "bad spec: $name (rc $rc, $lines lines, wanted '$needle')" "$(cat "$TMP/err")"
  fi
}

D='"scene": "rotating-disk", "set": {"time.end": 0.1}'
bad_spec "unknown axis key" "key 'solver.shceme'" "{$D, \"axes\": {\"solver.shceme\": [\"pic\"]}}"
bad_spec "unknown spec key" "key 'axis'" "{$D, \"axis\": {}}"
bad_spec "empty axis" "key 'solver.scheme': empty axis" "{$D, \"axes\": {\"solver.scheme\": []}}"
bad_spec "unknown scheme" "key 'solver.scheme': unknown scheme 'apik'" \
  "{$D, \"axes\": {\"solver.scheme\": [\"apik\"]}}"
bad_spec "scheme axis neither a list nor all" "key 'solver.scheme': expected an array of values or \"all\"" \
  "{$D, \"axes\": {\"solver.scheme\": \"al\"}}"
bad_spec "registry range" "key 'materials.0.E'" "{$D, \"axes\": {\"materials.0.E\": [1000, -5]}}"
bad_spec "registry range (flip_alpha)" "key 'solver.flip_alpha'" \
  "{$D, \"axes\": {\"solver.flip_alpha\": [0.5, 1.5]}}"
bad_spec "material index past the scene" "materials.3.E" \
  "{$D, \"axes\": {\"materials.3.E\": [1000]}}"
bad_spec "non-positive dt_factor" "key 'dt_factor'" "{$D, \"axes\": {\"dt_factor\": [1, 0]}}"
bad_spec "number for a choice" "key 'solver.kernel'" "{$D, \"axes\": {\"solver.kernel\": [2]}}"
bad_spec "missing scene" "key 'scene'" '{"axes": {"resolution": [1]}}'
bad_spec "scene not found" "key 'scene': cannot open scene 'no-such-scene'" \
  '{"scene": "no-such-scene"}'
bad_spec "zip lengths" "key 'solver.kernel': zipped with" \
  "{$D, \"zip\": [{\"solver.scheme\": [\"pic\", \"apic\"], \"solver.kernel\": [\"cubic\"]}]}"
bad_spec "exclusion value not in the sweep" "key 'solver.scheme': exclude value 'flip'" \
  "{$D, \"axes\": {\"solver.scheme\": [\"pic\", \"apic\"]}, \"exclude\": [{\"solver.scheme\": \"flip\"}]}"
bad_spec "reference value not in the sweep" "key 'resolution': reference value '4'" \
  "{$D, \"axes\": {\"resolution\": [1, 2]}, \"reference\": {\"resolution\": 4}}"
bad_spec "reference excluded" "key 'reference': the reference configuration" \
  "{$D, \"axes\": {\"resolution\": [1, 2], \"solver.scheme\": [\"pic\", \"apic\"]}, \"exclude\": [{\"resolution\": 2, \"solver.scheme\": \"apic\"}]}"
bad_spec "combination the scene rejects" "key 'solver.kernel'" \
  "{$D, \"axes\": {\"solver.kernel\": [\"quadratic\", \"linear\"]}}"
bad_spec "bad fixed override" "key 'solver.cg_tolerance'" \
  "{\"scene\": \"rotating-disk\", \"set\": {\"time.end\": 0.1, \"solver.cg_tolerance\": -1}}"
bad_spec "malformed JSON" "malformed JSON" '{"scene": '
bad_spec "unknown error name" "key 'errors'" "{$D, \"errors\": [\"accuracy\"]}"

# bad_flag NAME NEEDLE ARGS...: exit 2, one stderr line, nothing written.
bad_flag() {
  local name=$1 needle=$2
  shift 2
  rm -rf "$TMP/flag-out"
  "$APICLAB" sweep "$@" >"$TMP/out" 2>"$TMP/err"
  local rc=$? lines
  lines=$(wc -l <"$TMP/err")
  if [ $rc -eq 2 ] && [ "$lines" -eq 1 ] && grep -qF -- "$needle" "$TMP/err" &&
    [ ! -e "$TMP/flag-out" ]; then
    ok "bad flag: $name"
  else
    nok "bad flag: $name (rc $rc, $lines lines, wanted '$needle')" "$(cat "$TMP/err")"
  fi
}
bad_flag "no --out" "--out DIR is required" "$TINY"
bad_flag "--jobs 0" "--jobs: expected a whole number from 1 to 4096, got '0'" "$TINY" --out "$TMP/flag-out" --jobs 0
bad_flag "--target-error 0" "--target-error must be positive" "$TINY" --out "$TMP/flag-out" \
  --target-error 0
bad_flag "--collect of a missing folder" "no such folder" "$TINY" --collect "$TMP/flag-out"
bad_flag "spec file missing" "cannot open sweep spec" "$TMP/no-such-spec.json" --out "$TMP/flag-out"

# csv_without_costs FILE: runs.csv without the columns that time the runs.
csv_without_costs() {
  awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) drop[i] = ($i ~ /wall_s|cpu_s|per_s|rss/) }
           { line = ""; for (i = 1; i <= NF; i++) if (!drop[i]) line = line $i ","; print line }' "$1"
}

# The tiny sweep, two at a time.
if "$APICLAB" sweep "$TINY" --out "$TMP/a" --jobs 2 --quiet --target-error 0.5 >"$TMP/out" 2>"$TMP/err"; then
  rows=$(($(wc -l <"$TMP/a/runs.csv") - 1))
  completed=$(grep -c ',completed,' "$TMP/a/runs.csv")
  if [ "$rows" -eq 4 ] && [ "$completed" -eq 4 ] && [ -s "$TMP/a/summary.md" ] &&
    grep -q 'Pareto front' "$TMP/a/summary.md" && grep -q 'Cheapest configuration' "$TMP/a/summary.md" &&
    [ "$(ls "$TMP"/a/runs/*/diagnostics.csv | wc -l)" -eq 4 ]; then
    ok "tiny sweep: 4 runs completed, summary.md, diagnostics per run"
  else
    nok "tiny sweep ($rows rows, $completed completed)" "$(cat "$TMP/a/runs.csv")"
  fi
  # The reference (finest resolution, the scene's own scheme apic) has distance 0 to itself;
  # every other run a positive one.
  ref_err=$(awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i }
    NR > 1 && $c["solver.scheme"] == "apic" && $c["resolution"] == 1 { print $c["err_displacement"] }' "$TMP/a/runs.csv")
  others=$(awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i }
    NR > 1 && !($c["solver.scheme"] == "apic" && $c["resolution"] == 1) && $c["err_displacement"] > 0 { n++ } END { print n + 0 }' "$TMP/a/runs.csv")
  if [ "$ref_err" = "0" ] && [ "$others" -eq 3 ]; then
    ok "tiny sweep: reference distance 0 for the reference, positive for the 3 others"
  else
    nok "tiny sweep reference distances (reference '$ref_err', positive others $others)"
  fi
  if "$APICLAB" --help 2>/dev/null | grep -q figures; then
    if [ -s "$TMP/a/error_vs_cost_rotating-disk.png" ] && [ -s "$TMP/a/error_vs_cost_rotating-disk.csv" ] &&
      [ -s "$TMP/a/stability_rotating-disk.png" ] && [ -s "$TMP/a/convergence_rotating-disk.png" ]; then
      ok "tiny sweep: charts beside their CSVs"
    else
      nok "tiny sweep charts" "$(ls "$TMP/a")"
    fi
  fi
else
  nok "tiny sweep exited $?" "$(cat "$TMP/err")"
fi

# dt_factor steps are the steps asked for and still comparable: at 64 fps the 8x step (0.0192 s
# on the 16x16 disk) is longer than a frame, so the sweep records frames at 1/0.0192 s: 0.1 s
# takes 6 steps (7 if the step were cut to the frame interval) and both runs have errors.
cat >"$TMP/dtf.json" <<'JSON'
{"name": "dtf", "scene": "rotating-disk",
 "set": {"time.end": 0.1, "time.fps": 64, "solver.integrator": "midpoint"},
 "axes": {"dt_factor": [0.5, 8], "resolution": [0.5]}}
JSON
if "$APICLAB" sweep "$TMP/dtf.json" --out "$TMP/dtf" --jobs 2 --quiet >"$TMP/out" 2>"$TMP/err"; then
  got=$(awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
    $c["dt_factor"] == 8 { s = $c["steps"] } $c["err_displacement"] != "" { e++ }
    END { print s "/" e + 0 }' "$TMP/dtf/runs.csv")
  if [ "$got" = "6/2" ]; then
    ok "dt_factor past the frame interval: exact steps (6), errors for both runs"
  else
    nok "dt_factor past the frame interval (steps/runs with errors: $got, want 6/2)" "$(cat "$TMP/dtf/runs.csv")"
  fi
else
  nok "dt_factor sweep exited $?" "$(cat "$TMP/err")"
fi

# solver.method as an axis: MPM, EoL and Eulerian from one scene (eol-spin); a method other than
# the scene's own replaces the solver section; the Eulerian baseline's energy change is the
# largest (advection damps the spin).
cat >"$TMP/methods.json" <<'JSON'
{"name": "methods", "scene": "eol-spin", "set": {"time.end": 0.1},
 "axes": {"solver.method": ["mpm", "eol", "eulerian"]}}
JSON
if "$APICLAB" sweep "$TMP/methods.json" --out "$TMP/methods" --jobs 2 --quiet >"$TMP/out" 2>"$TMP/err"; then
  got=$(awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
    $c["outcome"] == "completed" { n++ } { e[$c["solver.method"]] = $c["final_energy"] }
    END { print n + 0, (e["eulerian"] > 10 * e["eol"] && e["eulerian"] > 10 * e["mpm"]) ? "damps" : "no" }' "$TMP/methods/runs.csv")
  if [ "$got" = "3 damps" ] && grep -rq 'solver={.\?"method.\?":.\?"mpm' "$TMP/methods/runs"/*/result.json; then
    ok "solver.method axis: mpm, eol, eulerian runs from eol-spin; Eulerian damps"
  else
    nok "solver.method axis ($got)" "$(cat "$TMP/methods/runs.csv")"
  fi
else
  nok "solver.method sweep exited $?" "$(cat "$TMP/err")"
fi
# Moving EoL bodies (eol-two-balls): the grid nodes that hold material change from frame to frame
# as the balls cross the baseline's world grid, so frames.bin records the surface vertices, the
# same material points at every frame; the sweep collects both methods and measures eol against
# the baseline.
cat >"$TMP/moving.json" <<'JSON'
{"name": "moving", "scene": "eol-two-balls", "set": {"time.end": 0.09, "domain.dx": 0.025},
 "axes": {"solver.method": ["eol", "eulerian"]}}
JSON
if "$APICLAB" sweep "$TMP/moving.json" --out "$TMP/moving" --jobs 2 --quiet >"$TMP/out" 2>"$TMP/err"; then
  got=$(awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
    $c["outcome"] == "completed" { n++ } $c["err_displacement"] > 0 && $c["err_com"] != "" { e++ }
    END { print n + 0, e + 0 }' "$TMP/moving/runs.csv")
  if [ "$got" = "2 1" ]; then
    ok "eol and eulerian runs of moving bodies recorded and collected: one distance to the other"
  else
    nok "eol and eulerian sweep of eol-two-balls (completed, distances: $got)" "$(cat "$TMP/moving/runs.csv")"
  fi
else
  nok "eol and eulerian sweep of eol-two-balls exited $?" "$(tail -n 3 "$TMP/err")"
fi
bad_spec "unknown solver method" "unknown solver method 'fem'" '{"name":"x","scene":"eol-spin","axes":{"solver.method":["eol","fem"]}}'

# Resume: kill the sweep (and its run) after its first complete run, leave a half-written run,
# restart: the complete run is skipped, the half-written one removed, runs.csv the same.
setsid "$APICLAB" sweep "$TINY" --out "$TMP/b" --jobs 1 --quiet >/dev/null 2>&1 &
pgid=$!
for _ in $(seq 1 600); do
  n=$(ls "$TMP"/b/runs/*/result.json 2>/dev/null | wc -l)
  [ "$n" -ge 1 ] && break
  sleep 0.05
done
kill -KILL -- "-$pgid" 2>/dev/null
wait "$pgid" 2>/dev/null
complete=$(ls "$TMP"/b/runs/*/result.json 2>/dev/null | wc -l)
if [ "$complete" -ge 4 ]; then  # a very fast machine finished before the kill: drop two runs
  echo "note: the sweep finished before it was killed; removing two runs to resume"
  ls -d "$TMP"/b/runs/*/ | tail -n 2 | xargs rm -rf
fi
first=$(ls -d "$TMP"/b/runs/*/ 2>/dev/null | grep -v tmp | head -n 1)
mkdir -p "$TMP/b/runs/0123456789abcdef.tmp-99999"
echo '{"half": ' >"$TMP/b/runs/0123456789abcdef.tmp-99999/result.json"
before=$(stat -c %Y.%N "$first/result.json" 2>/dev/null | cut -c1-30)
if "$APICLAB" sweep "$TINY" --out "$TMP/b" --jobs 1 >"$TMP/out" 2>"$TMP/err"; then
  after=$(stat -c %Y.%N "$first/result.json" 2>/dev/null | cut -c1-30)
  if grep -qE 'sweep: [1-3] of 4 runs already complete' "$TMP/err" && [ "$before" = "$after" ] &&
    [ ! -e "$TMP/b/runs/0123456789abcdef.tmp-99999" ] &&
    diff <(csv_without_costs "$TMP/a/runs.csv") <(csv_without_costs "$TMP/b/runs.csv") >"$TMP/diff"; then
    ok "resume after a kill: complete runs skipped, half-written run ignored, same runs.csv"
  else
    nok "resume after a kill" "$(cat "$TMP/err")" "$(cat "$TMP/diff" 2>/dev/null | head -5)"
  fi
else
  nok "resumed sweep exited $?" "$(cat "$TMP/err")"
fi

# Exported job list through GNU parallel, then --collect.
if command -v parallel >/dev/null; then
  if "$APICLAB" sweep "$TINY" --out "$TMP/c" --export-jobs "$TMP/jobs.txt" >"$TMP/out" 2>"$TMP/err" &&
    [ "$(wc -l <"$TMP/jobs.txt")" -eq 4 ] && (cd / && parallel --jobs 2 <"$TMP/jobs.txt") &&
    "$APICLAB" sweep "$TINY" --collect "$TMP/c" >"$TMP/out" 2>"$TMP/err" &&
    diff <(csv_without_costs "$TMP/a/runs.csv") <(csv_without_costs "$TMP/c/runs.csv") >"$TMP/diff"; then
    ok "exported job list through GNU parallel: same runs.csv as --jobs (costs aside)"
  else
    nok "export + parallel + collect" "$(cat "$TMP/err")" "$(head -5 "$TMP/diff" 2>/dev/null)"
  fi
else
  nok "GNU parallel not installed (apt-get install parallel; setup.sh lists it)"
fi

# Dumps from the sweep's runs: asking for them re-runs the runs recorded without them;
# each run then has dump/series.pvd listing one .vtp per recorded frame, and runs.csv is the same.
bad_flag "--dump-format xyz" "--dump-format: unknown dump format 'xyz'" "$TINY" --out "$TMP/flag-out" \
  --dump-format xyz
cp "$TMP/a/runs.csv" "$TMP/a-before-dumps.csv" 2>/dev/null
if "$APICLAB" sweep "$TINY" --out "$TMP/a" --jobs 2 --dump-format vtk,ply >"$TMP/out" 2>"$TMP/err"; then
  bad=0
  for run in "$TMP"/a/runs/*/; do
    frames=$(sed -n 's/.*"frames": *\([0-9]*\).*/\1/p' "$run/result.json")
    listed=$(grep -c '<DataSet' "$run/dump/series.pvd" 2>/dev/null)
    vtp=$(ls "$run"/dump/frame_*.vtp 2>/dev/null | wc -l)
    ply=$(ls "$run"/dump/frame_*.ply 2>/dev/null | wc -l)
    [ -n "$frames" ] && [ "$listed" = "$frames" ] && [ "$vtp" = "$frames" ] && [ "$ply" = "$frames" ] &&
      [ -s "$run/dump/frames.csv" ] || bad=$((bad + 1))
  done
  if [ $bad -eq 0 ] && ! grep -q 'already complete' "$TMP/err" &&
    diff <(csv_without_costs "$TMP/a/runs.csv") <(csv_without_costs "$TMP/a-before-dumps.csv") >/dev/null; then
    ok "sweep --dump-format vtk,ply: every run re-run with a dump per frame and series.pvd"
  else
    nok "sweep --dump-format ($bad runs without complete dumps)" "$(cat "$TMP/err")" "$(ls "$TMP"/a/runs/*/dump | head)"
  fi
  if "$APICLAB" sweep "$TINY" --out "$TMP/a" --dump-format vtk,ply >"$TMP/out" 2>"$TMP/err" &&
    grep -q '4 of 4 runs already complete' "$TMP/err"; then
    ok "sweep --dump-format: runs with their dumps are skipped on a rerun"
  else
    nok "sweep --dump-format rerun" "$(cat "$TMP/err")"
  fi
  "$APICLAB" sweep "$TINY" --out "$TMP/a" --export-jobs "$TMP/dump-jobs.txt" --dump-format vtk >/dev/null 2>&1
  if grep -q -- '--dump dump --dump-format vtk --record' "$TMP/dump-jobs.txt"; then
    ok "sweep --export-jobs carries --dump-format into every command"
  else
    nok "export with --dump-format" "$(head -1 "$TMP/dump-jobs.txt")"
  fi
else
  nok "sweep --dump-format exited $?" "$(cat "$TMP/err")"
fi

finish sweep_tests
