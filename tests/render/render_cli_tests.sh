#!/usr/bin/env bash
# `apiclab render` and `apiclab compare` through the real executable ($APICLAB), headless.
set -u
app="${APICLAB:?set APICLAB to the apiclab executable}"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
export EGL_PLATFORM=surfaceless
passed=0 failed=0
ok() { passed=$((passed + 1)); echo "ok: $1"; }
fail() { failed=$((failed + 1)); echo "FAILED: $1"; }
check() { if eval "$2"; then ok "$1"; else fail "$1"; fi; }
last_t_is() { awk -F, -v t="$2" 'END {exit !($2 == t)}' "$1"; }  # CSV's last row at time t
# PNG width and height from the IHDR chunk.
png_size() { od -An -tu1 -j16 -N8 "$1" | awk '{print $1*16777216+$2*65536+$3*256+$4 "x" $5*16777216+$6*65536+$7*256+$8}'; }
small=(--size 160x120 --quiet)

# Frames at the scene's fps, CSV, log of the backend.
"$app" render rotating-disk --out "$tmp/plain" --frames 2 --size 160x120 2>"$tmp/plain.log"
check "render exits 0" "[ $? = 0 ]"
check "render writes frame_0000..0002.png" "[ -s $tmp/plain/frame_0000.png ] && [ -s $tmp/plain/frame_0002.png ] && [ ! -e $tmp/plain/frame_0003.png ]"
check "frames have the asked size" "[ \"\$(png_size $tmp/plain/frame_0001.png)\" = 160x120 ]"
check "render writes the diagnostics CSV" "head -1 $tmp/plain/apic.csv | grep -q '^step,t,dt,kinetic,kinetic_grid,potential,total,px,py,pz,Lx,Ly,Lz'"
check "render logs the backend" "grep -q 'rendering with EGL' $tmp/plain.log"
check "render reports progress and cost" "grep -q 'ms/frame' $tmp/plain.log"

# A scene end that is not a whole frame (3.24 frames): frame 3 at 3/24, frame 4 on time.end.
"$app" render rotating-disk --out "$tmp/end" --t-end 0.135 "${small[@]}"
check "render: last frame (frame_0004) at time.end" "[ -s $tmp/end/frame_0004.png ] && [ ! -e $tmp/end/frame_0005.png ] && last_t_is $tmp/end/apic.csv 0.135"

# Options change the picture.
"$app" render rotating-disk --out "$tmp/vectors" --frames 1 --vectors "${small[@]}"
check "--vectors changes the image" "! cmp -s $tmp/plain/frame_0001.png $tmp/vectors/frame_0001.png"
for mode in material noise; do
  "$app" render rotating-disk --out "$tmp/$mode" --frames 1 --color $mode "${small[@]}"
  check "--color $mode differs from speed" "[ -s $tmp/$mode/frame_0001.png ] && ! cmp -s $tmp/plain/frame_0001.png $tmp/$mode/frame_0001.png"
done
"$app" render ring-collision --out "$tmp/fit" --frames 1 --fit particles "${small[@]}"
check "--fit particles renders" "[ -s $tmp/fit/frame_0001.png ]"
# --fit auto (the default) frames skew-impact's two small disks over their run, not the domain
# they fill a twentieth of; the printed scales with --fit domain draw the domain.
"$app" compare skew-impact --schemes pic,apic --out "$tmp/auto" --t-end 0.2 --size 320x120 2>"$tmp/auto.log"
scales=$(sed -n 's/^apiclab: one scale for all [0-9]* frames (a first pass over them): //p' "$tmp/auto.log")
# shellcheck disable=SC2086  # the options as printed
"$app" compare skew-impact --schemes pic,apic --out "$tmp/domain" --t-end 0.2 --size 320x120 --fit domain $scales --quiet
check "--fit auto frames the bodies, not the domain" "[ -s $tmp/auto/frame_0002.png ] && ! cmp -s $tmp/auto/frame_0002.png $tmp/domain/frame_0002.png"
check "--color material and noise differ" "! cmp -s $tmp/material/frame_0001.png $tmp/noise/frame_0001.png"

# OSMesa as the backend.
"$app" render rotating-disk --out "$tmp/osmesa" --frames 1 --backend osmesa --size 160x120 2>"$tmp/osmesa.log"
check "--backend osmesa renders" "[ -s $tmp/osmesa/frame_0001.png ] && grep -q 'rendering with OSMesa' $tmp/osmesa.log"

