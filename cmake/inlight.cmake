# Helpers that keep each module's and tool's CMakeLists.txt to a few lines (like Mitsuba's add_plugin).

add_library(inlight_warnings INTERFACE)
target_compile_options(inlight_warnings INTERFACE -Wall -Wextra -Wpedantic
    $<IF:$<CXX_COMPILER_ID:GNU>,-Wshadow=local,-Wshadow-uncaptured-local>
    -Wnon-virtual-dtor -Wno-unused-parameter)
if(INLIGHT_WARNINGS_AS_ERRORS)
    target_compile_options(inlight_warnings INTERFACE -Werror)
endif()
if(INLIGHT_SANITIZE)
    target_compile_options(inlight_warnings INTERFACE -fsanitize=${INLIGHT_SANITIZE}
        -fno-omit-frame-pointer -fno-sanitize-recover=all)
    target_link_options(inlight_warnings INTERFACE -fsanitize=${INLIGHT_SANITIZE})
endif()

# Where tests find ../shared/data and the Debian data packages; tests skip when absent.
get_filename_component(INLIGHT_SHARED_DIR "${CMAKE_SOURCE_DIR}/../shared" ABSOLUTE)
set(INLIGHT_TEST_ENV
    "INLIGHT_SHARED_DIR=${INLIGHT_SHARED_DIR}"
    "INLIGHT_SOURCE_DIR=${CMAKE_SOURCE_DIR}"
    "INLIGHT_BIN=${CMAKE_BINARY_DIR}/bin")

