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

source "$(dirname "${BASH_SOURCE[0]}")/../check_lib.sh"

# expect_error NAME NEEDLE... -- ARGS...: exit 2, one stderr line holding every needle (a needle
# "!TEXT" must not appear), never the JSON library's raw exception text.
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
  if grep -qF "json.exception" "$ERR"; then problems+=("stderr shows the JSON library's raw text"); fi
  local n
  for n in "${needles[@]}"; do
    case "$n" in
      !*) if grep -qF -- "${n#!}" "$ERR"; then problems+=("stderr names '${n#!}'"); fi ;;
      *) grep -qF -- "$n" "$ERR" || problems+=("stderr lacks '$n'") ;;
    esac
  done
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
expect_error "missing shipped scene name" "no-such-scene" "apiclab list" -- run no-such-scene --t-end 0.01
expect_error "empty scene path" "no scene file given" -- run ""

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
# Flags go through --set, so the registry's range and message apply (sim/scene/parameters.hpp).
# The message names the option, and the scene key it sets, never the scene file.
expect_error "--dt 0 (fixed step)" "--dt 0" "'time.dt.value'" "(0, inf)" "!$DISK" -- run "$DISK" --dt 0
expect_error "--flip-alpha 1.5" "--flip-alpha 1.5" "'solver.flip_alpha'" "[0, 1]" "!$DISK" -- run "$DISK" --flip-alpha 1.5
expect_error "--set of a fractional CG cap" "'solver.cg_max_iterations'" -- run "$DISK" --set solver.cg_max_iterations=2.5
expect_error "--scheme unknown" "apicc" -- run "$DISK" --scheme apicc
expect_error "--kernel unknown" "quintic" -- run "$DISK" --kernel quintic
expect_error "unwritable --csv" "/proc/nope" -- run "$DISK" --t-end 0.01 --csv /proc/nope/x.csv
expect_error "unwritable --dump" "/proc/nope" -- run "$DISK" --t-end 0.01 --csv "$TMP/d.csv" --dump /proc/nope/dir
expect_error "roundtrip --scheme flip" "FLIP" -- roundtrip --scheme flip --res 16
expect_error "roundtrip --scheme asflip" "ASFLIP" "prior particle velocities" -- roundtrip --scheme asflip --res 16
expect_error "xpic order below 1" "solver.xpic_order" "outside the allowed range" -- run rotating-disk --scheme xpic --set solver.xpic_order=0
expect_error "asflip beta above 1" "solver.asflip_beta" "outside the allowed range" -- run rotating-disk --scheme asflip --set solver.asflip_beta=1.5
expect_error "roundtrip --kernel unknown" "quintic" -- roundtrip --kernel quintic --res 16

# ---- bad input: each class with one line naming the real cause ----------------------------
# Paths that are not regular files (a fifo would block a plain open).
expect_error "scene path is a directory" "$TMP" "is a directory" -- run "$TMP"
mkfifo "$TMP/fifo.json"
expect_error "scene path is a fifo" "$TMP/fifo.json" "fifo" -- run "$TMP/fifo.json"
expect_error "scene path is a character device" "/dev/null" "character device" -- run /dev/null
: >"$TMP/empty.json"
expect_error "empty scene file" "$TMP/empty.json" "malformed JSON" "line 1" -- run "$TMP/empty.json"
if [ "$(id -u)" -ne 0 ]; then
  cp "$DISK" "$TMP/unreadable.json" && chmod 000 "$TMP/unreadable.json"
  expect_error "unreadable scene file" "$TMP/unreadable.json" "cannot read" -- run "$TMP/unreadable.json"
fi