APICLAB_EGL_LIBRARY=/nonexistent/libEGL.so.1 "$app" render rotating-disk --out "$tmp/fallback" --frames 1 --size 160x120 2>"$tmp/fallback.log"
check "auto falls back to OSMesa without EGL, and says why" "[ -s $tmp/fallback/frame_0001.png ] && grep -q 'rendering with OSMesa.*EGL: /nonexistent' $tmp/fallback.log"

# Compare: lockstep panes, one CSV per scheme.
"$app" compare rotating-disk --schemes pic,flip,apic --out "$tmp/cmp" --frames 1 --size 480x160 --quiet
check "compare exits 0" "[ $? = 0 ]"
check "compare writes frames" "[ -s $tmp/cmp/frame_0000.png ] && [ -s $tmp/cmp/frame_0001.png ]"
check "compare writes one CSV per scheme" "[ -s $tmp/cmp/pic.csv ] && [ -s $tmp/cmp/flip.csv ] && [ -s $tmp/cmp/apic.csv ]"
check "compare schemes reach the same time" "[ \"\$(tail -1 $tmp/cmp/pic.csv | cut -d, -f2)\" = \"\$(tail -1 $tmp/cmp/apic.csv | cut -d, -f2)\" ]"
"$app" compare rotating-disk --schemes pic,apic --out "$tmp/cmp-end" --t-end 0.135 --size 320x120 --quiet
check "compare: every scheme's last frame at time.end" "[ -s $tmp/cmp-end/frame_0004.png ] && [ ! -e $tmp/cmp-end/frame_0005.png ] && last_t_is $tmp/cmp-end/pic.csv 0.135 && last_t_is $tmp/cmp-end/apic.csv 0.135"
check "compare schemes start from the same state" "[ \"\$(sed -n 2p $tmp/cmp/pic.csv | cut -d, -f8,9)\" = \"\$(sed -n 2p $tmp/cmp/flip.csv | cut -d, -f8,9)\" ]"

# Clear one-line errors, before any simulation.
expect_error() {  # name, pattern, command...
  local name="$1" pattern="$2"
  shift 2
  "$@" >"$tmp/err.out" 2>"$tmp/err.log"
  local status=$?
  if [ $status = 2 ] && [ "$(wc -l <"$tmp/err.log")" = 1 ] && grep -q "$pattern" "$tmp/err.log"; then
    ok "$name"
  else
    fail "$name (exit $status: $(cat "$tmp/err.log"))"
  fi
}
touch "$tmp/a-file"
expect_error "unwritable --out" "cannot create output directory" "$app" render rotating-disk --out "$tmp/a-file/frames"
expect_error "bad --size" "invalid --size" "$app" render rotating-disk --out "$tmp/x" --size 12by3
expect_error "bad --color" "unknown color mode" "$app" render rotating-disk --out "$tmp/x" --color rainbow
expect_error "bad --fit" "unknown --fit" "$app" render rotating-disk --out "$tmp/x" --fit everything
expect_error "bad --backend" "unknown backend" "$app" render rotating-disk --out "$tmp/x" --backend vulkan
expect_error "unknown scheme in --schemes" "unknown scheme 'pick'" "$app" compare rotating-disk --out "$tmp/x" --schemes pic,pick
expect_error "compare with --scheme" "not --scheme" "$app" compare rotating-disk --out "$tmp/x" --schemes pic --scheme flip
expect_error "a scheme twice in --schemes" "listed twice" "$app" compare rotating-disk --out "$tmp/x" --schemes pic,pic
expect_error "neither EGL nor OSMesa" "install libegl1" env APICLAB_EGL_LIBRARY=/nonexistent/libEGL.so.1 \
  APICLAB_OSMESA_LIBRARY=/nonexistent/libOSMesa.so.8 "$app" render rotating-disk --out "$tmp/none" --frames 1
expect_error "--video without ffmpeg" "apt-get install ffmpeg" env PATH=/nonexistent "$app" render rotating-disk \
  --out "$tmp/x" --video "$tmp/x.mp4" --frames 1

# Video, where Debian's ffmpeg is installed.
if command -v ffmpeg >/dev/null; then
  "$app" render rotating-disk --out "$tmp/video" --frames 2 --video "$tmp/video.mp4" "${small[@]}"
  check "--video writes an MP4" "[ -s $tmp/video.mp4 ]"
else
  echo "skipped: --video (ffmpeg not installed)"
fi

echo "$passed passed, $failed failed"
[ "$failed" = 0 ]
