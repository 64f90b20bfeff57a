#!/usr/bin/env bash
# One-command set-up on a fresh Debian 12 machine (README):
#   ./setup.sh demo   install, build, then open the viewer (display) or render PNG frames
#   ./setup.sh test   install, build, run the test suite (the same command CI runs)
set -euo pipefail
cd "$(dirname "$0")"
mode="${1:-demo}"

packages=(
  build-essential cmake ninja-build pkg-config git
  libeigen3-dev nlohmann-json3-dev libtinyobjloader-dev libcli11-dev libgtest-dev
  libegl-dev libgl-dev libegl1 libgl1-mesa-dri libosmesa6-dev libstb-dev fonts-dejavu-core
  libglfw3-dev libimgui-dev xvfb xauth ffmpeg clang-format
  libnanoflann-dev parallel zlib1g-dev
)
# The test set also fuzzes (clang, libFuzzer in libclang-rt-dev, OpenMP for clang) and drives
# the viewer with random input (xdotool); README "Fuzzing and sanitizers", "GUI soak".
if [ "$mode" = test ]; then packages+=(clang libclang-rt-dev libomp-dev xdotool); fi
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
  test)
    # The default test set (slow validations carry the label "slow" and are not run here).
    ctest --test-dir build -LE slow --output-on-failure -j 2
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
  *)
    echo "usage: ./setup.sh demo|test" >&2
    exit 2
    ;;
esac
