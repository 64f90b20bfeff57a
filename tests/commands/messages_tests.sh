#!/usr/bin/env bash
# Messages in the project's words: bad input through the real executable gives one line,
# "apiclab: " and the cause, exit 2, and no library's phrase (CLI11's, nlohmann's,
# std::filesystem's) reaches the user; options that belong to another solver method say so;
# --help reads cleanly. docs/cli.md, Errors.
# Usage: APICLAB=/path/to/apiclab messages_tests.sh
set -u
APICLAB=${APICLAB:?set APICLAB to the apiclab executable}
TMP=$(mktemp -d "${TMPDIR:-/tmp}/apiclab-messages.XXXXXX")
trap 'rm -rf "$TMP"' EXIT
mkdir -p "$TMP/cwd"
source "$(dirname "${BASH_SOURCE[0]}")/../check_lib.sh"

# Phrases of the libraries apiclab is built on; none may reach stderr or stdout of a refusal.
LIBRARY_PHRASES=("Could not convert" "not in range" "The following argument" "were not expected"
  "is not an allowed value" "Should be true/false" "required but received" "INT in [" "Value "
  "syntax error while parsing" "parse_error" "json.exception" "last read:" "invalid literal"
  "unexpected end of input" "filesystem error" "File name too long" "terminate called" "what():"
  "std::" "basic_string" "bad_alloc")

