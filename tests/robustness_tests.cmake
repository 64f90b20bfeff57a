# Robustness, all in the full tier (docs/testing.md: sanitizers, fuzzing, the GUI soak).
#
# The three libFuzzer targets, 60 s each from their seeds (label "fuzz"): fuzz.build builds
# them with clang into build/fuzz-build (a fixture), each fuzz.TARGET runs one. Without clang
# or libFuzzer every one prints "SKIP: ..." and passes.
set(APICLAB_FUZZ_BUILD_DIR ${CMAKE_BINARY_DIR}/fuzz-build
    CACHE PATH "Where fuzz.build builds the fuzz targets (an existing fuzz tree is reused)")
set(_fuzz_build ${APICLAB_FUZZ_BUILD_DIR})
set(_fuzz_script ${CMAKE_CURRENT_SOURCE_DIR}/fuzz/fuzz_test.sh)
add_test(NAME fuzz.build COMMAND bash ${_fuzz_script} build ${CMAKE_SOURCE_DIR} ${_fuzz_build})
# The timeout leaves room for a machine shared with other compiles (the ledger of build times:
# docs/testing.md).
set_tests_properties(fuzz.build PROPERTIES LABELS "fuzz;full" TIMEOUT 2400 FIXTURES_SETUP fuzz_targets
                                           SKIP_REGULAR_EXPRESSION "^SKIP:")
foreach(_target scene set obj)
  add_test(NAME fuzz.${_target}
           COMMAND bash ${_fuzz_script} run ${_target} 60 ${CMAKE_SOURCE_DIR} ${_fuzz_build})
  set_tests_properties(fuzz.${_target} PROPERTIES LABELS "fuzz;full" TIMEOUT 300
                       FIXTURES_REQUIRED fuzz_targets SKIP_REGULAR_EXPRESSION "^SKIP:")
endforeach()

# The GUI soak: random input for 2 minutes (full tier), and the 30-minute one (extended tier).
if(TARGET apiclab_imgui_glfw)
  add_test(NAME gui.soak
           COMMAND ${CMAKE_COMMAND} -E env APICLAB=$<TARGET_FILE:apiclab>
                   bash ${CMAKE_CURRENT_SOURCE_DIR}/gui/gui_soak.sh --seconds 120
                   --out ${CMAKE_CURRENT_BINARY_DIR}/gui-soak)
  # RUN_SERIAL: the frame-gap bound is wall time, and on CI's 2 cores the clang fuzz build beside
  # it starved the viewer to a 1.09 s frame at load 4.9 (0.37 s worst when it runs alone).
  set_tests_properties(gui.soak PROPERTIES LABELS "gui;soak;full" TIMEOUT 300 RUN_SERIAL TRUE
                                           SKIP_REGULAR_EXPRESSION "^SKIP:")
  add_test(NAME gui.soak_30min
           COMMAND ${CMAKE_COMMAND} -E env APICLAB=$<TARGET_FILE:apiclab>
                   bash ${CMAKE_CURRENT_SOURCE_DIR}/gui/gui_soak.sh --seconds 1800
                   --out ${CMAKE_CURRENT_BINARY_DIR}/gui-soak-30min)
  set_tests_properties(gui.soak_30min PROPERTIES LABELS "gui;soak;slow;extended" TIMEOUT 2400 RUN_SERIAL TRUE
                                                  SKIP_REGULAR_EXPRESSION "^SKIP:")
endif()

# The job pool (figures' thread pool, app/jobs.cpp) and the frame loop under ThreadSanitizer,
# as gui.tsan_worker does for the viewer's worker: app code and test instrumented, the solver
# library as built (each job's simulation is touched by one thread).
if(NOT APICLAB_TSAN)
  add_executable(test_app_core_tsan EXCLUDE_FROM_ALL app/test_app_core.cpp ${CMAKE_SOURCE_DIR}/app/jobs.cpp
                                    ${CMAKE_SOURCE_DIR}/app/lockstep.cpp
                                    ${CMAKE_SOURCE_DIR}/app/thread_pool.cpp
                                    ${CMAKE_SOURCE_DIR}/app/frame_loop.cpp
                                    ${CMAKE_SOURCE_DIR}/app/run_length.cpp
                                    ${CMAKE_SOURCE_DIR}/app/stop_signal.cpp
                                    ${CMAKE_SOURCE_DIR}/app/assets.cpp)
  target_include_directories(test_app_core_tsan PRIVATE ${CMAKE_SOURCE_DIR})
  target_compile_options(test_app_core_tsan PRIVATE -fsanitize=thread -g)
  target_link_options(test_app_core_tsan PRIVATE -fsanitize=thread)
  target_link_libraries(test_app_core_tsan PRIVATE apiclab_sim Threads::Threads GTest::gtest_main)
  target_compile_definitions(test_app_core_tsan PRIVATE APICLAB_SOURCE_DIR="${CMAKE_SOURCE_DIR}"
                                                        APICLAB_ASSETS_DIR="${APICLAB_ASSETS_DIR}")
  add_test(NAME app.tsan_jobs COMMAND ${CMAKE_COMMAND} -E env TSAN_OPTIONS=halt_on_error=1
                                      $<TARGET_FILE:test_app_core_tsan>)
  set_tests_properties(app.tsan_jobs PROPERTIES LABELS "sanitizer;full" TIMEOUT 300
                                                FIXTURES_REQUIRED full_build)
  list(APPEND APICLAB_FULL_TIER_TARGETS test_app_core_tsan)
endif()

# Every unit test and the worker's tests under AddressSanitizer + UBSan, in a build of their own
# (tests/asan_tests.sh).
add_test(NAME asan.unit_tests COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/asan_tests.sh
                                      ${CMAKE_SOURCE_DIR} ${CMAKE_BINARY_DIR}/asan)
set_tests_properties(asan.unit_tests PROPERTIES LABELS "sanitizer;slow;extended" TIMEOUT 5400)
