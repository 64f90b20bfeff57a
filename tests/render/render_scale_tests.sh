#!/usr/bin/env bash
# One colour scale and one arrow scale for a whole `render`/`compare` sequence (docs/cli.md): a
# first pass over the frames finds them and says them as options; the same command with those
# options (no first pass) draws every frame the same, pixel for pixel. A falling body's speed
# grows frame by frame, so scales that grew with the sequence would make the frames differ.
# Usage: APICLAB=/path/to/apiclab render_scale_tests.sh
set -u
APICLAB=${APICLAB:?set APICLAB to the apiclab executable}
TMP=$(mktemp -d "${TMPDIR:-/tmp}/apiclab-scale.XXXXXX")
trap 'rm -rf "$TMP"' EXIT
export EGL_PLATFORM=surfaceless
source "$(dirname "${BASH_SOURCE[0]}")/../check_lib.sh"

DROP=(eol-drop --set 'solver.method="mpm"' --t-end 0.25 --vectors --size 160x120 --threads 1)
for cmd in render compare; do
  extra=()
  [ $cmd = compare ] && extra=(--schemes pic,apic)
  "$APICLAB" $cmd "${DROP[@]}" "${extra[@]}" --out "$TMP/$cmd-a" 2>"$TMP/$cmd-a.log" >/dev/null
  rc=$?
  fixed=$(sed -n 's/^apiclab: one scale for all [0-9]* frames (a first pass over them): //p' "$TMP/$cmd-a.log")
  if [ $rc -ne 0 ] || [ -z "$fixed" ]; then
    nok "$cmd: a first pass says the scales (rc $rc)" "$(cat "$TMP/$cmd-a.log")"
    continue
  fi
  ok "$cmd: a first pass says the scales: $fixed"
  # shellcheck disable=SC2086  # the options as printed: --color-max X --vector-scale Y
  "$APICLAB" $cmd "${DROP[@]}" "${extra[@]}" $fixed --out "$TMP/$cmd-b" 2>"$TMP/$cmd-b.log" >/dev/null
  if grep -q "one scale for all" "$TMP/$cmd-b.log"; then
    nok "$cmd: scales given as options need no first pass"
  fi
  n=$(ls "$TMP/$cmd-a"/frame_*.png | wc -l)
  same=0
  for f in "$TMP/$cmd-a"/frame_*.png; do
    cmp -s "$f" "$TMP/$cmd-b/$(basename "$f")" && same=$((same + 1))
  done
  if [ "$n" -ge 6 ] && [ "$same" -eq "$n" ]; then
    ok "$cmd: all $n frames drawn with the one scale (identical to the scales given as options)"
  else
    nok "$cmd: $same of $n frames match the fixed scales"
  fi
done

finish render_scale_tests
