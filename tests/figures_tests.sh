#!/usr/bin/env bash
# `apiclab figures --out DIR --quick`: files, headers, series, non-blank PNGs; then the full
# Figs 3, 5, 6 and 11, whose numbers README.md states: each is recomputed from the CSVs and
# must appear in README.md as written there, so the README cannot drift from the code.
# Usage: APICLAB=... CHECK=figures_png_check figures_tests.sh OUT_DIR README
set -u
app="${APICLAB:?set APICLAB to the apiclab executable}"
check_png="${CHECK:?set CHECK to figures_png_check}"
out="$1" readme="$2"
export EGL_PLATFORM=surfaceless
rm -rf "$out" "$out-full"
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
# Every registry scheme but the two that blend with a prior particle velocity (flip, asflip).
check "fig11_roundtrip.csv series: every scheme the probe runs, 16..64" "[ \"\$(csv_schemes $out/fig11_roundtrip.csv)\" = 'apic mls pic polypic rpic tpic xpic ' ] && [ \$(grep -c ',64,' $out/fig11_roundtrip.csv) = 7 ]"
check "fig11_roundtrip.png shows PIC and APIC" "'$check_png' $out/fig11_roundtrip.png 600 400 ${color[pic]} ${color[apic]}"
check "Fig 11: APIC's error below PIC's at every resolution" \
  "awk -F, 'NR>1 {e[\$1\",\"\$2]=\$4; r[\$2]=1} END {for (k in r) if (!(e[\"apic,\"k] < e[\"pic,\"k])) exit 1}' $out/fig11_roundtrip.csv"

time_figure fig10_ringing_energy "pic flip apic"
check "fig1_ringing.png: three schemes' frames" "[ -s $out/fig1_ringing.png ] && '$check_png' $out/fig1_ringing.png 1000 1000"

# Fan et al. 2013 Figs 6, 7 and 8 (EoL against the Eulerian baseline), CSVs with dt_limit and
# the grid's nodes and bytes.
eol_header="$time_header,dt_limit,grid_nodes,grid_bytes"
for name in eol_fig6_translation eol_fig7_spin eol_fig8_drop; do
  check "$name.png and $name.csv exist" "[ -s $out/$name.png ] && [ -s $out/$name.csv ]"
  check "$name.csv header" "[ \"\$(head -1 $out/$name.csv)\" = '$eol_header' ]"
  check "$name.csv series: eol eulerian" "[ \"\$(csv_schemes $out/$name.csv)\" = 'eol eulerian ' ]"
  check "$name.png is a chart with both methods" "'$check_png' $out/$name.png 800 350 ${color[apic]} ${color[flip]}"
done
lz_loss() {  # CSV METHOD: percent of L_z lost from t = 0 to the end
  awk -F, -v s="$2" '$1 == s {if (!n++) L0 = $9; L = $9} END {printf "%.6f", 100 * (1 - L / L0)}' "$1"
}
f7=$out/eol_fig7_spin.csv
check "Fig 7 (quick): EoL keeps omega within 0.1 %, Eulerian loses more than 0.4 %" \
  "awk 'BEGIN {l = $(lz_loss $f7 eol); exit !(l < 0.1 && l > -0.1 && $(lz_loss $f7 eulerian) > 0.4)}'"
check "Fig 8: every EoL row names the bound that set dt" \
  "! awk -F, '\$1 == \"eol\" && \$10 !~ /^(advection|elastic|max|frame|fixed)\$/ {bad = 1} END {exit !bad}' $out/eol_fig8_drop.csv"
check "Fig 8: the drop's dt is bound by the elastic limit in some steps" "grep -q '^eol,.*,elastic,' $out/eol_fig8_drop.csv"
# Fig 8's Δt is coloured by its bound: the elastic limit's purple (app/figures/time_figure.cpp).
check "Fig 8: the Δt curve is drawn in the elastic limit's colour" "'$check_png' $out/eol_fig8_drop.png 800 350 7b3294"
# Fig 6: the grids each solver allocated (EolSimulation::grid_bytes): nodes the same in every
# row, bytes peaking once the work arrays are allocated; README quotes them (the quick run's
# grids are the full run's: they do not change in time).
f6e=$out/eol_fig6_translation.csv
col() { awk -F, -v s="$2" -v c="$3" '$1 == s {print $c}' "$1" | sort -u | tr '\n' ' '; }
check "Fig 6: each method's grid keeps its nodes in every row" \
  "[ \$(col $f6e eol 11 | wc -w) = 1 ] && [ \$(col $f6e eulerian 11 | wc -w) = 1 ]"
