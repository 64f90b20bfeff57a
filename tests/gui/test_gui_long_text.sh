#!/usr/bin/env bash
# The viewer on a scene whose description is 25,000 characters: it shows a few lines of it, cut
# with "...", keeps its controls on the panel and takes its screenshot (drawn whole, the text
# overflowed ImGui's 16-bit vertex indices: an assertion, exit 134).
# Usage: APICLAB=path/to/apiclab test_gui_long_text.sh SOURCE_DIR OUTDIR
set -uo pipefail
src="${1:?usage: test_gui_long_text.sh SOURCE_DIR OUTDIR}"
out="${2:-/tmp/apiclab-gui-long-text}"
mkdir -p "$out"
if ! command -v xvfb-run >/dev/null; then
  echo "SKIP: xvfb-run not found (apt-get install xvfb xauth)"
  exit 0
fi
awk 'BEGIN {for (i = 0; i < 2500; i++) d = d "lorem ips "}  # 25,000 characters
     /"description"/ {print "  \"description\": \"" d "\","; next} {print}' \
  "$src/assets/scenes/rotating-disk.json" >"$out/long.json"
png="$out/long.png"
rm -f "$png"
APICLAB_PRINT_LAYOUT=1 timeout 120 xvfb-run -a -s "-screen 0 1280x800x24" "$APICLAB" gui "$out/long.json" \
  --screenshot "$png" --frames 2 --size 1280x800 >"$out/long.log" 2>&1
rc=$?
cat "$out/long.log"
if [ $rc -ne 0 ] || [ ! -s "$png" ]; then
  echo "FAIL: the viewer on a 25,000-character description exited $rc"
  exit 1
fi
# "description: SHOWN of 25000 characters, H px": cut, and a few lines high.
read -r shown total px < <(sed -n 's/^description: \([0-9]*\) of \([0-9]*\) characters, \([0-9]*\) px$/\1 \2 \3/p' "$out/long.log")
if [ "${total:-0}" -ne 25000 ] || [ "${shown:-0}" -lt 50 ] || [ "$shown" -ge 2000 ] || [ "${px:-999}" -gt 100 ]; then
  echo "FAIL: the description was not cut to a few lines (shown ${shown:-?} of ${total:-?}, ${px:-?} px)"
  exit 1
fi
echo "a 25,000-character description: $shown characters shown in $px px, the screenshot taken"
