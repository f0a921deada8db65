# cmake -D TEST_EXECUTABLE=... -D OUTPUT=... -P gtest_suites.cmake: lists the GoogleTest suites
# of a test binary, one per line, into OUTPUT (run after each build of the binary; ctest reads
# the list through the include file inlight_add_module writes: a ctest test per suite).
execute_process(COMMAND "${TEST_EXECUTABLE}" --gtest_list_tests
    OUTPUT_VARIABLE listing RESULT_VARIABLE rc TIMEOUT 60)
if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${TEST_EXECUTABLE} --gtest_list_tests failed (${rc}):\n${listing}")
endif()
string(REPLACE "\n" ";" lines "${listing}")
set(suites "")
foreach(line IN LISTS lines)
    # "Suite." or "Prefix/Suite.  # TypeParam = ...": a suite; indented lines are its tests.
    if(line MATCHES "^([A-Za-z_][A-Za-z0-9_/]*)\\.( |$)")
        string(APPEND suites "${CMAKE_MATCH_1}\n")
    endif()
endforeach()
if(suites STREQUAL "")
    message(FATAL_ERROR "${TEST_EXECUTABLE}: no GoogleTest suite listed")
endif()
file(WRITE "${OUTPUT}.tmp" "${suites}")
file(RENAME "${OUTPUT}.tmp" "${OUTPUT}")
