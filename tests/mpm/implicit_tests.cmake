# Implicit integrators (midpoint, backward Euler): finite differences and conservation.
add_executable(apiclab_implicit_tests ${CMAKE_CURRENT_LIST_DIR}/test_implicit.cpp
                                      ${CMAKE_CURRENT_LIST_DIR}/test_stress_hessian.cpp)
target_link_libraries(apiclab_implicit_tests PRIVATE apiclab_sim GTest::gtest_main)
target_compile_definitions(apiclab_implicit_tests PRIVATE APICLAB_SOURCE_DIR="${CMAKE_SOURCE_DIR}")
apiclab_discover_tests(apiclab_implicit_tests LABELS unit default)

# The CG preconditioners of the implicit solve (block-Jacobi with deflation, mass).
add_executable(apiclab_cg_preconditioner_tests ${CMAKE_CURRENT_LIST_DIR}/test_cg_preconditioner.cpp)
target_link_libraries(apiclab_cg_preconditioner_tests PRIVATE apiclab_sim GTest::gtest_main)
target_compile_definitions(apiclab_cg_preconditioner_tests
                           PRIVATE APICLAB_SOURCE_DIR="${CMAKE_SOURCE_DIR}")
apiclab_discover_tests(apiclab_cg_preconditioner_tests LABELS unit default)
