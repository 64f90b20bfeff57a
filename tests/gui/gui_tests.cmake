# GUI tests. Label "gui", default tier: the headless worker tests (scheme switch, reset,
# blow-up, handoff) and the Xvfb smoke test (skips with a message when xvfb-run is missing).
# Full tier: the worker's handoff test under ThreadSanitizer, partly instrumented
# (gui.tsan_worker) and in a ThreadSanitizer build of its own (gui.tsan_handoff); by hand:
#   cmake -S . -B build-tsan -G Ninja -DAPICLAB_TSAN=ON && ninja -C build-tsan test_gui_worker &&
#   build-tsan/tests/test_gui_worker
add_executable(test_gui_worker app/test_gui_worker.cpp)
target_link_libraries(test_gui_worker PRIVATE apiclab_app_core GTest::gtest_main)
target_compile_definitions(test_gui_worker PRIVATE APICLAB_SOURCE_DIR="${CMAKE_SOURCE_DIR}")
apiclab_discover_tests(test_gui_worker TEST_PREFIX "gui." LABELS gui default)

# The worker's handoff under ThreadSanitizer, cheaply: the worker, the lockstep and the test
# instrumented, the solver library as built (its code runs on the worker thread alone, and what
# it makes is handed over through the worker's code, which TSAN sees). gui.tsan_handoff
# instruments everything.
if(NOT APICLAB_TSAN)
  add_executable(test_gui_worker_tsan EXCLUDE_FROM_ALL app/test_gui_worker.cpp ${CMAKE_SOURCE_DIR}/app/sim_worker.cpp
                                      ${CMAKE_SOURCE_DIR}/app/lockstep.cpp
                                      ${CMAKE_SOURCE_DIR}/app/thread_pool.cpp
                                      ${CMAKE_SOURCE_DIR}/app/frame_loop.cpp
                                      ${CMAKE_SOURCE_DIR}/app/run_length.cpp
                                      ${CMAKE_SOURCE_DIR}/app/stop_signal.cpp)
  target_include_directories(test_gui_worker_tsan PRIVATE ${CMAKE_SOURCE_DIR})
  target_compile_options(test_gui_worker_tsan PRIVATE -fsanitize=thread -g)
  target_link_options(test_gui_worker_tsan PRIVATE -fsanitize=thread)
  target_link_libraries(test_gui_worker_tsan PRIVATE apiclab_sim Threads::Threads GTest::gtest_main)
  target_compile_definitions(test_gui_worker_tsan PRIVATE APICLAB_SOURCE_DIR="${CMAKE_SOURCE_DIR}")
  add_test(NAME gui.tsan_worker COMMAND ${CMAKE_COMMAND} -E env TSAN_OPTIONS=halt_on_error=1
                                        $<TARGET_FILE:test_gui_worker_tsan>)
  set_tests_properties(gui.tsan_worker PROPERTIES LABELS "gui;sanitizer;full" TIMEOUT 300
                                                 FIXTURES_REQUIRED full_build)
  list(APPEND APICLAB_FULL_TIER_TARGETS test_gui_worker_tsan)
endif()

# The loops the commands share (app/frame_loop, lockstep, jobs; sim/measure/run_summary.hpp).
add_executable(test_app_core app/test_app_core.cpp)
target_link_libraries(test_app_core PRIVATE apiclab_app_core GTest::gtest_main)
target_compile_definitions(test_app_core PRIVATE APICLAB_SOURCE_DIR="${CMAKE_SOURCE_DIR}")
apiclab_discover_tests(test_app_core TEST_PREFIX "app." LABELS unit default)
# What a run hands a person: exact fixed steps, drift series, sidecars, run summary.
add_executable(test_outputs app/test_outputs.cpp)
target_link_libraries(test_outputs PRIVATE apiclab_app_core GTest::gtest_main)
target_compile_definitions(test_outputs PRIVATE APICLAB_SOURCE_DIR="${CMAKE_SOURCE_DIR}")
apiclab_discover_tests(test_outputs TEST_PREFIX "app." LABELS unit default)

# --dump formats read back: VTK, PLY, OBJ, CSV, series.pvd.
add_executable(test_particle_export app/test_particle_export.cpp)
target_link_libraries(test_particle_export PRIVATE apiclab_app_core GTest::gtest_main)
target_compile_definitions(test_particle_export PRIVATE APICLAB_SOURCE_DIR="${CMAKE_SOURCE_DIR}")
if(ZLIB_FOUND)  # the test reads the zlib blocks back itself
  target_link_libraries(test_particle_export PRIVATE ZLIB::ZLIB)
  target_compile_definitions(test_particle_export PRIVATE APICLAB_HAVE_ZLIB)
