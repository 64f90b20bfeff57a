#!/usr/bin/env bash
# `apiclab figures --out DIR --quick`: files, headers, series, non-blank PNGs; then the full
# Figs 3, 5, 6, 11 and the two-ring energy table. Every number the docs state about them lives in
# a data file (docs/data/figures.csv, docs/data/two-ring-energy.csv; docs/paper-figures.md and
# docs/transfer-schemes.md render them with tools/gen-docs.sh): each is recomputed here from the
# figures' CSVs, formatted as the file writes it, and must equal the file's value, so the data
# cannot drift from the code. A row of figures.csv that nothing here recomputes fails too.
# Usage: APICLAB=... CHECK=figures_png_check figures_tests.sh OUT_DIR [DATA_DIR] [quick]
#   DATA_DIR: the folder of figures.csv and two-ring-energy.csv (default: docs/data beside tests/)
#   quick: the --quick run's checks alone (the default tier); without it, the full runs and the
#   check that every row of figures.csv is recomputed too (the full tier)
set -u
app="${APICLAB:?set APICLAB to the apiclab executable}"
check_png="${CHECK:?set CHECK to figures_png_check}"
root="$(cd "$(dirname "$0")/../.." && pwd)"
out="$1" data="${2:-$root/docs/data}" part="${3:-all}"
export EGL_PLATFORM=surfaceless
rm -rf "$out" "$out-full"
passed=0 failed=0
ok() { passed=$((passed + 1)); echo "ok: $1"; }
fail() { failed=$((failed + 1)); echo "FAILED: $1"; }
check() { if eval "$2"; then ok "$1"; else fail "$1"; fi; }

# docs/data/figures.csv: figure,key,value,unit,quantity,paper_claim (no commas inside a field).
figures_csv=$data/figures.csv two_ring_csv=$data/two-ring-energy.csv
declare -A want=() seen=()
if [ -s "$figures_csv" ] && [ "$(head -1 "$figures_csv")" = 'figure,key,value,unit,quantity,paper_claim' ] &&
   awk -F, 'NR > 1 && NF != 6 {exit 1}' "$figures_csv"; then
  ok "$figures_csv: header and six fields a row"
  while IFS=, read -r _ key value _; do want[$key]=$value; done < <(tail -n +2 "$figures_csv")
else
  fail "$figures_csv: missing, or not 'figure,key,value,unit,quantity,paper_claim' with six fields a row"
fi
is() {  # KEY VALUE: figures.csv gives KEY the value the code gives now, character for character
  seen[$1]=1
  if [ -z "${want[$1]+x}" ]; then fail "figures.csv has no row $1 (the code gives '$2')"
  elif [ "${want[$1]}" = "$2" ]; then ok "figures.csv: $1 = $2"
  else fail "figures.csv: $1 = ${want[$1]}, the code gives '$2'"; fi
}

start=$SECONDS
"$app" figures --out "$out" --quick 2>"$out.log"
status=$?
cat "$out.log"
check "figures --quick exits 0" "[ $status = 0 ]"
echo "figures --quick took $((SECONDS - start)) s"

# Colors of the schemes' lines: render/palette.hpp (kPalette, the slot each sim/mpm/schemes/ file names), hex.
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

# Fan et al. 2013 Figs 6, 7, 8 and 9 (EoL against the Eulerian baseline), CSVs with dt_limit,
# the grid's nodes and bytes, and the pairs of objects in contact.
eol_header="$time_header,dt_limit,grid_nodes,grid_bytes,contact_pairs"
for name in eol_fig6_translation eol_fig7_spin eol_fig9_two_balls; do
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
# Figs 8 and 9: the two balls under implicit elasticity. Fig 8: E never above E0 (the contact
# rows held inside the backward Euler solve; projected after it, E rose to 2.3 E0); during
# contact (contact_pairs > 0) Δt is at most 0.1 of its value after contact, and it is back at
# 1/fps (24 fps) within 0.25 s of the balls parting. Fig 9: the median of Δt_EoL / Δt_Eulerian at
# the same times (every 5 ms, in flight in the quick run: the baseline's solves fail in contact
# under implicit elasticity, docs/eol.md) is at least 5 (the paper: about 10).
f8=$out/eol_fig8_two_balls.csv f9=$out/eol_fig9_two_balls.csv
check "eol_fig8_two_balls.csv: header, EoL only" "[ \"\$(head -1 $f8)\" = '$eol_header' ] && [ \"\$(csv_schemes $f8)\" = 'eol ' ]"
check "Fig 8: every row names the bound that set dt" \
  "! awk -F, 'NR > 1 && \$2 > 0 && \$10 !~ /^(advection|elastic|contact|max|frame|fixed)\$/ {bad = 1} END {exit !bad}' $f8"