# Degenerate geometry.
variant rot-axis-zero 's/"radius": 0.3/"radius": 0.3, "rotation": {"axis": [0, 0, 0], "degrees": 30}/'
expect_error "zero-length rotation axis" "$f" "'objects.0.shape.rotation.axis'" "zero length" -- run "$f"
cat >"$TMP/torus.json" <<'EOF'
{"name": "torus", "dim": 3,
 "domain": {"min": [0, 0, 0], "max": [1, 1, 1], "dx": 0.05},
 "materials": [{"E": 1000, "nu": 0.3, "rho": 1}],
 "objects": [{"name": "ring", "shape": {"type": "torus", "center": [0.5, 0.5, 0.5], "inner": 0.1, "outer": 0.2, "axis": [0, 0, 0]}, "material": 0}]}
EOF
expect_error "zero-length torus axis" "$TMP/torus.json" "'objects.0.shape.axis'" "zero length" -- run "$TMP/torus.json"
sed -e 's/"type": "torus"/"type": "annulus", "length": 0.2/' "$TMP/torus.json" >"$TMP/annulus.json"
expect_error "zero-length annulus axis" "$TMP/annulus.json" "'objects.0.shape.axis'" "zero length" -- run "$TMP/annulus.json"
expect_error "NaN through --set" "--set" "nan" "not valid JSON" -- run "$DISK" --set objects.0.velocity=[nan,0]

# Meshes: a scene around one OBJ file.
mesh_scene() {  # mesh_scene OBJ: $f = a 3D scene sampling that mesh
  f="$TMP/mesh-$(basename "$1" .obj).json"
  cat >"$f" <<EOF
{"name": "mesh", "dim": 3, "domain": {"min": [-1, -1, -1], "max": [2, 2, 2], "dx": 0.1},
 "materials": [{"E": 1000, "nu": 0.3, "rho": 1}],
 "objects": [{"name": "solid", "shape": {"type": "mesh", "file": "$1"}, "material": 0}]}
EOF
}
tetra_vertices=$'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n'
printf '%sf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 9\n' "$tetra_vertices" >"$TMP/badindex.obj"
mesh_scene "$TMP/badindex.obj"
expect_error "mesh face index past the vertex count" "badindex.obj" "face 4" "vertex 9" "4 vertices" "!outside the domain" -- run "$f"
printf '%sf 1 3 2\nf 1 2 4\nf 1 4 3\n' "$tetra_vertices" >"$TMP/open.obj"
mesh_scene "$TMP/open.obj"
expect_error "open (non-manifold) mesh" "open.obj" "not a closed manifold" -- run "$f"
# The EoL rest shape reads the same OBJ with the same checks (sim/eol/shape/rest_shape.cpp).
expect_error "open mesh as an EoL rest shape" "open.obj" "not a closed manifold" -- run "$f" --set solver.method=eol
expect_error "open mesh as an Eulerian rest shape" "open.obj" "not a closed manifold" -- run "$f" --set solver.method=eulerian
printf '%sv 0 0 -1\nv 0 -1 0\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\nf 1 2 5\nf 1 5 6\nf 1 6 2\nf 2 6 5\n' "$tetra_vertices" >"$TMP/bowtie.obj"  # two tetrahedra on one edge
mesh_scene "$TMP/bowtie.obj"
expect_error "non-manifold mesh as an EoL rest shape" "bowtie.obj" "not a closed manifold" "joins 4" -- run "$f" --set solver.method=eol
printf '%sf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n' "$tetra_vertices" >"$TMP/tetra.obj"
mesh_scene "$TMP/tetra.obj"
expect_error "EoL mesh outside the domain" "'objects.0.shape'" "outside the domain on axis x" -- run "$f" --set solver.method=eulerian --set objects.0.shape.translate=[5,0,0]
printf '%s' "$tetra_vertices" >"$TMP/nofaces.obj"
mesh_scene "$TMP/nofaces.obj"
expect_error "mesh without faces" "nofaces.obj" "no faces" -- run "$f"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 3 2\n' >"$TMP/flat.obj"  # closed, but flat
mesh_scene "$TMP/flat.obj"
expect_error "flat mesh (zero volume)" "flat.obj" "no volume" -- run "$f"
printf 'v nan 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n' >"$TMP/nan.obj"
mesh_scene "$TMP/nan.obj"
expect_error "mesh vertex nan" "nan.obj:1:" "vertex 1" "not a finite number" -- run "$f"
printf '%sf 0 3 2\n' "$tetra_vertices" >"$TMP/zero.obj"
mesh_scene "$TMP/zero.obj"
expect_error "mesh face index 0" "zero.obj:5:" "vertex index 0" "!Failed parse" -- run "$f"
mesh_scene "$TMP"
expect_error "mesh path is a directory" "'objects.0.shape.file'" "is a directory" -- run "$f"