endif()
apiclab_discover_tests(test_particle_export TEST_PREFIX "app." LABELS unit default)

# The plot widget headless: its legend never covers a curve (ImGui without a renderer).
if(TARGET apiclab_charts)
  add_executable(test_plot_legend app/test_plot_legend.cpp)
  target_link_libraries(test_plot_legend PRIVATE apiclab_charts GTest::gtest_main)
  apiclab_discover_tests(test_plot_legend TEST_PREFIX "gui." LABELS unit default)
endif()

if(NOT TARGET apiclab_imgui_glfw)
  return()
endif()
add_executable(gui_screenshot_check gui/test_gui_screenshot_check.cpp)
target_link_libraries(gui_screenshot_check PRIVATE apiclab_render)
add_test(NAME gui.smoke
         COMMAND ${CMAKE_COMMAND} -E env APICLAB=$<TARGET_FILE:apiclab> CHECK=$<TARGET_FILE:gui_screenshot_check>
                 bash ${CMAKE_CURRENT_SOURCE_DIR}/gui/test_gui_smoke.sh ${CMAKE_CURRENT_BINARY_DIR}/gui-smoke)
set_tests_properties(gui.smoke PROPERTIES LABELS "gui;default" TIMEOUT 120 SKIP_REGULAR_EXPRESSION "^SKIP:")
# A 25,000-character scene description: shown cut to a few lines, the viewer does not abort.
add_test(NAME gui.long_description
         COMMAND ${CMAKE_COMMAND} -E env APICLAB=$<TARGET_FILE:apiclab>
                 bash ${CMAKE_CURRENT_SOURCE_DIR}/gui/test_gui_long_text.sh ${CMAKE_SOURCE_DIR}
                 ${CMAKE_CURRENT_BINARY_DIR}/gui-long-text)
set_tests_properties(gui.long_description PROPERTIES LABELS "gui;default" TIMEOUT 150
                                                     SKIP_REGULAR_EXPRESSION "^SKIP:")
# gui --sweep: bad folders (one line, exit 2) and, under Xvfb, a run beside its reference.
add_test(NAME gui.sweep
         COMMAND ${CMAKE_COMMAND} -E env APICLAB=$<TARGET_FILE:apiclab> CHECK=$<TARGET_FILE:gui_screenshot_check>
                 bash ${CMAKE_CURRENT_SOURCE_DIR}/gui/test_gui_sweep.sh ${CMAKE_CURRENT_BINARY_DIR}/sweep-view
                 ${CMAKE_CURRENT_BINARY_DIR}/gui-sweep)
set_tests_properties(gui.sweep PROPERTIES LABELS "gui;default" TIMEOUT 120 SKIP_REGULAR_EXPRESSION "^SKIP:"
                                          FIXTURES_REQUIRED sweep_view)
# Checkpoints in the viewer: a pane saved resumes with run --resume; a run's checkpoint opens.
add_test(NAME gui.checkpoint
         COMMAND ${CMAKE_COMMAND} -E env APICLAB=$<TARGET_FILE:apiclab> CHECK=$<TARGET_FILE:gui_screenshot_check>
                 bash ${CMAKE_CURRENT_SOURCE_DIR}/gui/test_gui_checkpoint.sh ${CMAKE_CURRENT_BINARY_DIR}/gui-checkpoint)
set_tests_properties(gui.checkpoint PROPERTIES LABELS "gui;default" TIMEOUT 120 SKIP_REGULAR_EXPRESSION "^SKIP:")

if(NOT APICLAB_TSAN)
  add_test(NAME gui.tsan_handoff
           COMMAND bash -c "cmake -S '${CMAKE_SOURCE_DIR}' -B '${CMAKE_BINARY_DIR}/tsan' -G Ninja -DAPICLAB_TSAN=ON \
-DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null && cmake --build '${CMAKE_BINARY_DIR}/tsan' --target test_gui_worker -j2 \
&& TSAN_OPTIONS=halt_on_error=1 '${CMAKE_BINARY_DIR}/tsan/tests/test_gui_worker'")
  set_tests_properties(gui.tsan_handoff PROPERTIES LABELS "gui;sanitizer;slow;extended" TIMEOUT 1800)
endif()
