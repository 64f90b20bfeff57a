#!/usr/bin/env bash
# The performance ledger (docs/performance.md): `apiclab bench --record FILE` creates FILE with the
# ledger's header and appends one row a run with the values asked; it refuses a FILE whose header
# is another (exit 2, one line, FILE unchanged); tools/render-performance.sh renders the newest
# row of each cell of a small ledger.
#   perf_ledger_tests.sh ROOT      (APICLAB: the binary; default ROOT/build/app/apiclab)
set -uo pipefail
root="$(cd "${1:-.}" && pwd)"
app="${APICLAB:-$root/build/app/apiclab}"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
fail() { echo "perf_ledger_tests: FAIL: $*" >&2; exit 1; }
header="$(head -n 1 "$root/docs/data/performance-ledger.csv")"

# Two tiny benches into a new ledger.
ledger="$tmp/ledger.csv"
for run in 1 2; do
  "$app" bench --particles 1024 --steps 3 --threads 1 --record "$ledger" >"$tmp/out$run" 2>&1 ||
    fail "bench --record (run $run) exited $?: $(cat "$tmp/out$run")"
done
[ "$(head -n 1 "$ledger")" = "$header" ] || fail "the new ledger's first line is not the header"
[ "$(wc -l <"$ledger")" -eq 3 ] || fail "expected the header and 2 rows, got: $(cat "$ledger")"
[ "$(grep -c '^date,' "$ledger")" -eq 1 ] || fail "the header was written more than once"
particles="$(sed -n 's/.* \([0-9]*\) particles,.*/\1/p' "$tmp/out1")"
[ "$particles" = 1024 ] || fail "bench printed '$particles' particles, expected 1024"
awk -F, -v n="$particles" '
  NR == 1 { next }
  NF != 19 { print "row " NR - 1 ": " NF " columns, not 19"; bad = 1; next }
  $1 !~ /^[0-9][0-9][0-9][0-9]-[0-9][0-9]-[0-9][0-9]$/ { print "row " NR - 1 ": date " $1; bad = 1 }
  $3 == "" || $4 == "" || $5 == "" { print "row " NR - 1 ": cpu, isa or build empty"; bad = 1 }
  $6 != "mpm" || $7 != "bench" { print "row " NR - 1 ": method/scene " $6 "/" $7; bad = 1 }
  $8 != 2 || $9 != "float" || $10 != 1 { print "row " NR - 1 ": dim/precision/threads " $8 "/" $9 "/" $10; bad = 1 }
  $11 != "apic" || $12 != "quadratic" || $13 != "symplectic" { print "row " NR - 1 ": solver " $11 " " $12 " " $13; bad = 1 }
  $14 != n || $15 != 3 { print "row " NR - 1 ": particles/steps " $14 "/" $15; bad = 1 }
  !($16 + 0 > 0) || !($17 + 0 > 0) { print "row " NR - 1 ": rate " $16 " wall " $17; bad = 1 }
  END { exit bad }' "$ledger" || fail "bad rows in $(cat "$ledger")"
rate="$(sed -n 's/^particle-steps\/s: //p' "$tmp/out2")"
[ "$(tail -n 1 "$ledger" | cut -d, -f16)" = "$rate" ] || fail "row 2's rate is not the printed $rate"

# A file with another header: refused before timing, one line on stderr, the file unchanged.
printf 'a,b,c\n1,2,3\n' >"$tmp/other.csv"
cp "$tmp/other.csv" "$tmp/other.orig"
"$app" bench --particles 1024 --steps 3 --threads 1 --record "$tmp/other.csv" >"$tmp/out3" 2>"$tmp/err3"
rc=$?
[ "$rc" -eq 2 ] || fail "--record onto a non-ledger exited $rc, expected 2"
[ "$(wc -l <"$tmp/err3")" -eq 1 ] || fail "expected one line on stderr, got: $(cat "$tmp/err3")"
cmp -s "$tmp/other.csv" "$tmp/other.orig" || fail "the refused file was changed"
[ ! -s "$tmp/out3" ] || fail "the refused run timed anyway: $(cat "$tmp/out3")"

# The renderer: the newest row of each cell, per cpu and build; rows without a number left out.
cat >"$tmp/fixture.csv" <<EOF
$header
2026-01-02,abc1234,CPU A,avx2,native,mpm,bench,2,float,1,apic,quadratic,symplectic,262144,200,20000000,,,old
2026-01-03,def5678,CPU A,avx2,native,mpm,bench,2,float,1,apic,quadratic,symplectic,262144,200,21500000,2.44,,new
2026-01-03,,CPU A,avx2,native,mpm,bench,2,float,1,apic,quadratic,symplectic,262144,200,,,,ratio only
2026-01-01,,CPU A,avx2,x86-64-v3,mpm,bench,3,double,2,apic,quadratic,symplectic,110592,50,9870000,,,v3 a|b
2026-01-01,,CPU A,avx2,native,mpm,two-cubes,3,double,2,apic,quadratic,symplectic,134521,10000,,130.3,0.00767,run
EOF
bash "$root/tools/render-performance.sh" "$tmp/fixture.csv" >"$tmp/table.md" ||
  fail "render-performance.sh failed on the fixture"
expect() { grep -qF -- "$1" "$tmp/table.md" || fail "the rendered table lacks '$1': $(cat "$tmp/table.md")"; }
expect "### CPU A, native build (avx2)"
expect "### CPU A, x86-64-v3 build (avx2)"
expect "| bench | 2D float | 1 | apic quadratic symplectic | 262144 | 200 | 21.5 M | 2.44 |  | 2026-01-03 def5678 | new |"
expect "| bench | 3D double | 2 | apic quadratic symplectic | 110592 | 50 | 9.87 M |  |  | 2026-01-01 | v3 a\|b |"
expect "| two-cubes | 3D double | 2 | apic quadratic symplectic | 134521 | 10000 |  | 130.3 | 0.00767 | 2026-01-01 | run |"
! grep -qE "\| (old|ratio only) \|" "$tmp/table.md" || fail "an older or number-less row was rendered"
[ "$(grep -c '^| [a-z]' "$tmp/table.md")" -eq 5 ] || fail "expected 3 rows under 2 header lines"
bash "$root/tools/render-performance.sh" "$tmp/other.csv" >/dev/null 2>&1
[ $? -eq 2 ] || fail "render-performance.sh accepted a file that is not a ledger"
echo "perf_ledger_tests: OK (bench --record, refusal, renderer)"