# Values of the wrong kind.
variant dim-fraction 's/"dim": 2/"dim": 2.5/'
expect_error "fractional dim" "'dim'" "integer" -- run "$f"
variant dim-huge 's/"dim": 2/"dim": 4294967298/'
expect_error "dim past the int range" "'dim'" "integer" -- run "$f"
variant ppc-fraction 's/"ppc": 4/"ppc": 4.5/'
expect_error "fractional particles per cell" "'objects.0.sampling.ppc'" "(integers)" -- run "$f"
variant E-string 's/"E": 1000/"E": "1000"/'
expect_error "string where a number goes" "'materials.0.E'" "expected a number" -- run "$f"
variant E-bool 's/"E": 1000/"E": true/'
expect_error "bool where a number goes" "'materials.0.E'" "expected a number" -- run "$f"
variant cg-fraction 's/"scheme": "apic"/"scheme": "apic", "cg_max_iterations": 2.5/'
expect_error "fractional iteration cap" "'solver.cg_max_iterations'" -- run "$f"
variant velocity-string 's/"angular_velocity": 0.4/"angular_velocity": "fast"/'
expect_error "string angular velocity" "'objects.0.angular_velocity'" "expected a number" -- run "$f"

# Required keys, named in the scene's terms.
variant no-E 's/"E": 1000, //'
expect_error "missing materials.0.E" "'materials.0.E'" "missing" -- run "$f"
variant no-shape 's/"shape": {"type": "ball", "center": \[0.5, 0.5\], "radius": 0.3},//'
expect_error "missing objects.0.shape" "'objects.0.shape'" "missing" -- run "$f"

# Numbers beyond a double.
variant E-overflow 's/"E": 1000/"E": 1e400/'
expect_error "1e400 in the scene" "'materials.0.E'" "1e400" "out of range" "line" -- run "$f"
expect_error "1e400 through --set" "--set materials.0.E=1e400" "not valid JSON" -- run "$DISK" --set materials.0.E=1e400

# Duplicate keys (JSON would keep the last silently).
variant E-twice 's/"E": 1000/"E": 1000, "E": 2000/'
expect_error "duplicate key" "'materials.0.E'" "twice" -- run "$f"

# Options are named as options, not as the scene's keys.
expect_error "--t-end nan" "--t-end" "!rotating-disk.json" -- run "$DISK" --t-end nan
expect_error "--fps -24" "--fps" "!rotating-disk.json" -- run "$DISK" --fps -24
expect_error "--dt inf" "--dt" "!rotating-disk.json" -- run "$DISK" --dt inf
expect_error "--set value that is not a number" "--set materials.0.E=abc" "must be a number" -- run "$DISK" --set materials.0.E=abc
expect_error "--set value that is not JSON" "--set" "'[1,'" "not valid JSON" -- run "$DISK" "--set" "objects.0.velocity=[1,"
expect_error "--set without =" "--set" "KEY=VALUE" -- run "$DISK" --set materials.0.E
expect_error "--set on a path through a number" "'materials.0.E.x'" -- run "$DISK" --set materials.0.E.x=1

# Argument-parser errors: exit 2 and one line, not CLI11's 104-109.
expect_error "run without a scene" "scene" -- run
expect_error "unknown option" "--bogus" -- run "$DISK" --bogus
expect_error "fractional --frames" "--frames" -- run "$DISK" --frames 2.5
expect_error "unknown subcommand" "nosuch" -- nosuch
expect_error "bench --dim 4" "--dim" -- bench --dim 4
expect_error "compare --scheme refused" "not --scheme" -- compare "$DISK" --out "$TMP/cmp" --schemes pic,apic --scheme apic

