# Writes the ctest entries of a GoogleTest executable, one per test suite (run after the
# executable is built: tests/CMakeLists.txt's oer_add_tests). One process per suite, not per
# test as gtest_discover_tests makes them: every process of a test executable first loads some
# 260 shared libraries (OpenImageIO's dependencies), 0.65 s of CPU, 1 s under the sanitizers,
# which across 700 tests was a quarter of the test run.
#
# A suite's tests whose full name contains "Slow" are an entry of their own, "<Suite>.Slow",
# labelled "<LABEL>-slow" with a 900 s timeout; the rest are "<Suite>", labelled LABEL.
#
#   cmake -DEXECUTABLE=... -DOUTPUT=... -DLABEL=... -DTIMEOUT=... [-DEXCLUDED=SuiteA;SuiteB]
#         -P gtest_suites.cmake
# EXCLUDED: suites that have entries of their own (SERIAL_SUITES).

cmake_minimum_required(VERSION 3.25)

execute_process(COMMAND "${EXECUTABLE}" --gtest_list_tests
    OUTPUT_VARIABLE listing
    RESULT_VARIABLE result
    TIMEOUT 60)
if(NOT result EQUAL 0)
    message(FATAL_ERROR "${EXECUTABLE} --gtest_list_tests failed (${result}):\n${listing}")
endif()

# The listing: "Suite." on a line of its own, then "  Test" per test; typed and parameterised
# tests add "  # ..." comments, which are dropped.
string(REPLACE "\n" ";" lines "${listing}")
set(suites "")
foreach(line IN LISTS lines)
    if(line MATCHES "^([A-Za-z_][A-Za-z0-9_/]*)\\.")
        set(suite "${CMAKE_MATCH_1}")
        # A parameterised suite is listed as "Instantiation/Suite".
        string(REGEX REPLACE "^.*/" "" suite_base "${suite}")
        if(NOT suite_base IN_LIST EXCLUDED)
            list(APPEND suites "${suite}")
            set(has_fast_${suite} FALSE)
            set(has_slow_${suite} FALSE)
        endif()
    elseif(line MATCHES "^  ([A-Za-z0-9_/]+)" AND DEFINED has_fast_${suite})
        if("${suite}.${CMAKE_MATCH_1}" MATCHES "Slow")
            set(has_slow_${suite} TRUE)
        else()
            set(has_fast_${suite} TRUE)
        endif()
    endif()
endforeach()
list(REMOVE_DUPLICATES suites)

set(content "")
foreach(suite IN LISTS suites)
    if(has_fast_${suite})
        string(APPEND content
            "add_test([=[${suite}]=] \"${EXECUTABLE}\" [=[--gtest_filter=${suite}.*-*Slow*]=])\n"
            "set_tests_properties([=[${suite}]=] PROPERTIES LABELS [=[${LABEL}]=] "
            "TIMEOUT ${TIMEOUT})\n")
    endif()
    if(has_slow_${suite})
        # A suite named Slow is slow whole; otherwise its tests named Slow are.
        if(suite MATCHES "Slow")
            set(slow_filter "${suite}.*")
        else()
            set(slow_filter "${suite}.*Slow*")
        endif()
        string(APPEND content
            "add_test([=[${suite}.Slow]=] \"${EXECUTABLE}\" [=[--gtest_filter=${slow_filter}]=])\n"
            "set_tests_properties([=[${suite}.Slow]=] PROPERTIES LABELS [=[${LABEL}-slow]=] "
            "TIMEOUT 900)\n")
    endif()
endforeach()
file(WRITE "${OUTPUT}" "${content}")
