#!/usr/bin/env bash
# Every GoogleTest unit binary that needs no OpenGL (apiclab_tests with EolSlow.* aside, the
# viewer worker, the app core, outputs, particle export) under AddressSanitizer + UndefinedBehaviorSanitizer, to the end
# (ctest asan.unit_tests, label slow; the render tests are left out because Mesa's driver is not
# instrumented and its own allocations then read as leaks;
# README "Fuzzing and sanitizers"). Builds SOURCE into BUILD (-O1, GUI off), then runs the
# GoogleTest binaries in two shards at once; any sanitizer report or failed test fails.
# Usage: tests/asan_tests.sh SOURCE_DIR BUILD_DIR
set -uo pipefail
src="$1" build="$2"
compiler=()
command -v clang++ >/dev/null && compiler=(-DCMAKE_CXX_COMPILER=clang++ -DCMAKE_C_COMPILER=clang)
cmake -S "$src" -B "$build" -G Ninja "${compiler[@]}" -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS=-O1 \
  -DAPICLAB_ASAN=ON -DAPICLAB_BUILD_GUI=OFF -DAPICLAB_NATIVE=OFF >"$build.configure.log" 2>&1 || {
  cat "$build.configure.log"
  exit 1
}
binaries=(apiclab_tests test_gui_worker test_app_core test_outputs test_particle_export)
cmake --build "$build" --target "${binaries[@]}" || exit 1
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1
status=0
for exe in "${binaries[@]}"; do
  for shard in 0 1; do
    GTEST_TOTAL_SHARDS=2 GTEST_SHARD_INDEX=$shard "$build/tests/$exe" --gtest_filter='-EolSlow.*' \
      >"$build/$exe.shard$shard.log" 2>&1 &
  done
  for shard in 0 1; do wait -n || status=1; done
  for shard in 0 1; do
    log="$build/$exe.shard$shard.log"
    grep -E '^\[  (PASSED|FAILED) |tests? ran' "$log" | sed "s|^|$exe shard $shard: |"
    if grep -qE 'ERROR: AddressSanitizer|runtime error:|ERROR: LeakSanitizer|^\[  FAILED' "$log"; then
      grep -E -A20 'ERROR: AddressSanitizer|runtime error:|ERROR: LeakSanitizer|^\[  FAILED' "$log" | head -60
      status=1
    fi
  done
done
((status == 0)) && echo "PASS: the unit and worker tests ran to the end under ASan + UBSan, no report"
exit $status
