#!/usr/bin/env bash
# The fuzzers under ctest (tests/CMakeLists.txt, README "Fuzzing and sanitizers"):
#   fuzz_test.sh build SOURCE_DIR BUILD_DIR           builds fuzz_scene, fuzz_set, fuzz_obj
#   fuzz_test.sh run TARGET SECONDS SOURCE_DIR BUILD_DIR   runs one, from its seeds, SECONDS s
# Both print "SKIP: ..." and succeed where clang or libFuzzer is missing. A finding fails the
# test and leaves its input in BUILD_DIR/findings/TARGET/ (copy it to tests/fuzz_regressions/).
set -uo pipefail
mode="$1"
shift
skip_without_clang() {
  if ! command -v clang++ >/dev/null || ! command -v clang >/dev/null; then
    echo "SKIP: clang not found, fuzzers not built (apt-get install clang libclang-rt-14-dev)"
    exit 0
  fi
  local probe
  probe=$(mktemp -d)
  echo 'extern "C" int LLVMFuzzerTestOneInput(const unsigned char*, unsigned long) { return 0; }' \
    >"$probe/probe.cpp"
  if ! clang++ -fsanitize=fuzzer,address "$probe/probe.cpp" -o "$probe/probe" 2>"$probe/err"; then
    echo "SKIP: clang cannot link libFuzzer (apt-get install libclang-rt-14-dev): $(head -1 "$probe/err")"
    rm -rf "$probe"
    exit 0
  fi
  rm -rf "$probe"
}
case "$mode" in
  build)
    src="$1" build="$2"
    skip_without_clang
    launcher=()
    command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
    # A tree configured already (by this script, or by hand as README shows) is only built.
    if ! grep -q '^APICLAB_FUZZ:BOOL=ON' "$build/CMakeCache.txt" 2>/dev/null; then
      cmake -S "$src" -B "$build" -G Ninja -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_C_COMPILER=clang \
        -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS=-O1 -DAPICLAB_FUZZ=ON -DAPICLAB_BUILD_GUI=OFF \
        -DAPICLAB_BUILD_TESTS=OFF -DAPICLAB_NATIVE=OFF "${launcher[@]}" >"$build.configure.log" 2>&1 || {
        cat "$build.configure.log"
        exit 1
      }
    fi
    exec cmake --build "$build" --target fuzz_scene fuzz_set fuzz_obj
    ;;
  run)
    target="$1" seconds="$2" src="$3" build="$4"
    skip_without_clang
    exe="$build/tests/fuzz/fuzz_$target"
    [ -x "$exe" ] || {
      echo "FAIL: $exe was not built (see the test fuzz.build)"
      exit 1
    }
    case "$target" in
      scene)
        # The shipped scenes but those too slow for an input's budget (too_slow_to_fuzz in
        # fuzz_targets.cpp says why).
        mkdir -p "$build/findings/scene-seeds" && rm -f "$build/findings/scene-seeds"/*
        find "$src/assets/scenes" -maxdepth 1 -name '*.json' ! -name eol-bunny-3d.json ! -name eol-two-balls-3d.json \
          -exec cp {} "$build/findings/scene-seeds/" \;
        seeds=("$build/findings/scene-seeds") dict="$src/tests/fuzz/scene.dict"
        ;;
      set) seeds=("$src/tests/fuzz/corpus/set") dict="$src/tests/fuzz/scene.dict" ;;
      obj) seeds=("$src/assets/meshes") dict="$src/tests/fuzz/obj.dict" ;;
    esac
    # The findings so far are seeds too: each must stay fixed.
    [ -d "$src/tests/fuzz_regressions/$target" ] && seeds+=("$src/tests/fuzz_regressions/$target")
    work="$build/findings/$target"
    rm -rf "$work" && mkdir -p "$work/corpus"
    # libFuzzer's timeout is wall time: on a loaded machine a 2 s input took 11 s (load 20), so a
    # hang here is an input over 30 s (the one-hour runs use 10 s and replay each timeout alone).
    "$exe" "$work/corpus" "${seeds[@]}" -dict="$dict" -max_total_time="$seconds" -timeout=30 \
      -rss_limit_mb=2048 -artifact_prefix="$work/" -print_final_stats=1 >"$work/log" 2>&1
    status=$?
    grep -E '^#[0-9]+ +(INITED|DONE)|stat::number_of_executed_units|Done [0-9]+ runs' "$work/log"
    if ((status != 0)); then
      tail -40 "$work/log"
      echo "FAIL: fuzz_$target found an input that crashes, hangs or leaks: $(ls "$work"/crash-* "$work"/timeout-* "$work"/leak-* "$work"/oom-* 2>/dev/null | head -1)"
      echo "      copy it to tests/fuzz_regressions/$target/, fix, and add a unit test"
      exit 1
    fi
    echo "PASS: fuzz_$target ran $seconds s without a finding"
    ;;
  *)
    echo "usage: fuzz_test.sh build SRC BUILD | run TARGET SECONDS SRC BUILD" >&2
    exit 2
    ;;
esac
