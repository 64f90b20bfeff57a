#!/usr/bin/env bash
# Whose files an output path holds (docs/outputs.md, "Whose files"): a command replaces what the
# same scene and settings wrote before (the README's first command twice, a dump folder of its
# own cleared of stale frames), and refuses with exit 2 and one line naming the owner an output
# that is its input, two outputs on one path, a file apiclab did not write, another run's files
# and another spec's sweep folder; --overwrite replaces the last ones. A scene's name never puts
# a default output outside apiclab-out/.
# Usage: APICLAB=/path/to/apiclab clobber_tests.sh SOURCE_DIR
set -u
APICLAB=${APICLAB:?set APICLAB to the apiclab executable}
SRC=${1:?usage: clobber_tests.sh SOURCE_DIR}
TMP=$(mktemp -d "${TMPDIR:-/tmp}/apiclab-clobber.XXXXXX")
trap 'rm -rf "$TMP"' EXIT
source "$(dirname "${BASH_SOURCE[0]}")/../check_lib.sh"
SCENE="$SRC/assets/scenes/rotating-disk.json"
SHORT=(--t-end 0.1 --quiet)

# at DIR ARGS...: apiclab run in DIR; sets RC, ERR (stderr text).
at() {
  local dir=$1
  shift
  mkdir -p "$dir"
  ERR=$(cd "$dir" && "$APICLAB" "$@" 2>&1 >/dev/null)
  RC=$?
}
# refused NAME PATTERN: exit 2 and the one line matches PATTERN (grep -E).
refused() {
  if [ "$RC" -eq 2 ] && [ "$(printf '%s\n' "$ERR" | grep -c .)" -eq 1 ] &&
    printf '%s\n' "$ERR" | grep -Eq "$2"; then
    ok "$1"
  else
    nok "$1" "exit $RC" "$ERR"
  fi
}
accepted() { [ "$RC" -eq 0 ] && ok "$1" || nok "$1" "exit $RC" "$(printf '%s\n' "$ERR" | tail -n 3)"; }
same() { cmp -s "$1" "$2" && ok "$3" || nok "$3" "$1 changed"; }

# ---- the README's first command, twice ---------------------------------------------------------
at "$TMP/readme" run rotating-disk "${SHORT[@]}"
at "$TMP/readme" run rotating-disk "${SHORT[@]}"
accepted "run rotating-disk twice: the second run replaces the first's apiclab-out/ CSV"
rows=$(wc -l <"$TMP/readme/apiclab-out/rotating-disk-apic.csv")
at "$TMP/readme" run rotating-disk --set solver.scheme=apic "${SHORT[@]}"
accepted "the same settings spelled as --set replace it too"
[ "$(wc -l <"$TMP/readme/apiclab-out/rotating-disk-apic.csv")" = "$rows" ] &&
  ok "the replaced CSV holds one run's rows" || nok "CSV rows after a re-run" "$rows"

# ---- an input is never an output ---------------------------------------------------------------
cp "$SCENE" "$TMP/s.json"
cp "$SCENE" "$TMP/s.orig"
at "$TMP" run s.json --csv s.json "${SHORT[@]}"
refused "run s.json --csv s.json: refused" "^apiclab: --csv s.json is the scene file this command reads"
at "$TMP" run s.json --csv s --overwrite "${SHORT[@]}"
refused "--csv s (its sidecar s.json is the scene): refused, --overwrite or not" \
  "^apiclab: the settings sidecar of --csv s, s.json, is the scene file"
same "$TMP/s.json" "$TMP/s.orig" "the scene file is untouched"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n' >"$TMP/tetra.obj"
cp "$TMP/tetra.obj" "$TMP/tetra.orig"
cat >"$TMP/mesh.json" <<EOF
{"name": "mesh", "dim": 3, "domain": {"min": [-1, -1, -1], "max": [2, 2, 2], "dx": 0.1},
 "materials": [{"E": 1000, "nu": 0.3, "rho": 1}],
 "objects": [{"name": "solid", "shape": {"type": "mesh", "file": "$TMP/tetra.obj"}, "material": 0}]}
EOF
at "$TMP" run mesh.json --csv tetra.obj --overwrite "${SHORT[@]}"
refused "--csv on the scene's mesh file: refused, --overwrite or not" "^apiclab: --csv tetra.obj is a mesh file this command reads"
same "$TMP/tetra.obj" "$TMP/tetra.orig" "the mesh file is untouched"