# inlight_add_gtest_suites(name): a ctest test "<name>.<Suite>" (label unit) per GoogleTest suite
# of inlight_<name>_test, run by tests/gtest_suite.sh: one process per suite rather than per test
# (gtest_discover_tests), since each start of a test binary costs ~0.6 s of library loading. The
# suites are listed after each build (cmake/gtest_suites.cmake); ctest reads that list.
function(inlight_add_gtest_suites name)
    set(target inlight_${name}_test)
    set(list_file ${CMAKE_CURRENT_BINARY_DIR}/${target}_suites.txt)
    set(include_file ${CMAKE_CURRENT_BINARY_DIR}/${target}_suites.cmake)
    add_custom_command(TARGET ${target} POST_BUILD
        COMMAND ${CMAKE_COMMAND} -D TEST_EXECUTABLE=$<TARGET_FILE:${target}> -D OUTPUT=${list_file}
                -P ${PROJECT_SOURCE_DIR}/cmake/gtest_suites.cmake
        VERBATIM)
    file(WRITE ${include_file} "
if(EXISTS [==[${list_file}]==])
    file(STRINGS [==[${list_file}]==] suites)
    foreach(suite IN LISTS suites)
        add_test(${name}.\${suite} bash [==[${PROJECT_SOURCE_DIR}/tests/gtest_suite.sh]==]
                 [==[${CMAKE_BINARY_DIR}/tests/${target}]==] \${suite})
        set_tests_properties(${name}.\${suite} PROPERTIES LABELS unit SKIP_RETURN_CODE 77
                             ENVIRONMENT [==[${INLIGHT_TEST_ENV}]==])
    endforeach()
else()
    add_test(${target}_NOT_BUILT ${target}_NOT_BUILT)
endif()
")
    set_property(DIRECTORY APPEND PROPERTY TEST_INCLUDE_FILES ${include_file})
endfunction()

# inlight_add_module(name SOURCES ... [PUBLIC_DEPS ...] [PRIVATE_DEPS ...] [TEST_DEPS ...])
# Builds static library inlight_<name> (alias inlight::<name>) and, when <name>_test.cpp files
# exist beside it, the test binary inlight_<name>_test registered with ctest under label "unit".
function(inlight_add_module name)
    cmake_parse_arguments(ARG "" "" "SOURCES;PUBLIC_DEPS;PRIVATE_DEPS;TESTS;TEST_DEPS" ${ARGN})
    add_library(inlight_${name} STATIC ${ARG_SOURCES})
    add_library(inlight::${name} ALIAS inlight_${name})
    target_include_directories(inlight_${name} PUBLIC ${PROJECT_SOURCE_DIR}/lib)
    target_link_libraries(inlight_${name} PUBLIC ${ARG_PUBLIC_DEPS}
        PRIVATE inlight_warnings ${ARG_PRIVATE_DEPS})
    if(INLIGHT_BUILD_TESTS)
        file(GLOB tests CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/*_test.cpp)
        if(tests)
            add_executable(inlight_${name}_test ${tests})
            target_link_libraries(inlight_${name}_test PRIVATE inlight_${name} inlight_testing
                ${ARG_TEST_DEPS} inlight_warnings GTest::gtest_main)
            set_target_properties(inlight_${name}_test PROPERTIES
                RUNTIME_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/tests)
            inlight_add_gtest_suites(${name})
        endif()
    endif()
endfunction()

# inlight_add_tool(name [SOURCES ...] DEPS ...): apps/<name>/main.cpp (and a subcommand per
# SOURCES file) -> build/bin/<name>
function(inlight_add_tool name)
    cmake_parse_arguments(ARG "" "" "SOURCES;DEPS" ${ARGN})
    add_executable(${name} main.cpp ${ARG_SOURCES})
    target_link_libraries(${name} PRIVATE ${ARG_DEPS} inlight::core inlight_warnings)
endfunction()

# inlight_add_bench(name SOURCES ... DEPS ...): a Google Benchmark binary in build/bench
function(inlight_add_bench name)
    cmake_parse_arguments(ARG "" "" "SOURCES;DEPS" ${ARGN})
    if(NOT INLIGHT_BUILD_BENCH)
        return()
    endif()
    add_executable(${name} ${ARG_SOURCES})
    target_link_libraries(${name} PRIVATE ${ARG_DEPS} benchmark::benchmark inlight_warnings)
    set_target_properties(${name} PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/bench)
endfunction()

# inlight_add_subdirectories(): add_subdirectory() every child folder that has a CMakeLists.txt,
# in sorted order (lib/, apps/ and tests/ pick up new modules, tools and test folders this way).
function(inlight_add_subdirectories)
    file(GLOB children LIST_DIRECTORIES true RELATIVE ${CMAKE_CURRENT_SOURCE_DIR} *)
    list(SORT children)
    foreach(child ${children})
        if(IS_DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/${child}
           AND EXISTS ${CMAKE_CURRENT_SOURCE_DIR}/${child}/CMakeLists.txt)
            add_subdirectory(${child})
        endif()
    endforeach()
endfunction()

# inlight_add_cli_tests(prefix): every *_test.sh beside the calling CMakeLists.txt becomes the
# ctest test <prefix>.<script>, labelled "cli" (and "slow" when its name says so), run with bash
# and the test environment (INLIGHT_BIN, INLIGHT_SHARED_DIR, INLIGHT_TEST_BIN, ...). Exit code 77
# (tests/cli/lib.sh's finish after a skip: ../shared or a data package absent) is reported by
# ctest as skipped, not passed.
# A hang guard, not a speed test: 300 s is several times the longest CLI test on 2 idle cores. A machine shared
# by many builds (load 20-30) can need more; raise it there, e.g. -DINLIGHT_CLI_TEST_TIMEOUT_S=900.
set(INLIGHT_CLI_TEST_TIMEOUT_S 300 CACHE STRING "ctest timeout of each non-slow CLI test script, in seconds")
function(inlight_add_cli_tests prefix)
    file(GLOB scripts CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/*_test.sh)
    foreach(script ${scripts})
        get_filename_component(name ${script} NAME_WE)
        set(labels cli)
        set(timeout ${INLIGHT_CLI_TEST_TIMEOUT_S})
        # ctest -j starts the costliest tests first; without a previous run's cost data (a fresh
        # build, as in CI) it orders by COST, so the slow scripts (minutes each) start at once
        # instead of last, where they would leave the other cores idle at the end.
        set(cost 10)
        if(name MATCHES "slow")
            set(labels cli slow)
            set(timeout 1500)  # slow tests run apart from the batch, often on a loaded machine
            set(cost 100)
        endif()
        add_test(NAME ${prefix}.${name} COMMAND bash ${script})
        set_tests_properties(${prefix}.${name} PROPERTIES LABELS "${labels}"
            ENVIRONMENT "${INLIGHT_TEST_ENV};INLIGHT_TEST_BIN=${CMAKE_BINARY_DIR}/tests"
            TIMEOUT ${timeout} SKIP_RETURN_CODE 77 COST ${cost})
    endforeach()
endfunction()
