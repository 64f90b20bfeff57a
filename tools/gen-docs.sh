#!/usr/bin/env bash
# Regenerates the generated sections of README.md and docs/ from their sources, or checks them.
#   tools/gen-docs.sh [--check] [NAME ...]     NAME: one of the generators below; none: all
# A generated section sits between two marker lines in a Markdown file:
#   <!-- BEGIN GENERATED NAME: tools/gen-docs.sh NAME -->
#   <!-- END GENERATED NAME -->
# --check rewrites nothing and exits 1 naming every stale section (docs_generated test).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
app="${APICLAB:-$root/build/app/apiclab}"
[[ "$app" == /* ]] || app="$PWD/$app"  # the generators run from the repository root

# NAME -> "FILE|COMMAND": COMMAND prints the section's body on stdout, run from the repo root.
declare -A generators=(
  [scene-keys]="docs/scene-keys.md|\"$app\" docs scene-keys"
  [schemes]="README.md|\"$app\" docs schemes"
  [scenes]="README.md|\"$app\" docs scenes"
  [figures]="docs/paper-figures.md|tools/render-figures.sh docs/data/figures.csv"
  [two-ring-energy]="docs/transfer-schemes.md|tools/render-two-ring-energy.sh docs/data/two-ring-energy.csv"
  [performance]="docs/performance.md|tools/render-performance.sh docs/data/performance-ledger.csv"
)

check=0
names=()
for a in "$@"; do
  case "$a" in
    --check) check=1 ;;
    -h | --help) sed -n '2,7p' "$0"; exit 0 ;;
    *) [ -n "${generators[$a]+x}" ] || { echo "gen-docs: unknown generator '$a' (${!generators[*]})" >&2; exit 2; }
       names+=("$a") ;;
  esac
done
((${#names[@]})) || names=("${!generators[@]}")

stale=0
for name in "${names[@]}"; do
  file="$root/${generators[$name]%%|*}" cmd="${generators[$name]#*|}"
  begin="<!-- BEGIN GENERATED $name: tools/gen-docs.sh $name -->"
  end="<!-- END GENERATED $name -->"
  grep -qxF "$begin" "$file" && grep -qxF "$end" "$file" ||
    { echo "gen-docs: $file has no '$begin' ... '$end' markers" >&2; exit 2; }
  body="$(cd "$root" && eval "$cmd")" || { echo "gen-docs: '$cmd' failed" >&2; exit 2; }
  new="$(mktemp)"
  awk -v b="$begin" -v e="$end" -v bodyfile=<(printf '%s\n' "$body") '
    $0 == b { print; while ((getline l < bodyfile) > 0) print l; skip = 1; next }
    $0 == e { skip = 0 }
    !skip { print }' "$file" >"$new"
  if cmp -s "$new" "$file"; then
    rm -f "$new"
  elif ((check)); then
    echo "gen-docs: ${file#$root/} section '$name' is stale: run tools/gen-docs.sh $name" >&2
    stale=1; rm -f "$new"
  else
    cat "$new" >"$file"; rm -f "$new"; echo "gen-docs: updated ${file#$root/} ($name)"
  fi
done
exit $stale