# Conflicting or meaningless options.
expect_error "--t-end 1e300: more frames than an int holds" "'time.end'" "frames" -- run "$DISK" --t-end 1e300
expect_error "--frames with --t-end" "--frames" "--t-end" -- run "$DISK" --frames 3 --t-end 0.1
expect_error "--flip-alpha with APIC" "--flip-alpha" "apic" -- run "$DISK" --flip-alpha 0.5 --t-end 0.01
expect_error "--threads 0" "--threads" -- run "$DISK" --threads 0
expect_error "bench --particles 0" "--particles" -- bench --particles 0
expect_error "bench --steps 0" "--steps" -- bench --steps 0
if "$APICLAB" gui --help >/dev/null 2>&1; then
  expect_error "gui --frames 0" "--frames" -- gui "$DISK" --frames 0
  expect_error "gui --scheme with --schemes" "--schemes" -- gui "$DISK" --scheme pic --schemes pic,apic
  # The pane list is compare's (app/pane_spec.cpp): same names, same messages.
  expect_error "gui pane listed twice" "'apic' is listed twice" -- gui eol-spin --schemes apic,eol,apic
  expect_error "gui mls pane with an implicit scene" "--schemes mls" "symplectic" -- gui "$DISK" --schemes apic,mls
  expect_error "gui unknown pane" "unknown scheme 'foo'" "solver method without schemes" -- gui eol-spin --schemes apic,foo
  expect_error "gui mpm:eol is no scheme" "unknown scheme 'eol'" -- gui eol-spin --schemes mpm:eol
  # Window sizes the soak found crashing GLFW (assert on < 0) or X (BadValue on 100000).
  expect_error "gui --size -5x300" "--size" "1 to 8192" -- gui "$DISK" --size -5x300
  expect_error "gui --size 0x0" "--size" "1 to 8192" -- gui "$DISK" --size 0x0
  expect_error "gui --size 100000x100000" "--size" "1 to 8192" -- gui "$DISK" --size 100000x100000
  expect_error "gui --size with trailing junk" "--size" "WxH" -- gui "$DISK" --size 1600x900px
  expect_error "gui --heartbeat into a directory" "--heartbeat" "is a directory" -- gui "$DISK" --heartbeat "$TMP"
fi

# Memory: a typo dx is refused at once with the estimate and the available memory.
start=$(date +%s%N)
expect_error "typo dx 1e-6" "needs about" "grid nodes" "available memory" "--max-memory" -- run "$DISK" --set domain.dx=1e-6
ms=$(( ($(date +%s%N) - start) / 1000000 ))
if [ "$ms" -lt 1000 ]; then ok "typo dx refused in $ms ms"; else nok "typo dx refused quickly" "took $ms ms"; fi
expect_error "--max-memory below the estimate" "needs about" "cap of 500 kB" -- run "$DISK" --max-memory 500k
expect_error "--max-memory malformed" "--max-memory" "BYTES" -- run "$DISK" --max-memory lots
expect_error "roundtrip --res past memory" "roundtrip --res 2000000" "needs about" -- roundtrip --res 16,2000000
expect_error "bench past --max-memory" "needs about" -- bench --particles 100000 --max-memory 1k
# compare holds one simulation per scheme: the estimate counts them all. The disk needs about
# 0.9 MB alone: a 3 MB cap passes one copy and refuses four.
expect_error "compare counts every pane" "4 simulations at once" "needs about" -- compare "$DISK" --out "$TMP/cmp4" --schemes pic,flip,apic,rpic --max-memory 3M
run_cli run "$DISK" --t-end 0.01 --max-memory none --csv "$TMP/none.csv" --quiet
if [ "$RC" -eq 0 ]; then ok "--max-memory none runs"; else nok "--max-memory none" "exit $RC" "$(cat "$ERR")"; fi
# The grid stores only the particles' box: a domain 1e6 x the disk's area runs in the disk's grid.
expect_error "bench --domain-times without --scene" "--domain-times goes with --scene" -- bench --domain-times 5
run_cli bench --scene "$DISK" --frames 1 --domain-times 1e6
if [ "$RC" -eq 0 ] && grep -q "domain: 1e+06 x the scene's; grid arrays: [0-9.]* kB" "$OUT"; then
  ok "bench --domain-times 1e6 runs in kB of grid"
