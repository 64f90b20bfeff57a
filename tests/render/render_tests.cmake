# Renderer tests (label "render", default tier), all headless: Mesa llvmpipe through EGL's surfaceless
# platform, and once more through OSMesa. Regenerate the golden images after an intended
# change with:  APICLAB_REGENERATE_GOLDEN=1 ctest --test-dir build -R render
if(NOT TARGET apiclab_render)
  return()
endif()

add_executable(test_render render/test_render.cpp)
target_link_libraries(test_render PRIVATE apiclab_render GTest::gtest)
target_compile_definitions(test_render PRIVATE APICLAB_SOURCE_DIR="${CMAKE_SOURCE_DIR}"
                           APICLAB_BINARY_DIR="${CMAKE_CURRENT_BINARY_DIR}")
apiclab_discover_tests(test_render TEST_PREFIX "render." EXTRA_ARGS --backend egl LABELS render default
                       PROPERTIES ENVIRONMENT "EGL_PLATFORM=surfaceless")
apiclab_discover_tests(test_render TEST_PREFIX "render_osmesa." EXTRA_ARGS --backend osmesa
                       LABELS render default)

# Not a test, and not built by default: cmake --build build --target render_bench
add_executable(render_bench EXCLUDE_FROM_ALL render/render_bench.cpp)
target_link_libraries(render_bench PRIVATE apiclab_render)

# The two commands through the real executable: frames, options, panes, CSVs, errors, video.
add_test(NAME render.cli COMMAND ${CMAKE_COMMAND} -E env APICLAB=$<TARGET_FILE:apiclab>
         bash ${CMAKE_CURRENT_SOURCE_DIR}/render/render_cli_tests.sh)
set_tests_properties(render.cli PROPERTIES LABELS "render;default" TIMEOUT 300)
# One colour and arrow scale per sequence: the first pass's scales given back as options draw
# the same frames.
add_test(NAME render.scales COMMAND ${CMAKE_COMMAND} -E env APICLAB=$<TARGET_FILE:apiclab>
         bash ${CMAKE_CURRENT_SOURCE_DIR}/render/render_scale_tests.sh)
set_tests_properties(render.scales PROPERTIES LABELS "render;default" TIMEOUT 300)