# ---- two outputs on one path -------------------------------------------------------------------
at "$TMP/two" run rotating-disk --summary X --csv X "${SHORT[@]}"
refused "--summary X --csv X: refused" "^apiclab: --csv X and --summary X are one file"
[ ! -e "$TMP/two/X" ] && ok "--summary X --csv X: nothing written" || nok "X written" "$(ls -l "$TMP/two")"
at "$TMP/two" run rotating-disk --csv a.csv --summary a.csv.json "${SHORT[@]}"
refused "--summary on the CSV's sidecar: refused" "settings sidecar of --csv a.csv and --summary a.csv.json are one file"
at "$TMP/two" run rotating-disk --csv d/frames.csv --dump d "${SHORT[@]}"
refused "--csv inside --dump as frames.csv: refused" "frames.csv of --dump d are one file"

# ---- a file apiclab did not write ----------------------------------------------------------------
mkdir -p "$TMP/mine"
echo "my notes" >"$TMP/mine/notes.csv"
cp "$TMP/mine/notes.csv" "$TMP/mine/notes.orig"
at "$TMP/mine" run rotating-disk --csv notes.csv "${SHORT[@]}"
refused "--csv on a file without sidecar: refused" \
  "^apiclab: --csv notes.csv: the file exists and no sidecar notes.csv.json names its owner .*--overwrite"
same "$TMP/mine/notes.csv" "$TMP/mine/notes.orig" "the file without sidecar is untouched"
echo '{"mine": 1}' >"$TMP/mine/s.json"
at "$TMP/mine" run rotating-disk --csv r.csv --summary s.json "${SHORT[@]}"
refused "--summary on a JSON that is no run summary: refused" "^apiclab: --summary s.json: the file exists and is not an apiclab run summary"
mkdir -p "$TMP/mine/d" && echo x >"$TMP/mine/d/frame_0000.csv"
at "$TMP/mine" run rotating-disk --csv r.csv --dump d "${SHORT[@]}"
refused "--dump on a folder with frames and no sidecar: refused" \
  "^apiclab: --dump d: d/frame_0000.csv exists and no sidecar d/frames.csv.json names its owner"
at "$TMP/mine" run rotating-disk --csv notes.csv --overwrite "${SHORT[@]}"
accepted "--overwrite replaces the file without sidecar"
[ "$(head -c 5 "$TMP/mine/notes.csv")" = "step," ] && [ -f "$TMP/mine/notes.csv.json" ] &&
  ok "--overwrite: a diagnostics CSV with its sidecar now" || nok "--overwrite CSV" "$(head -2 "$TMP/mine/notes.csv")"

# ---- another run's files -------------------------------------------------------------------------
at "$TMP/other" run rotating-disk --csv o.csv --dump d --summary o.json "${SHORT[@]}"
cp "$TMP/other/o.csv" "$TMP/other/o.orig"
at "$TMP/other" run rotating-disk --scheme flip --csv o.csv "${SHORT[@]}"
refused "another run's CSV: refused naming the owner and the difference" \
  "^apiclab: --csv o.csv holds another run's diagnostics \(rotating-disk, apic: solver.scheme is apic there, flip here; o.csv.json\)"
same "$TMP/other/o.csv" "$TMP/other/o.orig" "another run's CSV is untouched"
at "$TMP/other" run rotating-disk --scheme flip --csv f.csv --summary o.json "${SHORT[@]}"
refused "another run's summary: refused" "^apiclab: --summary o.json holds another run's summary \(rotating-disk, apic"
at "$TMP/other" run rotating-disk --set materials.0.E=2000 --csv f.csv --dump d "${SHORT[@]}"
refused "another run's dump folder: refused" \
  "^apiclab: --dump d holds another run's frames \(rotating-disk, apic: materials.0.E is [0-9.e+]+ there, 2000(\.0)? here"
at "$TMP/other" run rotating-disk --scheme flip --csv o.csv --overwrite "${SHORT[@]}"
accepted "--overwrite replaces another run's CSV"
grep -q '"scheme": "flip"' "$TMP/other/o.csv.json" && ok "--overwrite: the sidecar is the new run's" ||
  nok "sidecar after --overwrite" "$(head -c 300 "$TMP/other/o.csv.json")"

# ---- a dump folder of its own is cleared of stale frames -----------------------------------------
D="$TMP/own/d"
at "$TMP/own" run rotating-disk --csv r.csv --dump d --dump-format csv,vtk "${SHORT[@]}"
echo "kept" >"$D/notes.txt"
at "$TMP/own" run rotating-disk --csv r.csv --dump d --dump-format csv "${SHORT[@]}"
accepted "the same run again into its own dump folder"
if [ -z "$(cd "$D" && ls ./*.vtp series.pvd 2>/dev/null)" ] && [ -f "$D/notes.txt" ]; then
  ok "own dump folder: the older run's .vtp and series.pvd removed, other files kept"
else
  nok "stale frames removed" "$(ls "$D")"
