# The 3D paper scenes: particle counts, seeded rotations, mesh sampling, first frames.
add_executable(apiclab_paper_scenes_tests ${CMAKE_CURRENT_LIST_DIR}/test_paper_scenes.cpp)
target_link_libraries(apiclab_paper_scenes_tests PRIVATE apiclab_sim GTest::gtest_main)
target_compile_definitions(apiclab_paper_scenes_tests PRIVATE APICLAB_SOURCE_DIR="${CMAKE_SOURCE_DIR}")
apiclab_discover_tests(apiclab_paper_scenes_tests LABELS unit default)
