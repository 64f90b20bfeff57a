#!/usr/bin/env bash
# `apiclab figures --out DIR --quick`: files, headers, series, non-blank PNGs.
# Usage: APICLAB=... CHECK=figures_png_check figures_tests.sh OUT_DIR SCENES_DIR
set -u
app="${APICLAB:?set APICLAB to the apiclab executable}"
check_png="${CHECK:?set CHECK to figures_png_check}"
out="$1" scenes="$2"
export EGL_PLATFORM=surfaceless
rm -rf "$out"
passed=0 failed=0
ok() { passed=$((passed + 1)); echo "ok: $1"; }
fail() { failed=$((failed + 1)); echo "FAILED: $1"; }
check() { if eval "$2"; then ok "$1"; else fail "$1"; fi; }

start=$SECONDS
"$app" figures --out "$out" --quick 2>"$out.log"
status=$?
cat "$out.log"
check "figures --quick exits 0" "[ $status = 0 ]"
echo "figures --quick took $((SECONDS - start)) s"

# Colors of the schemes' lines: render/palette.hpp (kSchemeLooks, kPalette), hex.
declare -A color=([pic]=0072b2 [flip]=d55e00 [apic]=009e73 [rpic]=cc79a7)
time_header='scheme,step,t,dt,kinetic,kinetic_grid,potential,total_energy,angular_momentum'
csv_schemes() { tail -n +2 "$1" | cut -d, -f1 | sort -u | tr '\n' ' '; }

time_figure() {  # NAME "schemes"
  local name=$1 schemes=$2 cols=()
  check "$name.png and $name.csv exist" "[ -s $out/$name.png ] && [ -s $out/$name.csv ]"
  check "$name.csv header" "[ \"\$(head -1 $out/$name.csv)\" = '$time_header' ]"
  local want
  want=$(echo $schemes | tr ' ' '\n' | sort | tr '\n' ' ')
  check "$name.csv series: $schemes" "[ \"\$(csv_schemes $out/$name.csv)\" = '$want' ]"
  for s in $schemes; do
    check "$name.csv: $s has rows from t = 0 on" "[ \$(grep -c '^$s,' $out/$name.csv) -ge 3 ] && grep -q '^$s,0,0,' $out/$name.csv"
    cols+=("${color[$s]}")
  done
  check "$name.png is a chart with every series" "'$check_png' $out/$name.png 800 350 ${cols[*]}"
}

time_figure fig3_rotating_disk "pic flip apic rpic"
time_figure fig4_cylinder_rebound "pic flip apic rpic"
time_figure fig5_skew_impact "pic flip apic rpic"
time_figure fig6_ring_collision "pic flip apic rpic"

check "fig11_roundtrip.png and .csv exist" "[ -s $out/fig11_roundtrip.png ] && [ -s $out/fig11_roundtrip.csv ]"
check "fig11_roundtrip.csv header" "[ \"\$(head -1 $out/fig11_roundtrip.csv)\" = 'scheme,resolution,dx,l2_error' ]"
check "fig11_roundtrip.csv series: pic apic, 16..64" "[ \"\$(csv_schemes $out/fig11_roundtrip.csv)\" = 'apic pic ' ] && [ \$(grep -c ',64,' $out/fig11_roundtrip.csv) = 2 ]"
check "fig11_roundtrip.png shows PIC and APIC" "'$check_png' $out/fig11_roundtrip.png 600 400 ${color[pic]} ${color[apic]}"
check "Fig 11: APIC's error below PIC's at every resolution" \
  "awk -F, 'NR>1 {e[\$1\",\"\$2]=\$4; r[\$2]=1} END {for (k in r) if (!(e[\"apic,\"k] < e[\"pic,\"k])) exit 1}' $out/fig11_roundtrip.csv"

if [ -f "$scenes/ringing.json" ]; then
  time_figure fig10_ringing_energy "pic flip apic"
  check "fig1_ringing.png: three schemes' frames" "[ -s $out/fig1_ringing.png ] && '$check_png' $out/fig1_ringing.png 1000 1000"
else
  check "without the ringing scene, Figs 1 and 10 are skipped with one line" \
    "grep -q 'skipping Fig 1 and Fig 10' $out.log && [ ! -e $out/fig1_ringing.png ]"
fi

echo "$passed passed, $failed failed"
[ "$failed" = 0 ]