fi
at "$TMP/own" run rotating-disk --csv r.csv --dump d --t-end 0.2 --quiet --overwrite
at "$TMP/own" run rotating-disk --csv r.csv --dump d --overwrite "${SHORT[@]}"
listed=$(awk -F, 'NR > 1 { printf "frame_%04d.csv\n", $1 }' "$D/frames.csv" | sort)
present=$(cd "$D" && ls frame_*.csv | sort)
if [ "$RC" -eq 0 ] && [ "$listed" = "$present" ]; then
  ok "--overwrite over a longer run's folder: frames.csv lists exactly the frames present"
else
  nok "frames after --overwrite" "listed: $listed" "present: $present"
fi

# ---- a scene's name stays a file name in apiclab-out/ --------------------------------------------
python3 -c "import json,sys; j=json.load(open(sys.argv[1])); j['name']='../../../../elsewhere/x'; json.dump(j, open(sys.argv[2], 'w'))" \
  "$SCENE" "$TMP/evil.json"
at "$TMP/a/b/c" run "$TMP/evil.json" "${SHORT[@]}"
made=$(cd "$TMP/a/b/c/apiclab-out" 2>/dev/null && ls ./*.csv)
if [ "$RC" -eq 0 ] && [ ! -e "$TMP/elsewhere" ] && [ "$made" = "./---..-..-..-elsewhere-x-apic.csv" ]; then
  ok "a scene named ../../../../elsewhere/x writes apiclab-out/---..-..-..-elsewhere-x-apic.csv"
else
  nok "scene name sanitised" "exit $RC" "$made" "$(ls "$TMP")" "$ERR"
fi

# ---- render and compare --------------------------------------------------------------------------
if "$APICLAB" render --help >/dev/null 2>&1; then
  R=(--size 64x48 "${SHORT[@]}")
  at "$TMP/r" render rotating-disk --out out "${R[@]}"
  at "$TMP/r" render rotating-disk --out out "${R[@]}"
  accepted "render twice into its own --out folder"
  at "$TMP/r" compare rotating-disk --schemes pic,apic --out out "${R[@]}"
  refused "compare into a render's folder: refused" "^apiclab: --out out holds another run's frames \(rotating-disk, apic: panes is unset there"
  at "$TMP/r" compare rotating-disk --schemes pic,apic --out out --overwrite "${R[@]}"
  accepted "compare --overwrite into a render's folder"
  if command -v ffmpeg >/dev/null; then
    echo "my notes" >"$TMP/r/notes.mp4"
    at "$TMP/r" render rotating-disk --out out2 --video notes.mp4 "${R[@]}"
    refused "render --video on a file that is no MP4: refused" "^apiclab: --video notes.mp4: the file exists and is not the kind"
  fi
fi

# ---- gui --screenshot ----------------------------------------------------------------------------
if "$APICLAB" gui --help >/dev/null 2>&1; then
  echo "my notes" >"$TMP/notes.txt"
  at "$TMP" gui rotating-disk --screenshot notes.txt --frames 1
  refused "gui --screenshot on a file that is no PNG: refused before a window opens" \
    "^apiclab: --screenshot notes.txt: the file exists and is not the kind apiclab writes there"
fi

# ---- sweeps: another spec's folder --------------------------------------------------------------
A="$SRC/tests/sweeps/tiny.json"
python3 -c "import json,sys; j=json.load(open(sys.argv[1])); j['name']='tiny-b'; json.dump(j, open(sys.argv[2], 'w'))" "$A" "$TMP/b.json"
python3 -c "import json,sys; json.dump(json.load(open(sys.argv[1])), open(sys.argv[2], 'w'), indent=8)" "$A" "$TMP/a-reformatted.json"
at "$TMP/sw" sweep "$A" --out s --export-jobs jobs.txt
accepted "sweep A: its folder (jobs exported)"
at "$TMP/sw" sweep "$TMP/b.json" --out s --export-jobs jobs-b.txt
refused "sweep B --out on A's folder: refused naming A" "^apiclab: sweep: s holds another sweep \(sweep 'tiny': s/spec.json differs from"
at "$TMP/sw" sweep "$TMP/b.json" --collect s
refused "sweep B --collect on A's folder: refused" "^apiclab: sweep: s holds another sweep"
same "$TMP/sw/s/spec.json" "$A" "A's spec.json is untouched"
at "$TMP/sw" sweep "$TMP/a-reformatted.json" --collect s
accepted "the same spec laid out otherwise: its own folder"
at "$TMP/sw" sweep "$TMP/b.json" --collect s --overwrite
accepted "sweep B --collect --overwrite on A's folder"
same "$TMP/sw/s/spec.json" "$TMP/b.json" "--overwrite: spec.json is B's"
at "$TMP/sw" sweep "$TMP/b.json" --out s --export-jobs "$TMP/b.json"
refused "--export-jobs on the spec: refused" "is the spec this sweep reads"

finish clobber_tests
