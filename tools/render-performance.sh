#!/usr/bin/env bash
# Renders the performance ledger as Markdown tables, one per machine and build: for each cpu and
# build, the newest row (latest date; on a tie, the later line) of each cell that holds a number,
# a cell being scene, dim, precision, threads, scheme, kernel, integrator and particle count.
#   tools/render-performance.sh [LEDGER]      default: docs/data/performance-ledger.csv
# (awk, not C++: it reads a CSV of plain cells, and the docs check runs it without a build.)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
ledger="${1:-$root/docs/data/performance-ledger.csv}"
header="date,commit,cpu,isa,build,method,scene,dim,precision,threads,scheme,kernel,integrator,particles,steps,particle_steps_per_s,wall_s,sim_s_per_wall_s,note"
[ -r "$ledger" ] || { echo "render-performance: cannot read $ledger" >&2; exit 2; }
[ "$(head -n 1 "$ledger" | tr -d '\r')" = "$header" ] ||
  { echo "render-performance: $ledger does not start with the ledger's header" >&2; exit 2; }

# Pass 1: the newest row of each cell, each printed with a sort key in front (tab-separated).
awk -F, -v OFS='\t' '
  NR == 1 || NF != 19 || ($16 == "" && $17 == "" && $18 == "") { next }
  {
    gsub(/\r/, "")
    cell = $3 SUBSEP $5 SUBSEP $7 SUBSEP $8 SUBSEP $9 SUBSEP $10 SUBSEP $11 SUBSEP $12 SUBSEP $13 SUBSEP $14
    if (!(cell in date) || $1 >= date[cell]) { date[cell] = $1; row[cell] = $0 }
  }
  END {
    for (cell in row) {
      split(row[cell], f, ",")
      order = (f[7] == "bench" ? 0 : 1) OFS f[7] OFS f[8] OFS (f[9] == "float" ? 0 : 1)
      print f[3], f[5], order, f[10] + 0, f[11] " " f[12] " " f[13], f[14] + 0, row[cell]
    }
  }' "$ledger" |
  LC_ALL=C sort -t $'\t' -k1,1 -k2,2 -k3,3n -k4,4 -k5,5n -k6,6n -k7,7n -k8,8 -k9,9n |
  cut -f 10 |
  # Pass 2: a heading and a table for each cpu and build.
  awk -F, '
    function cellText(s) { gsub(/\|/, "\\|", s); return s == "" ? "" : s }
    function rate(r) { return r == "" ? "" : sprintf("%.3g M", r / 1e6) }
    function join(a, b, c,   s) {
      s = a; if (b != "") s = s (s == "" ? "" : " ") b; if (c != "") s = s (s == "" ? "" : " ") c
      return s
    }
    {
      group = $3 SUBSEP $5
      if (group != last) {
        if (NR > 1) print ""
        printf "### %s, %s build (%s)\n\n", $3, ($5 == "" ? "unnamed" : $5), ($4 == "" ? "isa not recorded" : $4)
        print "| scene | case | threads | solver | particles | steps | particle-steps/s | wall s | sim s / wall s | measured | note |"
        print "|---|---|---|---|---|---|---|---|---|---|---|"
        last = group
      }
      printf "| %s | %sD %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |\n", $7, $8, $9, $10,
             join($11, $12, $13), $14, $15, rate($16), $17, $18, join($1, $2, ""), cellText($19)
    }'