peak() { awk -F, -v s="$2" -v c="$3" '$1 == s && $c > m {m = $c} END {print m}' "$1"; }
n_eol=$(col $f6e eol 11 | tr -d ' ') n_eul=$(col $f6e eulerian 11 | tr -d ' ')
b_eol=$(peak $f6e eol 12) b_eul=$(peak $f6e eulerian 12)
check "Fig 6: EoL's grid is smaller than the world grid" "[ $n_eol -lt $n_eul ] && [ $b_eol -lt $b_eul ]"
says6() { local text6; text6=$(tr '\n' ' ' <"$readme" | tr -s ' ')
  if [[ "$text6" == *"$1"* ]]; then ok "README says: $1"; else fail "README does not say: $1"; fi; }
says6 "EoL's grid has $n_eol nodes ($(awk "BEGIN {printf \"%.1f\", $b_eol / 1024}") KiB), the Eulerian baseline's $n_eul ($(awk "BEGIN {printf \"%.0f\", $b_eul / 1024}") KiB): $(awk "BEGIN {printf \"%.0f\", $n_eul / $n_eol}")× the nodes, $(awk "BEGIN {printf \"%.0f\", $b_eul / $b_eol}")× the memory"

# The two-ring energy table (issue 15): one row per scheme; PIC lowest, FLIP highest, every
# other scheme that ran to the end between (the claim of issue 15, checked on the CSV). A run
# that blew up (PolyPIC with all 9 modes does, README "Further transfer schemes") has its
# failure in the last column and is left out of the order; pic, flip, apic, rpic, mls and tpic
# must have run to the end.
# XPIC(2) and ASFLIP (α = β = 1) are left out of the order: measured, XPIC(2) ends below PIC
# (241.8 against 359.1 J at t = 0.01 s) and ASFLIP above FLIP at t = 0.005 s (2108 against
# 1848 J, most of it elastic), which issue 15's expectation does not foresee; README
# "The two-ring energy table" explains both (the table measures the rebound, and ASFLIP's
# position correction stops it), tests/test_scheme_energy_mechanism.cpp measures why.
energy_order() {  # CSV: exit 0 when pic < every affine scheme < flip
  awk -F, 'NR > 1 {if ($7 == "") e[$1] = $3; else failed[$1] = 1}
    END {split("pic flip apic rpic mls tpic", need, " ")
      for (k in need) if (!(need[k] in e)) exit 1
      for (s in e) if (s != "pic" && s != "flip" && s != "xpic" && s != "asflip" &&
                       !(e["pic"] < e[s] && e[s] < e["flip"])) exit 1}' "$1"
}
se=$out/scheme_energy.csv
check "scheme_energy.png and .csv exist" "[ -s $out/scheme_energy.png ] && [ -s $se ]"
check "scheme_energy.csv header" "[ \"\$(head -1 $se)\" = 'scheme,t,total_energy,kinetic,potential,initial_total,failure' ]"
has_schemes() {  # CSV SCHEME...: a row for each
  local csv=$1 s
  shift
  for s in "$@"; do grep -q "^$s," "$csv" || return 1; done
}
check "scheme_energy.csv: every scheme (pic flip apic rpic mls tpic polypic at least)" \
  "has_schemes $se pic flip apic rpic mls tpic polypic"
check "scheme_energy (quick): PIC lowest, FLIP highest, the affine schemes between" "energy_order $se"
check "scheme_energy.png shows the schemes' colours" "'$check_png' $out/scheme_energy.png 800 350 ${color[pic]} ${color[flip]} ${color[apic]}"

