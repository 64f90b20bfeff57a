# Every test of the build tree carries exactly one tier label (docs/testing.md): a test with
# none would run in no tier, one with two would run twice. tests/CMakeLists.txt refuses to
# configure such an add_test; this script also sees the GoogleTest cases, which
# gtest_discover_tests registers only after their binary is built (ctest test "tiers").
# Usage: cmake -DCTEST=ctest -DBUILD_DIR=build -DTIERS="default;full;extended" -P tiers_check.cmake

cmake_minimum_required(VERSION 3.22)

# Test names as `ctest -N` lists them; -FA keeps ctest from adding fixture set-ups of other tiers.
function(list_tests out)
  execute_process(COMMAND "${CTEST}" --test-dir "${BUILD_DIR}" -N -FA ".*" ${ARGN}
                  OUTPUT_VARIABLE text RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "ctest -N ${ARGN} failed in ${BUILD_DIR}")
  endif()
  string(REGEX MATCHALL "Test +#[0-9]+: [^\n]+" lines "${text}")
  set(names "")
  foreach(line IN LISTS lines)
    string(REGEX REPLACE "^Test +#[0-9]+: " "" name "${line}")
    list(APPEND names "${name}")
  endforeach()
  set(${out} "${names}" PARENT_SCOPE)
endfunction()

list_tests(all)
list(LENGTH all count)
if(count EQUAL 0)
  message(FATAL_ERROR "no tests found in ${BUILD_DIR}")
endif()
foreach(tier IN LISTS TIERS)
  list_tests(in_${tier} -L "^${tier}$")
  list(LENGTH in_${tier} n)
  message(STATUS "${tier}: ${n} tests")
endforeach()

set(bad "")
foreach(name IN LISTS all)
  set(n 0)
  foreach(tier IN LISTS TIERS)
    if(name IN_LIST in_${tier})
      math(EXPR n "${n} + 1")
    endif()
  endforeach()
  if(NOT n EQUAL 1)
    list(APPEND bad "${name} (${n} tiers)")
  endif()
endforeach()
if(bad)
  list(JOIN bad "\n  " bad)
  message(FATAL_ERROR "tests without exactly one tier label (${TIERS}):\n  ${bad}")
endif()
message(STATUS "PASS: each of the ${count} tests carries exactly one of ${TIERS}")
