#!/usr/bin/env bash
# One-command set-up on a fresh Debian 12 machine (README, docs/testing.md):
#   ./setup.sh demo       install, build, then open the viewer (display) or render PNG frames
#   ./setup.sh test       install, build, run the default test tier (CI's first step)
#   ./setup.sh full       install, build, run the full tier: sanitizers, fuzzing, the GUI soak,
#                         the slow validations (CI's second step)
#   ./setup.sh extended   install, build, run the extended tier (by hand: the 30-minute soak,
#                         VTK's readers)
set -euo pipefail
cd "$(dirname "$0")"
mode="${1:-demo}"
case "$mode" in
  demo | test | full | extended) ;;
  *)
    echo "usage: ./setup.sh demo|test|full|extended" >&2
    exit 2
    ;;
esac

packages=(
  build-essential cmake ninja-build pkg-config git
  libeigen3-dev nlohmann-json3-dev libcgal-dev libcli11-dev libgtest-dev
  libegl-dev libgl-dev libegl1 libgl1-mesa-dri libosmesa6-dev libstb-dev fonts-dejavu-core
  libglfw3-dev libimgui-dev xvfb xauth ffmpeg clang-format
  libnanoflann-dev parallel zlib1g-dev
  python3-dev python3-numpy python3-pytest pybind11-dev
)
# The full tier builds with clang's sanitizers and fuzzes (clang, libFuzzer in libclang-rt-dev,
# OpenMP for clang) and drives the viewer with random input (xdotool); the extended tier reads
# the exports with VTK (python3-vtk9, about 300 MB). docs/testing.md.
case "$mode" in
  full) packages+=(clang libclang-rt-dev libomp-dev xdotool) ;;
  extended) packages+=(clang libclang-rt-dev libomp-dev xdotool python3-vtk9) ;;
esac
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  sudo=""
  [ "$(id -u)" = 0 ] || sudo=sudo
  echo "setup: installing ${missing[*]}" >&2
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j "$(nproc)"

case "$mode" in
  test | full | extended)
    # One tier: every test carries exactly one of the labels default, full, extended.
    tier=$mode
    [ "$mode" = test ] && tier=default
    ctest --test-dir build -L "^$tier\$" --output-on-failure -j "$(nproc)"
    ;;
  demo)
    app=build/app/apiclab
    if [ -n "${DISPLAY:-}${WAYLAND_DISPLAY:-}" ] && $app --help | grep -q '^  gui'; then
      exec $app gui rotating-disk --schemes pic,flip,apic
    elif $app --help | grep -q '^  render'; then
      $app render skew-impact --out out/skew-impact --vectors --color speed
      echo "setup: PNG frames in out/skew-impact/"
    else
      $app run rotating-disk
    fi
    ;;
esac
