#!/usr/bin/env bash
# Prints docs/data/figures.csv as the Markdown table of docs/paper-figures.md: every number of
# the paper figures that tests/render/figures_tests.sh recomputes, beside the paper's claim.
#   tools/render-figures.sh [CSV]        (default docs/data/figures.csv; run from the repo root)
# Values are written as the test formats them (2e-9, -11.4) and shown as 2·10⁻⁹, −11.4.
set -euo pipefail
csv="${1:-docs/data/figures.csv}"
awk -F, '
function sup(n,   s, out, k) {  # an integer exponent in superscript digits
  s = n ""; out = ""
  for (k = 1; k <= length(s); k++) out = out digit[substr(s, k, 1)]
  return out
}
function cell(s) { gsub(/\|/, "\\|", s); return s }
function show(v, unit,   neg, p) {
  neg = v ~ /^-/
  if (neg) v = substr(v, 2)
  if (v ~ /e/) { split(v, p, "e"); v = (p[1] == "1" ? "" : p[1] "·") "10" sup(p[2] + 0) }
  if (neg) v = "−" v
  if (unit == "×") return v "×"
  return unit == "" ? v : v " " unit
}
BEGIN {
  split("⁰ ¹ ² ³ ⁴ ⁵ ⁶ ⁷ ⁸ ⁹", d, " ")
  for (k = 0; k <= 9; k++) digit[k ""] = d[k + 1]
  digit["-"] = "⁻"
}
NR == 1 { print "| figure | quantity | the paper | here |"; print "| --- | --- | --- | --- |"; next }
NF != 6 { printf "render-figures: %s line %d has %d fields, not 6\n", FILENAME, NR, NF > "/dev/stderr"; exit 2 }
{ print "| " ($1 == last ? "" : $1) " | " cell($5) " | " cell($6) " | " show($3, $4) " |"; last = $1 }
' "$csv"