# refuse NAME NEEDLE... -- ARGS: exit 2, one line "apiclab: ...", each NEEDLE in it, no library
# phrase.
refuse() {
  local name=$1
  shift
  local needles=()
  while [ "$1" != "--" ]; do
    needles+=("$1")
    shift
  done
  shift
  run_cli "$@"
  local problems=()
  [ "$RC" -eq 2 ] || problems+=("exit $RC, expected 2")
  local lines
  lines=$(grep -c '' "$ERR")
  [ "$lines" -eq 1 ] || problems+=("$lines lines on stderr")
  head -n 1 "$ERR" | grep -q '^apiclab: ' || problems+=("no 'apiclab: ' prefix")
  for n in "${needles[@]}"; do grep -qF -- "$n" "$ERR" || problems+=("lacks '$n'"); done
  for p in "${LIBRARY_PHRASES[@]}"; do
    grep -qF -- "$p" "$ERR" "$OUT" && problems+=("library phrase '$p'")
  done
  if [ ${#problems[@]} -eq 0 ]; then
    ok "$name"
  else
    nok "$name" "${problems[@]}" "$(head -c 400 "$ERR")"
  fi
}

printf '// a comment\n{"dim": 2}\n' >"$TMP/comments.json"
: >"$TMP/empty.json"
printf '{"dim": 2,}\n' >"$TMP/comma.json"
printf "{'dim': 2}\n" >"$TMP/single.json"
long=$(printf 'a%.0s' $(seq 1 30000))

# ---- CLI11: conversions, ranges, unknown options and commands ------------------------------
refuse "--threads abc" "--threads" "whole number from 1 to 4096" "'abc'" -- run rotating-disk --threads abc
refuse "--frames 2.5" "--frames" "whole number" "'2.5'" -- run rotating-disk --frames 2.5
refuse "--t-end abc" "--t-end" "expected a number" -- run rotating-disk --t-end abc
refuse "--tend: did you mean" "unexpected argument '--tend'" "did you mean '--t-end'?" -- run rotating-disk --tend 1
refuse "runn: did you mean" "unexpected argument 'runn'" "did you mean 'run'?" -- runn rotating-disk
refuse "--frames without a value" "--frames needs a value" -- run rotating-disk --frames
refuse "--max-steps -1" "--max-steps" "above 0" -- run rotating-disk --max-steps -1
refuse "bench --dim 4" "--dim" "from 2 to 3" -- bench --dim 4
refuse "docs nosuch" "expected one of scene-keys, schemes, scenes" -- docs nosuch
refuse "roundtrip --seed -1" "--seed" "whole number" -- roundtrip --seed -1
refuse "sweep --jobs 0" "--jobs" "from 1 to 4096" -- sweep spec.json --jobs 0
refuse "run without a scene" "scene is required" -- run

# ---- numeric flags refuse through the registry: --set KEY=VALUE's words, naming the flag ------
for c in "--dt 0 time.dt.value" "--t-end 0 time.end" "--fps 0 time.fps" \
  "--flip-alpha 1.5 solver.flip_alpha" "--lambda 2 solver.lambda solver.integrator=lambda"; do
  # The scene's integrator is midpoint: --lambda runs the lambda integrator, as its --set must.
  read -r flag value key also <<<"$c"
  refuse "$flag $value: the registry's message" "apiclab: $flag $value: key '$key': " \
    "is outside the allowed range" -- run rotating-disk "$flag" "$value"
  flag_says=$(sed "s/^apiclab: $flag $value: //" "$ERR")
  run_cli run rotating-disk ${also:+--set "$also"} --set "$key=$value"
  set_says=$(sed -E "s/^apiclab: [^:]*rotating-disk.json: //" "$ERR")
  if [ "$RC" -eq 2 ] && [ "$flag_says" = "$set_says" ]; then
    ok "$flag $value and --set $key=$value say the same"
  else
    nok "$flag $value and --set $key=$value differ" "flag: $flag_says" "--set (exit $RC): $set_says"
  fi
done

# ---- nlohmann: scene files and --set values that are not JSON --------------------------------
refuse "scene with comments" "comments.json" "line 1, column 1" "comments (// and /* */) are not part of JSON" -- run "$TMP/comments.json"
refuse "empty scene file" "empty.json" "the text is empty" -- run "$TMP/empty.json"
refuse "trailing comma" "comma.json" "line 1, column 11" "unexpected '}'" "expected a key in double quotes" -- run "$TMP/comma.json"
refuse "single quotes" "single.json" "double quotes" -- run "$TMP/single.json"
refuse "--set with a value that is not JSON" "--set solver.scheme=a/b" "not valid JSON" -- run rotating-disk --set solver.scheme=a/b
refuse "--set with a bare word for a number" "E must be a number" -- run rotating-disk --set materials.0.E=abc

# ---- std::filesystem: a 30 kB name -----------------------------------------------------------
refuse "30 kB scene name" "the path is too long (30000 characters" -- run "$long"
refuse "30 kB --csv name" "cannot write output file" "the path is too long (30004 characters" -- run rotating-disk --t-end 0.01 --csv "$long.csv"

# ---- an allocation that fails past the memory cap (a 1e-4 grid under a 150 MB address space) ----
run_oom() { (ulimit -v 150000 && run_cli "$@"); }  # OUT and ERR are files: they outlive the subshell
run_oom run rotating-disk --max-memory none --set domain.dx=0.0005 --t-end 0.001 --csv big.csv
if grep -q "^apiclab: out of memory: an allocation failed" "$ERR" && [ "$(grep -c '' "$ERR")" -eq 1 ] &&
  ! grep -q "bad_alloc" "$ERR"; then
  ok "an allocation failure in apiclab's words"
else
  nok "an allocation failure in apiclab's words" "$(head -c 300 "$ERR")"
fi

# ---- options that belong to another method --------------------------------------------------
for opt in "--scheme apic" "--kernel quadratic" "--integrator midpoint" "--flip-alpha 0.9"; do
  # shellcheck disable=SC2086
  refuse "$opt on an EoL scene" "$opt: eol-spin runs solver.method eol" "how MPM runs" "--set solver.method=mpm" -- run eol-spin $opt
done
refuse "--scheme eol is a method" "eol is a solver method" "--set solver.method=eol" -- run rotating-disk --scheme eol
refuse "--scheme mls names the option and the fix" "--scheme mls on skew-impact" "(--integrator symplectic)" -- run skew-impact --scheme mls
refuse "--dump-format vtk,vtk-raw" "both write frame_NNNN.vtp" -- run rotating-disk --dump d --dump-format vtk,vtk-raw
refuse "render --video v.txt" "--video v.txt" ".mp4" -- render rotating-disk --out frames --video v.txt

# ffmpeg's own lines are not printed: its last line is the cause in apiclab's one line.
mkdir -p "$TMP/bin"
printf '#!/bin/sh\necho "ffmpeg chatter" >&2\necho "Unknown encoder libx264" >&2\nexit 1\n' >"$TMP/bin/ffmpeg"
chmod +x "$TMP/bin/ffmpeg"
(cd "$TMP/cwd" && PATH="$TMP/bin:$PATH" "$APICLAB" render rotating-disk --t-end 0.05 --out vid --video v.mp4 --quiet) >"$TMP/stdout" 2>"$TMP/stderr"
rc=$?
if [ $rc -eq 2 ] && [ "$(tail -n 1 "$TMP/stderr")" = "apiclab: ffmpeg failed (exit 1) encoding v.mp4: Unknown encoder libx264" ] &&
  ! grep -q "chatter" "$TMP/stderr"; then
  ok "render --video: ffmpeg's failure in one line"
elif grep -q "offscreen\|EGL\|OSMesa" "$TMP/stderr" && [ $rc -eq 2 ] && ! grep -q ffmpeg "$TMP/stderr"; then
  ok "render --video: no offscreen OpenGL here (skipped)"
else
  nok "render --video: ffmpeg's failure in one line" "exit $rc" "$(tail -n 3 "$TMP/stderr")"
fi

# --set solver.method switches the method: the scene's MPM keys are left out, with a note.
run_cli run rotating-disk --set solver.method=eulerian --t-end 0.02 --csv m.csv
if [ "$RC" -eq 0 ] && grep -q "note: .*solver.method=eulerian" "$ERR" &&
  python3 -c "import json,sys; j=json.load(open(sys.argv[1])); s=j['settings']; sys.exit(0 if s['solver']['method']=='eulerian' and 'kernel' not in s['solver'] and 'apiclab_version' in j else 1)" "$TMP/cwd/m.csv.json"; then
  ok "--set solver.method=eulerian on an MPM scene runs eulerian"
else
  nok "--set solver.method=eulerian on an MPM scene" "exit $RC" "$(head -c 600 "$ERR")"
fi

# An EoL run: --precision float warns; --dump defaults to vtk; the summary line gives steps/s;
# the sidecar records the EoL solver, the version, integers as integers and "none" as null.
run_cli run eol-spin --t-end 0.02 --precision float --dump dump --csv e.csv --summary s.json
problems=()
[ "$RC" -eq 0 ] || problems+=("exit $RC")
grep -q '^apiclab: warning: .*--precision float: the eol solver runs in double' "$ERR" || problems+=("no precision warning")
ls "$TMP/cwd/dump/"*.vtp >/dev/null 2>&1 || problems+=("--dump wrote no .vtp")
grep -q ' steps/s' "$ERR" && ! grep -q 'particle-steps/s' "$ERR" || problems+=("summary line rate")
python3 - "$TMP/cwd/e.csv.json" "$TMP/cwd/s.json" <<'EOF' || problems+=("sidecar or summary content")
import json, sys
side = json.load(open(sys.argv[1]))
s = side["settings"]
assert "apiclab_version" in side, "no version"
assert s["precision"] == "double", s["precision"]
assert set(s["solver"]) == {"method", "label", "contact", "elasticity"}, s["solver"]
assert s["solver"]["elasticity"] == "explicit", s["solver"]
p = s["parameters"]
assert "solver.flip_alpha" not in p, "an MPM key in an EoL run"
assert isinstance(p["solver.padding"], int), p["solver.padding"]
assert all(v is None or abs(v) < 1e30 for v in p.values()), "a 'none' written as a number"
summary = json.load(open(sys.argv[2]))
assert summary["particle_steps_per_second"] is None and summary["steps_per_second"] > 0
EOF
if [ ${#problems[@]} -eq 0 ]; then ok "EoL run: precision warning, vtk dump, steps/s, sidecar"; else nok "EoL run" "${problems[@]}" "$(head -c 600 "$ERR")"; fi

# A sweep's progress into a file: plain lines, no \r (a terminal gets the \r line).
printf '{"name": "one", "scene": "rotating-disk", "set": {"time.end": 0.05, "solver.scheme": "pic"}, "axes": {"resolution": [0.5]}}\n' >"$TMP/one.json"
"$APICLAB" sweep "$TMP/one.json" --out "$TMP/one" >"$TMP/sweep-out" 2>"$TMP/sweep-err"
rc=$?
if [ $rc -eq 0 ] && grep -q '^apiclab: sweep: 1/1 runs' "$TMP/sweep-err" && ! grep -q $'\r' "$TMP/sweep-err"; then
  ok "sweep progress into a file: plain lines without \\r"
else
  nok "sweep progress into a file" "exit $rc" "$(od -c "$TMP/sweep-err" | head -5)"
fi

# ---- help ------------------------------------------------------------------------------------
"$APICLAB" --help >"$TMP/help" 2>&1
problems=()
for n in "eol" "Eulerian-on-Lagrangian" "pic flip apic" "Exit codes" "130"; do grep -qF -- "$n" "$TMP/help" || problems+=("lacks '$n'"); done
grep -qF "PIC, FLIP, APIC and RPIC" "$TMP/help" && problems+=("the old description")
if [ ${#problems[@]} -eq 0 ]; then ok "apiclab --help names both families and the exit codes"; else nok "apiclab --help" "${problems[@]}"; fi
"$APICLAB" run --help >"$TMP/help" 2>&1
if ! grep -qE 'INT:|\[1;|in \[[0-9]+ - ' "$TMP/help" && grep -qF "dimensionless; allowed:" "$TMP/help"; then
  ok "run --help: no CLI11 validator text, units read as units"
else
  nok "run --help" "$(grep -E 'INT:|\[1;|in \[[0-9]+ - ' "$TMP/help" | head -3)"
fi
"$APICLAB" sweep --help >"$TMP/help" 2>&1
if grep -qE -- '--jobs.*default: 1' "$TMP/help"; then ok "sweep --help: --jobs default"; else nok "sweep --help: --jobs default"; fi
if "$APICLAB" figures --help >"$TMP/help" 2>&1; then
  if grep -qE -- '--only.*: 1,3' "$TMP/help"; then ok "figures --help lists --only ids"; else nok "figures --help lists --only ids" "$(grep -- --only "$TMP/help")"; fi
fi
"$APICLAB" list >"$TMP/list" 2>&1
if [ "$(awk 'length > 100' "$TMP/list" | wc -l)" -eq 0 ]; then ok "list: lines wrapped"; else nok "list: lines over 100 characters" "$(awk 'length > 100' "$TMP/list" | head -2)"; fi

finish messages_tests