else
  nok "bench --domain-times 1e6" "exit $RC" "$(cat "$OUT" "$ERR")"
fi

# Overlapping objects: a warning naming both and the overlap; the run goes on.
sed -e 's/"objects": \[/"objects": [{"name": "intruder", "shape": {"type": "ball", "center": [0.7, 0.5], "radius": 0.1}, "material": "disk"}, /' "$DISK" >"$TMP/overlap.json"
run_cli run "$TMP/overlap.json" --t-end 0.01 --csv "$TMP/overlap.csv" --quiet
if [ "$RC" -eq 0 ] && grep -q "warning: .*'intruder' and '.*' overlap: [1-9][0-9]* of intruder's [0-9]* particles lie inside" "$ERR"; then
  ok "overlapping objects warned: $(grep -o "overlap: .*" "$ERR" | head -c 120)"
else
  nok "overlapping objects warning" "exit $RC" "$(cat "$ERR")"
fi
run_cli run "$DISK" --t-end 0.01 --csv "$TMP/plain.csv" --quiet
if grep -q "overlap" "$ERR"; then nok "no overlap warning on the shipped disk" "$(cat "$ERR")"; else ok "no overlap warning on the shipped disk"; fi

# What a person expects: list and --version.
run_cli list
if [ "$RC" -eq 0 ] && grep -q "^  rotating-disk  *2D  Jiang et al. 2017, Sec 6.1" "$OUT" &&
  [ "$(grep -c '^  [a-z0-9-]*  *[23]D  ' "$OUT")" -eq "$(ls "$SRC"/assets/scenes/*.json | wc -l)" ] &&
  ! grep -q "does not load\|no description" "$OUT"; then
  ok "list: every shipped scene with its description"
else
  nok "list" "exit $RC" "$(cat "$OUT")" "$(cat "$ERR")"
fi
# Sweeps beside the scenes are listed too (a scenes folder of our own through $APICLAB_SCENES).
mkdir -p "$TMP/assets/scenes" "$TMP/assets/sweeps"
cp "$DISK" "$TMP/assets/scenes/"
printf '{"description": "Which transfer is cheapest. More words."}' >"$TMP/assets/sweeps/cost.json"
OUT="$TMP/stdout" ERR="$TMP/stderr"
(cd "$TMP/cwd" && APICLAB_SCENES="$TMP/assets/scenes" exec "$APICLAB" list) >"$OUT" 2>"$ERR"
if grep -q "^  rotating-disk  " "$OUT" && grep -q "^  cost  *Which transfer is cheapest\.$" "$OUT"; then
  ok "list: sweeps with their descriptions"
else
  nok "list with a sweep" "$(cat "$OUT" "$ERR")"
fi
run_cli --version
if [ "$RC" -eq 0 ] && grep -qE "^apiclab [0-9]+\.[0-9]+\.[0-9]+" "$OUT"; then ok "--version: $(cat "$OUT")"; else nok "--version" "exit $RC" "$(cat "$OUT")"; fi

# Every --help shows defaults and allowed values; compare --help lists only what compare takes.
for sub in run roundtrip bench list render compare gui figures; do
  "$APICLAB" $sub --help >/dev/null 2>&1 || continue  # render, compare, gui, figures: optional builds
  run_cli $sub --help
  # One line per option: CLI11 continues a long description on indented lines.
  missing=$(awk '/^  +-/ { if (o) print o; o = $0; next } /^      +[^ -]/ { o = o " " $0; next } { if (o) print o; o = "" } END { if (o) print o }' "$OUT" |
    grep -vE 'default|allowed|REQUIRED|--help|--set' || true)
  if [ "$RC" -eq 0 ] && [ -z "$missing" ]; then ok "$sub --help: every option shows a default"; else nok "$sub --help" "$missing"; fi
