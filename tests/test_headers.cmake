# The test binaries' precompiled headers (tests/precompiled.hpp), built by a target with no
# definitions of its own: GCC uses a precompiled header only where every macro defined when it
# was built is defined alike. The top-level CMakeLists.txt includes this file before the solver's
# directory, so that Ninja, which starts ready jobs in the order the build file lists them,
# compiles the header early instead of leaving a core idle while the test files wait for it.
find_package(GTest REQUIRED)
if(APICLAB_PRECOMPILED_HEADERS)
  file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/tests_precompiled.cpp "")
  add_library(apiclab_test_headers OBJECT ${CMAKE_CURRENT_BINARY_DIR}/tests_precompiled.cpp)
  target_link_libraries(apiclab_test_headers PRIVATE apiclab_sim GTest::gtest)
  target_precompile_headers(apiclab_test_headers PRIVATE ${CMAKE_CURRENT_LIST_DIR}/precompiled.hpp)
endif()
