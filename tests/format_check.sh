#!/usr/bin/env bash
# Fails when a C++ source under sim/, render/, app/ or tests/ differs from what .clang-format
# makes of it, and prints the files (fix: clang-format -i FILE).
set -uo pipefail
root="${1:-.}"
cd "$root" || exit 2
command -v clang-format >/dev/null || { echo "format_check: clang-format is not installed" >&2; exit 2; }
mapfile -t files < <(find sim render app tests -name '*.[ch]pp' | sort)
bad=()
for f in "${files[@]}"; do
  [ -f "$f" ] || continue
  clang-format --dry-run --Werror "$f" >/dev/null 2>&1 || bad+=("$f")
done
if ((${#bad[@]})); then
  echo "format_check: ${#bad[@]} file(s) differ from .clang-format: ${bad[*]}"
  echo "format_check: run  clang-format -i ${bad[*]}"
  exit 1
fi
echo "format_check: ${#files[@]} files follow .clang-format"
