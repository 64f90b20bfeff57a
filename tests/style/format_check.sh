#!/usr/bin/env bash
# Fails when a C++ source under sim/, render/, app/, python/ or tests/ differs from what .clang-format
# makes of it, and prints the files (fix: clang-format -i FILE).
set -uo pipefail
root="${1:-.}"
cd "$root" || exit 2
command -v clang-format >/dev/null || { echo "format_check: clang-format is not installed" >&2; exit 2; }
mapfile -t files < <(find sim render app python tests -name '*.[ch]pp' | sort)
# One clang-format for all the files (a process a file took most of the time); a file that
# differs is named on its "error: code should be clang-formatted" lines.
out="$(clang-format --dry-run --Werror "${files[@]}" 2>&1)"
status=$?
mapfile -t bad < <(grep -oE '^[^:]+:[0-9]+:[0-9]+: error' <<<"$out" | cut -d: -f1 | sort -u)
if ((status != 0 && ${#bad[@]} == 0)); then
  echo "format_check: clang-format failed: $(head -n 1 <<<"$out")"
  exit 2
fi
if ((${#bad[@]})); then
  echo "format_check: ${#bad[@]} file(s) differ from .clang-format: ${bad[*]}"
  echo "format_check: run  clang-format -i ${bad[*]}"
  exit 1
fi
echo "format_check: ${#files[@]} files follow .clang-format"
