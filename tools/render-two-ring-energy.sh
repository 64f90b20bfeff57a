#!/usr/bin/env bash
# Prints docs/data/two-ring-energy.csv as the Markdown table of docs/transfer-schemes.md, in the
# very form `apiclab figures --only scheme-energy` prints it (tests/render/figures_tests.sh compares
# the two line by line).
#   tools/render-two-ring-energy.sh [CSV]   (default docs/data/two-ring-energy.csv)
set -euo pipefail
csv="${1:-docs/data/two-ring-energy.csv}"
awk -F, '
NR == 1 { next }
NF != 6 { printf "render-two-ring-energy: %s line %d has %d fields, not 6\n", FILENAME, NR, NF > "/dev/stderr"; exit 2 }
NR == 2 { printf "| scheme | total energy at t = %s s [J] | of the initial |\n| --- | --- | --- |\n", $3 }
$6 == "" { print "| " $2 " | " $4 " | " $5 " % |"; next }
{ print "| " $2 " | blew up at t = " $6 " s | – |" }
' "$csv"