check "Fig 8: the energy never above its start" \
  "awk -F, 'NR == 2 {e0 = \$8} NR > 2 && \$8 > e0 * (1 + 1e-9) {bad = 1} END {exit bad}' $f8"
fig8=$(awk -F, 'NR > 1 && $13 > 0 {if (!first) first = $3; last = $3; if ($4 > during) during = $4}
  NR > 1 && last && $13 == 0 && $3 > last {if ($4 > after) after = $4; if (!back && $4 >= 0.999 / 24) back = $3}
  END {printf "%s %s %s %s %s", first, last, during, after, back}' "$f8")
read -r c_first c_last c_during c_after c_back <<<"$fig8"
echo "Fig 8: contact from t = $c_first to $c_last s, dt at most $c_during there, $c_after after; back at 1/24 s at t = $c_back"
check "Fig 8: the balls touch" "[ -n \"$c_first\" ]"
check "Fig 8: dt in contact at most 0.1 of its value after contact" \
  "awk 'BEGIN {exit !($c_during > 0 && $c_during <= 0.1 * $c_after)}'"
check "Fig 8: dt back at 1/fps within 0.25 s of the balls parting" \
  "awk 'BEGIN {exit !(\"$c_back\" != \"\" && $c_back - $c_last <= 0.25)}'"
check "Fig 8: the contact bound and the frame time are drawn in their colours" \
  "'$check_png' $out/eol_fig8_two_balls.png 800 350 c81e3c 1e1e1e"
dt_ratio=$(awk -F, 'NR > 1 && $2 > 0 {n = ++k[$1]; t[$1, n] = $3; d[$1, n] = $4; last[$1] = $3}
  function dt_at(m, s,   i) {for (i = 1; i <= k[m]; i++) if (t[m, i] >= s) return d[m, i]; return d[m, k[m]]}
  END {n = 0; end = last["eol"] < last["eulerian"] ? last["eol"] : last["eulerian"]
       for (s = 0.0025; s < end; s += 0.005) r[++n] = dt_at("eol", s) / dt_at("eulerian", s)
       for (i = 2; i <= n; i++) for (j = i; j > 1 && r[j - 1] > r[j]; j--) {x = r[j]; r[j] = r[j - 1]; r[j - 1] = x}
       printf "%.2f", n % 2 ? r[(n + 1) / 2] : (r[n / 2] + r[n / 2 + 1]) / 2}' "$f9")
starts=$(awk -F, 'NR > 1 && $13 > 0 && !($1 in s) {s[$1] = $3} END {printf "%s %s", s["eol"], s["eulerian"]}' "$f9")
echo "Fig 9: median dt_EoL / dt_Eulerian $dt_ratio; contact starts at t = ${starts% *} s (EoL), ${starts#* } s (Eulerian)"
check "Fig 9: median dt_EoL / dt_Eulerian at least 5" "awk 'BEGIN {exit !($dt_ratio >= 5)}'"
# Fig 6: the grids each solver allocated (EolSimulation::grid_bytes): nodes the same in every
# row, bytes peaking once the work arrays are allocated; figures.csv holds them (the quick run's
# grids are the full run's: they do not change in time).
f6e=$out/eol_fig6_translation.csv
col() { awk -F, -v s="$2" -v c="$3" '$1 == s {print $c}' "$1" | sort -u | tr '\n' ' '; }
check "Fig 6: each method's grid keeps its nodes in every row" \
  "[ \$(col $f6e eol 11 | wc -w) = 1 ] && [ \$(col $f6e eulerian 11 | wc -w) = 1 ]"
peak() { awk -F, -v s="$2" -v c="$3" '$1 == s && $c > m {m = $c} END {print m}' "$1"; }
n_eol=$(col $f6e eol 11 | tr -d ' ') n_eul=$(col $f6e eulerian 11 | tr -d ' ')
b_eol=$(peak $f6e eol 12) b_eul=$(peak $f6e eulerian 12)
check "Fig 6: EoL's grid is smaller than the world grid" "[ $n_eol -lt $n_eul ] && [ $b_eol -lt $b_eul ]"
kib() { awk "BEGIN {printf \"$1\", $2 / 1024}"; }
is eol6.eol_nodes "$n_eol"
is eol6.eol_kib "$(kib %.1f "$b_eol")"
is eol6.eulerian_nodes "$n_eul"
is eol6.eulerian_kib "$(kib %.0f "$b_eul")"
is eol6.node_ratio "$(awk "BEGIN {printf \"%.0f\", $n_eul / $n_eol}")"
is eol6.memory_ratio "$(awk "BEGIN {printf \"%.0f\", $b_eul / $b_eol}")"

# The two-ring energy table: one row per scheme; PIC lowest, FLIP highest, every other scheme
# that ran to the end between, checked on the CSV. A run that blew up (PolyPIC with all 9 modes
# does) has its failure in the last column and is left out of the order; pic, flip, apic, rpic,
# mls and tpic must have run to the end. XPIC(2) (below PIC at t = 0.01 s) and ASFLIP with
# α = β = 1 (above FLIP at t = 0.005 s) are left out of the order: the table measures the
# rebound, which XPIC(2)'s kept vibration slows and ASFLIP's position correction stops
# (docs/transfer-schemes.md, "The two-ring energy table"; tests/mpm/test_scheme_energy_mechanism.cpp).
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

# The conservation ledger's chart (Jiang et al. 2017, Sec 5 stage by stage): the rotating disk
# under symplectic Euler, each stage's ΔL_z per step over L_z(0) (docs/outputs.md, Conservation ledger).
# figures.csv holds the quick run's numbers: APIC's and RPIC's transfers and PIC's P2G below
# 1e-12 of L_z, PIC's and FLIP's G2P to one significant digit.
fl=$out/ledger_rotating_disk.csv
check "ledger_rotating_disk.png and .csv exist" "[ -s $out/ledger_rotating_disk.png ] && [ -s $fl ]"
check "ledger_rotating_disk.csv header" \
  "[ \"\$(head -1 $fl)\" = '$time_header,p2g_dLz,forces_dLz,walls_dLz,colliders_dLz,g2p_dLz,move_dLz' ]"
check "ledger_rotating_disk.csv series: pic flip apic rpic" "[ \"\$(csv_schemes $fl)\" = 'apic flip pic rpic ' ]"
check "ledger_rotating_disk.png is a chart with every series" \
  "'$check_png' $out/ledger_rotating_disk.png 800 350 ${color[pic]} ${color[flip]} ${color[apic]}"
stage_dL() {  # CSV "SCHEME..." COLUMN: the largest |stage ΔL_z / L_z(0)| over the schemes' steps
  awk -F, -v s=" $2 " -v c="$3" 'NR > 1 && !($1 in l0) {l0[$1] = $9}
    NR > 1 && $2 > 0 && index(s, " " $1 " ") {
    r = $c / l0[$1]; if (r < 0) r = -r; if (r > m) m = r} END {printf "%.17g", m}' "$1"
}
round_off_or() {  # X: "<1e-12" when below, else X to one significant digit (3e-5)
  if awk "BEGIN {exit !($1 < 1e-12)}"; then echo "<1e-12"
  else awk "BEGIN {printf \"%.0e\", $1}" | sed 's/e-0*/e-/; s/e+0*/e/'; fi
}
transfers=$(awk "BEGIN {a = $(stage_dL $fl "apic rpic" 10); b = $(stage_dL $fl "apic rpic" 14); printf \"%.17g\", (a > b ? a : b)}")
is ledger.apic_rpic_transfers "$(round_off_or "$transfers")"
is ledger.pic_p2g "$(round_off_or "$(stage_dL $fl pic 10)")"
is ledger.pic_g2p "$(round_off_or "$(stage_dL $fl pic 14)")"
is ledger.flip_g2p "$(round_off_or "$(stage_dL $fl flip 14)")"

if [ "$part" = quick ]; then
  echo "$passed passed, $failed failed (the --quick run's checks; the full runs are the full tier's)"
  [ "$failed" = 0 ]
  exit
fi

# The numbers of docs/data against the full runs.
full="$out-full"
start=$SECONDS
"$app" figures --out "$full" --only 3,5,6,11,scheme-energy 2>"$full.log"
status=$?
check "figures --only 3,5,6,11,scheme-energy exits 0" "[ $status = 0 ]"
echo "figures --only 3,5,6,11,scheme-energy took $((SECONDS - start)) s"
# Per scheme of a time-figure CSV: first and last L and E, and the largest |L - L0|.
stats() {  # CSV SCHEME FIELD: FIELD of L0 L E0 E maxdL
  awk -F, -v s="$2" -v f="$3" '$1 == s {if (!n++) {L0 = $9; E0 = $8} L = $9; E = $8
    d = $9 - L0; if (d < 0) d = -d; if (d > m) m = d}
    END {v["L0"] = L0; v["L"] = L; v["E0"] = E0; v["E"] = E; v["maxdL"] = m; printf "%.17g", v[f]}' "$1"
}
calc() { awk "BEGIN {printf \"$1\", $2}"; }
pow10() { calc "%d" "(log($1) / log(10) < 0 ? int(log($1) / log(10) - 0.5) : int(log($1) / log(10) + 0.5))"; }
sig1() {  # X > 0 to one significant digit, as MeE: 2e-9
  local e m
  e=$(pow10 "$1")
  [ "$(calc %.0f "$1 / 10^$e")" = 10 ] && e=$((e + 1))
  m=$(calc %.0f "$1 / 10^$e")
  [ "$m" = 0 ] && { e=$((e - 1)); m=$(calc %.0f "$1 / 10^$e"); }
  echo "${m}e$e"
}
sci() { calc "%.1e" "$1" | sed 's/e+0*/e/; s/e-0*/e-/'; }  # 2.6e-05 -> 2.6e-5

f3=$full/fig3_rotating_disk.csv
is fig3.apic_L0_above_pic "$(calc %.1f "100 * ($(stats $f3 apic L0) / $(stats $f3 pic L0) - 1)")"
apic_rel=$(calc %.17g "$(stats $f3 apic maxdL) / $(stats $f3 apic L0)")
bound=$(sig1 "$apic_rel")
is fig3.apic_max_rel_dL "$bound"
check "Fig 3: RPIC keeps L as well as APIC's bound ($bound)" \
  "awk 'BEGIN {exit !($(stats $f3 rpic maxdL) / $(stats $f3 rpic L0) <= (${bound%e*} + 0.5) * 10^${bound#*e})}'"
is fig3.pic_L_lost "$(calc %.0f "100 * (1 - $(stats $f3 pic L) / $(stats $f3 pic L0))")"
is fig3.pic_E_lost "$(calc %.0f "100 * (1 - $(stats $f3 pic E) / $(stats $f3 pic E0))")"
is fig3.flip_L_lost "$(calc %.1f "100 * (1 - $(stats $f3 flip L) / $(stats $f3 flip L0))")"

f5=$full/fig5_skew_impact.csv
L0=$(calc %.1f "$(stats $f5 apic L0)")
check "Fig 5: APIC and RPIC end at L0 = $L0" \
  "[ $(calc %.1f "$(stats $f5 apic L)") = $L0 ] && [ $(calc %.1f "$(stats $f5 rpic L)") = $L0 ]"
is fig5.L0 "$L0"
is fig5.flip_L_end "$(calc %.1f "$(stats $f5 flip L)")"
is fig5.pic_L_end "$(calc %.1f "$(stats $f5 pic L)")"
is fig5.pic_E_lost "$(calc %.0f "100 * (1 - $(stats $f5 pic E) / $(stats $f5 pic E0))")"
is fig5.apic_E_kept "$(calc %.0f "100 * $(stats $f5 apic E) / $(stats $f5 apic E0)")"
is fig5.flip_E_kept "$(calc %.0f "100 * $(stats $f5 flip E) / $(stats $f5 flip E0)")"

f6=$full/fig6_ring_collision.csv
is fig6.apic_max_dL "1e$(pow10 "$(stats $f6 apic maxdL)")"
is fig6.flip_max_dL "1e$(pow10 "$(stats $f6 flip maxdL)")"

f11=$full/fig11_roundtrip.csv
err() { awk -F, -v s="$2" -v r="$3" '$1 == s && $2 == r {printf "%.17g", $4}' "$1"; }
ratio() { calc %.0f "$(err $f11 pic "$1") / $(err $f11 apic "$1")"; }
slope() {  # least-squares slope of log error against log dx
  awk -F, -v s="$1" '$1 == s {x = log($3); y = log($4); n++; sx += x; sy += y; sxx += x * x; sxy += x * y}
    END {printf "%.1f", (n * sxy - sx * sy) / (n * sxx - sx * sx)}' $f11
}
is fig11.ratio_16 "$(ratio 16)"
is fig11.ratio_128 "$(ratio 128)"
is fig11.ratio_256 "$(ratio 256)"
is fig11.apic_slope "$(slope apic)"
is fig11.pic_slope "$(slope pic)"
is fig11.tpic_over_apic_256 "$(calc %.1f "$(err $f11 tpic 256) / $(err $f11 apic 256)")"
is fig11.tpic_256 "$(sci "$(err $f11 tpic 256)")"
is fig11.polypic_max "$(sig1 "$(awk -F, '$1 == "polypic" && $4 > m {m = $4} END {printf "%.17g", m}' $f11)")"
is fig11.xpic_over_pic_16 "$(calc %.2f "$(err $f11 xpic 16) / $(err $f11 pic 16)")"
is fig11.xpic_over_pic_256 "$(calc %.2f "$(err $f11 xpic 256) / $(err $f11 pic 256)")"
is fig11.xpic_slope "$(slope xpic)"
same_errors() {  # A B: the two schemes' errors equal to the last digit at every resolution
  [ "$(awk -F, -v s="$1" '$1 == s {print $2, $4}' $f11)" = "$(awk -F, -v s="$2" '$1 == s {print $2, $4}' $f11)" ] &&
    [ -n "$(awk -F, -v s="$1" '$1 == s' $f11)" ]
}
check "Fig 11: MLS-MPM's errors are APIC's to the last digit (the same transfers)" "same_errors mls apic"
close_errors() {  # A B: the two schemes' errors within 1e-12 relative at every resolution
  awk -F, -v a="$1" -v b="$2" '$1 == a {e[$2] = $4} $1 == b {f[$2] = $4}
    END {for (r in f) {n++; if (!(r in e)) exit 1; d = e[r] - f[r]; if (d < 0) d = -d; if (d > 1e-12 * f[r]) exit 1}
         exit !n}' $f11
}
check "Fig 11: RPIC's errors are PIC's to round-off (the field is curl-free)" "close_errors rpic pic"

se_full=$full/scheme_energy.csv
check "scheme_energy (full, t = 0.01 s): PIC lowest, FLIP highest, the affine schemes between" \
  "energy_order $se_full"
is scheme_energy.initial_total "$(awk -F, 'NR == 2 {printf "%.1f", $6}' "$se_full")"
# The table the figure printed, line for line, against the one tools/render-two-ring-energy.sh
# renders from two-ring-energy.csv (the table of docs/transfer-schemes.md); and its schemes.
check "two-ring-energy.csv schemes are scheme_energy.csv's, in order" \
  "[ \"\$(tail -n +2 '$two_ring_csv' | cut -d, -f1)\" = \"\$(tail -n +2 '$se_full' | cut -d, -f1)\" ]"
if table_diff=$(diff <(grep '^| ' "$full.log") <(bash "$root/tools/render-two-ring-energy.sh" "$two_ring_csv") 2>&1); then
  ok "two-ring-energy.csv renders the table the figure printed"
else
  fail "two-ring-energy.csv does not render the table the figure printed (< printed, > rendered):"
  echo "$table_diff"
fi

for key in "${!want[@]}"; do
  [ -n "${seen[$key]+x}" ] || fail "figures.csv row $key: nothing here recomputes it"
done

echo "$passed passed, $failed failed"
[ "$failed" = 0 ]
