# `apiclab figures --quick` through the real executable (label "render"): every PNG and CSV
# is written, the PNGs are not blank and show each scheme's color, each CSV has its header
# and one series per scheme (render.figures); render.figures_data adds the full Figs 3, 5, 6,
# 11 and the two-ring energy table against the numbers of docs/data/figures.csv and
# docs/data/two-ring-energy.csv (17 s of full runs: a slow validation).
if(NOT TARGET apiclab_charts)
  return()
endif()

add_executable(figures_png_check render/figures_png_check.cpp)
target_link_libraries(figures_png_check PRIVATE apiclab_render)
add_test(NAME render.figures
         COMMAND ${CMAKE_COMMAND} -E env APICLAB=$<TARGET_FILE:apiclab> CHECK=$<TARGET_FILE:figures_png_check>
                 bash ${CMAKE_CURRENT_SOURCE_DIR}/render/figures_tests.sh ${CMAKE_CURRENT_BINARY_DIR}/figures-quick
                 ${CMAKE_SOURCE_DIR}/docs/data quick)
set_tests_properties(render.figures PROPERTIES LABELS "render" TIMEOUT 300)
add_test(NAME render.figures_data
         COMMAND ${CMAKE_COMMAND} -E env APICLAB=$<TARGET_FILE:apiclab> CHECK=$<TARGET_FILE:figures_png_check>
                 bash ${CMAKE_CURRENT_SOURCE_DIR}/render/figures_tests.sh ${CMAKE_CURRENT_BINARY_DIR}/figures-data
                 ${CMAKE_SOURCE_DIR}/docs/data)
set_tests_properties(render.figures_data PROPERTIES LABELS "render" TIMEOUT 300)
