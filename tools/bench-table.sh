#!/usr/bin/env bash
# Builds the native and the portable (-march=x86-64-v3) binaries and times the standard table,
# appending every measurement to the performance ledger (apiclab bench --record; docs/performance.md).
#   tools/bench-table.sh [OPTIONS]
#     --builds LIST      native,x86-64-v3                  [default: both]
#     --parts LIST       block,sizes,reference,scenes      [default: all four]
#     --dims LIST        2,3                               [default: 2,3]
#     --precisions LIST  float,double                      [default: float,double]
#     --threads LIST     1,all (all: every core)           [default: 1,all]
#     --rounds N         each cell N times, the builds alternating in each  [default: 1]
#     --ledger FILE      [default: docs/data/performance-ledger.csv]
#     --no-build         use build-bench-native/ and build-bench-v3/ as they are
#     --dry-run          print the commands, run nothing
# block: `bench` for each dim x precision x threads; sizes and reference: one thread each;
# scenes: two-cubes, bunnies and sphere-impact-3d to their end on 2 threads (the old targets:
# 3, 8 and 20 minutes), rotating-disk (implicit midpoint) to its end on 1 thread.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
builds=native,x86-64-v3 parts=block,sizes,reference,scenes dims=2,3 precisions=float,double
threads=1,all rounds=1 ledger="$root/docs/data/performance-ledger.csv" build=1 dry=0
while (($#)); do
  case "$1" in
    --builds) builds="$2"; shift ;;
    --parts) parts="$2"; shift ;;
    --dims) dims="$2"; shift ;;
    --precisions) precisions="$2"; shift ;;
    --threads) threads="$2"; shift ;;
    --rounds) rounds="$2"; shift ;;
    --ledger) ledger="$2"; shift ;;
    --no-build) build=0 ;;
    --dry-run) dry=1 ;;
    -h | --help) sed -n '2,17p' "$0"; exit 0 ;;
    *) echo "bench-table: unknown option '$1' (--help)" >&2; exit 2 ;;
  esac
  shift
done
has() { [[ ",$1," == *",$2,"* ]]; }
run() { echo "+ $*" >&2; ((dry)) || "$@"; }

dir_of() { case "$1" in native) echo "$root/build-bench-native" ;; *) echo "$root/build-bench-v3" ;; esac; }
flags_of() {
  case "$1" in
    native) echo "-DAPICLAB_NATIVE=ON" ;;
    x86-64-v3) echo "-DAPICLAB_NATIVE=OFF -DAPICLAB_MARCH=x86-64-v3" ;;
    *) echo "bench-table: unknown build '$1' (native, x86-64-v3)" >&2; exit 2 ;;
  esac
}
IFS=, read -r -a build_list <<<"$builds"
for b in "${build_list[@]}"; do
  flags="$(flags_of "$b")"
  ((build)) || continue
  launcher=()
  command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
  # shellcheck disable=SC2086  # flags holds separate -D words
  run cmake -S "$root" -B "$(dir_of "$b")" -G Ninja -DCMAKE_BUILD_TYPE=Release $flags \
    -DAPICLAB_BUILD_TESTS=OFF -DAPICLAB_BUILD_GUI=OFF "${launcher[@]}" >/dev/null
  run cmake --build "$(dir_of "$b")" --target apiclab -j "$(nproc)"
done

# One cell: every build in turn, `rounds` times; bench prints its block, --record appends the rows.
cell() {
  for ((k = 1; k <= rounds; ++k)); do
    for b in "${build_list[@]}"; do
      run "$(dir_of "$b")/app/apiclab" bench "$@" --record "$ledger"
    done
  done
}
IFS=, read -r -a dim_list <<<"$dims"
IFS=, read -r -a precision_list <<<"$precisions"
IFS=, read -r -a thread_list <<<"$threads"
for d in "${dim_list[@]}"; do
  for p in "${precision_list[@]}"; do
    if has "$parts" block; then
      for t in "${thread_list[@]}"; do
        [ "$t" = all ] && t="$(nproc)"
        cell --dim "$d" --precision "$p" --threads "$t"
      done
    fi
    if has "$parts" sizes; then
      cell --dim "$d" --precision "$p" --threads 1 --sizes 3000,30000,300000,1000000
    fi
    if has "$parts" reference; then cell --dim "$d" --precision "$p" --threads 1 --reference; fi
  done
done
if has "$parts" scenes; then
  for scene in two-cubes bunnies sphere-impact-3d; do
    cell --scene "$scene" --threads 2 --frames 100000
  done
  cell --scene rotating-disk --threads 1 --frames 100000
fi
echo "bench-table: rows appended to $ledger; tools/gen-docs.sh performance renders them" >&2