# README.md's numbers against the full runs.
full="$out-full"
start=$SECONDS
"$app" figures --out "$full" --only 3,5,6,11,scheme-energy 2>"$full.log"
status=$?
check "figures --only 3,5,6,11,scheme-energy exits 0" "[ $status = 0 ]"
echo "figures --only 3,5,6,11,scheme-energy took $((SECONDS - start)) s"
text=$(tr '\n' ' ' <"$readme" | tr -s ' ')
says() {  # PHRASE: README.md says it, word for word (line breaks as spaces)
  if [[ "$text" == *"$1"* ]]; then ok "README says: $1"; else fail "README does not say: $1"; fi
}
sup() {  # 10-based exponent in superscript digits, − for minus
  local s=$1 out="" c
  declare -A map=([-]=⁻ [0]=⁰ [1]=¹ [2]=² [3]=³ [4]=⁴ [5]=⁵ [6]=⁶ [7]=⁷ [8]=⁸ [9]=⁹)
  for ((k = 0; k < ${#s}; k++)); do c=${s:k:1}; out+=${map[$c]}; done
  echo "$out"
}
minus() { echo "${1/#-/−}"; }  # README writes a real minus sign
# Per scheme of a time-figure CSV: first and last L and E, and the largest |L - L0|.
stats() {  # CSV SCHEME FIELD: FIELD of L0 L E0 E maxdL
  awk -F, -v s="$2" -v f="$3" '$1 == s {if (!n++) {L0 = $9; E0 = $8} L = $9; E = $8
    d = $9 - L0; if (d < 0) d = -d; if (d > m) m = d}
    END {v["L0"] = L0; v["L"] = L; v["E0"] = E0; v["E"] = E; v["maxdL"] = m; printf "%.17g", v[f]}' "$1"
}
calc() { awk "BEGIN {printf \"$1\", $2}"; }
pow10() { calc "%d" "(log($1) / log(10) < 0 ? int(log($1) / log(10) - 0.5) : int(log($1) / log(10) + 0.5))"; }

f3=$full/fig3_rotating_disk.csv
says "APIC starts $(calc %.1f "100 * ($(stats $f3 apic L0) / $(stats $f3 pic L0) - 1)")% higher"
apic_rel=$(calc %.17g "$(stats $f3 apic maxdL) / $(stats $f3 apic L0)")
e=$(pow10 "$apic_rel")
[ "$(calc %.0f "$apic_rel / 10^$e")" = 10 ] && e=$((e + 1))
mant=$(calc %.0f "$apic_rel / 10^$e")
says "keeps L to ${mant}·10$(sup "$e") relative over 2 s (RPIC too)"
check "Fig 3: RPIC keeps L as well as APIC's bound" \
  "awk 'BEGIN {exit !($(stats $f3 rpic maxdL) / $(stats $f3 rpic L0) <= ($mant + 0.5) * 10^$e)}'"
says "PIC loses $(calc %.0f "100 * (1 - $(stats $f3 pic L) / $(stats $f3 pic L0))")% of L and $(calc %.0f "100 * (1 - $(stats $f3 pic E) / $(stats $f3 pic E0))")% of E"
says "FLIP drifts down $(calc %.1f "100 * (1 - $(stats $f3 flip L) / $(stats $f3 flip L0))")%"

f5=$full/fig5_skew_impact.csv
L0=$(calc %.1f "$(stats $f5 apic L0)")
check "Fig 5: APIC and RPIC end at L0 = $L0" \
  "[ $(calc %.1f "$(stats $f5 apic L)") = $L0 ] && [ $(calc %.1f "$(stats $f5 rpic L)") = $L0 ]"
says "APIC and RPIC keep L = $L0 exactly"
says "FLIP ends at $(minus "$(calc %.1f "$(stats $f5 flip L)")"), PIC at $(minus "$(calc %.1f "$(stats $f5 pic L)")")"
says "PIC dissipates most ($(calc %.0f "100 * (1 - $(stats $f5 pic E) / $(stats $f5 pic E0))")%), APIC keeps $(calc %.0f "100 * $(stats $f5 apic E) / $(stats $f5 apic E0)")%, FLIP $(calc %.0f "100 * $(stats $f5 flip E) / $(stats $f5 flip E0)")%"

f6=$full/fig6_ring_collision.csv
says "APIC keeps it to 10$(sup "$(pow10 "$(stats $f6 apic maxdL)")"), FLIP strays to 10$(sup "$(pow10 "$(stats $f6 flip maxdL)")")"

f11=$full/fig11_roundtrip.csv
err() { awk -F, -v s="$2" -v r="$3" '$1 == s && $2 == r {printf "%.17g", $4}' "$1"; }
ratio() { calc %.0f "$(err $f11 pic "$1") / $(err $f11 apic "$1")"; }
slope() {  # least-squares slope of log error against log dx
  awk -F, -v s="$1" '$1 == s {x = log($3); y = log($4); n++; sx += x; sy += y; sxx += x * x; sxy += x * y}
    END {printf "%.1f", (n * sxy - sx * sy) / (n * sxx - sx * sx)}' $f11
}
says "APIC is $(ratio 16)× below PIC at 16² and $(ratio 256)× at 256²; APIC's slope is $(slope apic)"
says "PIC's $(slope pic) over the range"
says "APIC's error is $(ratio 16)–$(ratio 128)× below PIC's over 16²…128²"

check "scheme_energy (full, t = 0.01 s): PIC lowest, FLIP highest, the affine schemes between" \
  "energy_order $full/scheme_energy.csv"
while IFS= read -r row; do  # the Markdown table the figure printed, row by row, in README.md
  says "$row"
done < <(grep '^| ' "$full.log")

echo "$passed passed, $failed failed"
[ "$failed" = 0 ]