done
if "$APICLAB" compare --help >"$TMP/cmp-help" 2>&1; then
  if grep -qE -- '--scheme[ ,]|--csv' "$TMP/cmp-help"; then
    nok "compare --help lists options compare refuses" "$(grep -E -- '--scheme[ ,]|--csv' "$TMP/cmp-help")"
  else
    ok "compare --help lists only what compare accepts"
  fi
fi

# ---- --help: every numeric option shows its unit, allowed range and default ------------------
run_cli run --help
help_problems=()
[ "$RC" -eq 0 ] || help_problems+=("exit code $RC")
for needle in "dimensionless; allowed: [0, 1]; default: 1]" "materials.*.nu" "allowed: (-1, 0.5)" "time.dt.value" "default: double"; do
  grep -qF -- "$needle" "$OUT" || help_problems+=("help lacks '$needle'")
done
flip_line=$(grep -F -- "--flip-alpha" "$OUT" | head -n 1)
case "$flip_line" in *allowed*default*) ;; *) help_problems+=("--flip-alpha line lacks range/default: $flip_line") ;; esac
if [ ${#help_problems[@]} -eq 0 ]; then ok "run --help shows ranges and defaults"; else nok "run --help" "${help_problems[@]}"; fi

# ---- --help: every scene key of the registries (apiclab docs scene-keys) has its line ---------
"$APICLAB" docs scene-keys >"$TMP/scene-keys" 2>&1
keys=$(grep -oE '^\| `[^`]+` \|' "$TMP/scene-keys" | sed -E 's/^\| `([^`]+)` \|/\1/')
missing=()
for key in $keys; do grep -qF -- "  $key  " "$OUT" || missing+=("$key"); done
if [ -n "$keys" ] && [ ${#missing[@]} -eq 0 ]; then
  ok "run --help: every registry key ($(echo $keys | wc -w)), numeric and word"
else
  nok "run --help lacks registry keys" "${missing[@]:-no keys from docs scene-keys}"
fi

# ---- --help: every scheme key of --scheme has a line with its help (source, equations) --------
scheme_keys=$(grep -oE -- '--scheme TEXT +transfer scheme: [a-z|]+' "$OUT" | sed 's/.*: //' | tr '|' ' ')
scheme_problems=()
[ -n "$scheme_keys" ] || scheme_problems+=("no scheme keys on the --scheme line")
for key in $scheme_keys; do
  grep -qE "^  $key  [A-Z].{20,}" "$OUT" || scheme_problems+=("no help line for scheme '$key'")
done
grep -qE '^  mls  MLS-MPM \(Hu et al\. 2018.*eq 17.*eq 18' "$OUT" || scheme_problems+=("mls line lacks eqs 17, 18")
if [ ${#scheme_problems[@]} -eq 0 ]; then ok "run --help: every scheme key with its source ($scheme_keys)"; else nok "run --help schemes" "${scheme_problems[@]}"; fi

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

# bench --sizes --reference: one row per size with the reference rate and a speed-up above 1
# (the optimised step against the readable one, same state and precision), then the flatness.
run_cli bench --sizes 300,1200 --steps 3 --reference --precision double --threads 1
rows=$(awk '$1 ~ /^[0-9]+$/ && NF == 7 && $7 ~ /x$/ && $7 + 0 > 1 { n++ } END { print n + 0 }' "$OUT")
if [ "$RC" -eq 0 ] && [ "$rows" -eq 2 ] && grep -q '^flatness: slowest / fastest size = ' "$OUT"; then
  ok "bench --sizes 300,1200 --reference: 2 rows with speed-up > 1, flatness"
else
  nok "bench --sizes --reference" "exit $RC, $rows good rows" "$(cat "$OUT")" "$(cat "$ERR")"
fi
# bench --scene: a shipped scene through step() (diagnostics included) over one frame.
run_cli bench --scene rotating-disk --frames 1 --threads 1
last=$(tail -n 1 "$OUT")
if [ "$RC" -eq 0 ] && grep -q '^simulated s per wall s: ' "$OUT" &&
  [[ "$last" =~ ^particle-steps/s:\ [0-9]+$ ]]; then
  ok "bench --scene rotating-disk ends with '$last'"
else
  nok "bench --scene rotating-disk --frames 1" "exit $RC" "$(cat "$OUT")" "$(cat "$ERR")"
fi
expect_error "bench --sizes below 16 particles" "--sizes" "16" -- bench --sizes 3000,10
expect_error "bench --reference with an implicit integrator" "--reference" "symplectic" -- \
  bench --reference --integrator midpoint
expect_error "bench --scene with a block option" "--particles" "--scene" -- \
  bench --scene rotating-disk --particles 1000
expect_error "bench --scene missing" "no-such-scene" -- bench --scene no-such-scene

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
# The two-ball experiment runs under every family (a coarse cell, the balls 0.04 m apart so that
# they touch within the run).
for scene in eol-two-balls eol-two-balls-3d; do
  for method in eol eulerian mpm; do
    run_cli run $scene --set solver.method=$method --set domain.dx=0.05 --set 'objects.0.shape.center.0=0.78' \
      --set 'objects.1.shape.center.0=1.12' --t-end 0.04 --csv "$TMP/$scene-$method.csv" --quiet
    last_t=$(tail -n 1 "$TMP/$scene-$method.csv" 2>/dev/null | cut -d, -f2)
    if [ "$RC" -eq 0 ] && [ "$last_t" = "0.040000000000000001" ]; then
      ok "$scene runs under $method"
    else
      nok "$scene under $method" "exit $RC, last t '$last_t'" "$(head -c 400 "$ERR")"
    fi
  done
done
# An MPM scene's cfl rule (nu = 1, a particle Courant number) does not set EoL's elastic cap:
# rotating-disk under eol blew up at t = 0.05 s with that nu (sim/eol/eol_time_step.hpp).
RCSV="$TMP/disk-eol.csv"
run_cli run rotating-disk --set solver.method=eol --t-end 0.1 --csv "$RCSV" --quiet
last_t=$(tail -n 1 "$RCSV" 2>/dev/null | cut -d, -f2)
if [ "$RC" -eq 0 ] && [ "$last_t" = "0.10000000000000001" ]; then
  ok "rotating-disk under eol takes EoL's stable elastic nu, not cfl's nu = 1"
else
  nok "rotating-disk under eol" "exit $RC, last t '$last_t'" "$(head -c 400 "$ERR")"
fi
# Under the elastic rule time.dt.nu is EoL's own; one it blows up with is named in the message.
expect_blowup "eol-spin blows up at time.dt.nu = 1" run eol-spin --set time.dt.nu=1 --t-end 0.1 --csv "$TMP/spin-nu1.csv" --quiet
if grep -q "time.dt.nu = 1 sets the explicit elastic cap" "$ERR"; then ok "the EoL blow-up names time.dt.nu"
else nok "the EoL blow-up names time.dt.nu" "$(head -c 400 "$ERR")"; fi
expect_error "EoL key in an MPM scene" "'solver.alpha'" "unknown key" -- run rotating-disk --set solver.alpha=0.5
expect_error "MPM key in an EoL scene" "'solver.scheme'" "unknown key" -- run eol-spin --set solver.scheme=apic
expect_error "rest shape outside its EoL grid" "'objects.0.shape'" "solver.grid_extent" -- run eol-spin --set solver.grid_extent=0.3
expect_error "EoL has no particles to dump as csv" "--dump" "eol" "surfaces" -- run eol-spin --t-end 0.01 --dump "$TMP/eoldump" --dump-format csv
expect_error "unwritable --dump of EoL surfaces" "/proc/nope" -- run eol-drop --t-end 0.01 --dump /proc/nope/dir --dump-format vtk,obj

expect_error "unknown dump format" "--dump-format" "xyz" -- run rotating-disk --dump "$TMP/fmt" --dump-format csv,xyz
expect_error "dump format without --dump" "--dump-format" "needs --dump" -- run rotating-disk --dump-format vtk

expect_error "compare --dump csv with a pane without particles" "--dump" "eol" -- compare eol-spin --schemes apic,eol --out "$TMP/cmpdump" --dump "$TMP/cmpdump/d" --dump-format csv

expect_error "compare mls pane with an implicit scene" "--schemes mls" "symplectic" -- compare rotating-disk --schemes apic,mls --out "$TMP/cmpmls"
expect_error "mls with an implicit integrator" "--scheme mls on rotating-disk" "(--integrator symplectic)" -- run rotating-disk --scheme mls
expect_error "polypic with the cubic kernel" "--scheme polypic --kernel cubic" "(--kernel quadratic)" -- run rotating-disk --scheme polypic --kernel cubic
# The same conflict written in a scene file names its key.
expect_error "mls with an implicit integrator in the file" "'solver.scheme'" "symplectic" -- run rotating-disk --set solver.scheme=mls
expect_error "polypic with more modes than 2D has" "'solver.polypic_modes'" "9 modes in 2D" -- run rotating-disk --scheme polypic --set solver.polypic_modes=12

# PolyPIC with its G modes (5 or more in 2D) runs, with one warning line naming the cause and the
# mode count that runs impacts; 4 modes run without it (README, Further transfer schemes).
run_cli run rotating-disk --scheme polypic --t-end 0.01 --csv "$TMP/polypic9.csv"
if [ $RC -eq 0 ] && [ "$(grep -c 'warning: .*polypic with 9 modes keeps the G modes' "$ERR")" = 1 ] &&
  grep -q 'polypic_modes=4 or fewer' "$ERR"; then
  ok "polypic with 9 modes: runs, one warning line"
else
  nok "polypic with 9 modes warning (rc $RC)" "$(cat "$ERR")"
fi
run_cli run rotating-disk --scheme polypic --set solver.polypic_modes=4 --t-end 0.01 --csv "$TMP/polypic4.csv"
if [ $RC -eq 0 ] && ! grep -q 'G modes' "$ERR"; then ok "polypic with 4 modes: no warning"; else
  nok "polypic with 4 modes (rc $RC)" "$(cat "$ERR")"
fi

# Colliders that move: a bad shape, motion or path is one line naming the key (exit 2); the
# shipped paddle runs under eol and mpm.
expect_error "collider of an unknown type" "'colliders.0.type'" "cone" -- run eol-paddle --set colliders.0.type=cone
expect_error "rod of negative radius" "'colliders.0.radius'" "outside the allowed range" -- run eol-paddle --set colliders.0.radius=-1
expect_error "box of zero size" "'colliders.0.size'" "outside the allowed range" -- run eol-paddle --set colliders.0.type=box --set 'colliders.0.size=[0.1,0]'
expect_error "path with times out of order" "'colliders.0.path'" "not after the key before it" -- run eol-paddle --set colliders.0.angular_velocity=0 --set 'colliders.0.path=[[0,0.5,0.4],[0,0.5,0.5]]'
expect_error "path key of the wrong length" "'colliders.0.path'" "[t, x, y] or [t, x, y, degrees]" -- run eol-paddle --set 'colliders.0.path=[[0,0.5]]'
expect_error "path with a spin" "'colliders.0.path'" "not both" -- run eol-paddle --set 'colliders.0.path=[[0,0.5,0.4]]'
for method in eol mpm; do
  run_cli run eol-paddle --set solver.method=$method --t-end 0.05 --csv "$TMP/paddle-$method.csv" --quiet
  if [ $RC -eq 0 ] && [ -s "$TMP/paddle-$method.csv" ]; then ok "eol-paddle runs under $method"; else
    nok "eol-paddle under $method (rc $RC)" "$(head -c 400 "$ERR")"
  fi
done

finish cli_tests
