# Runs browser_test.mjs (the ctest `browser`, tests/CMakeLists.txt), installing playwright-core
# from package-lock.json first when needed (cmake/npm_modules.cmake; scripts/setup-debian.sh
# does the same with --with-test-data):
#   cmake -DNODE=node -DNPM=npm -DTESTS_DIR=web/tests -DSERVER=oer-server -DARTIFACTS=dir -P ...
foreach(variable NODE NPM TESTS_DIR SERVER ARTIFACTS)
    if(NOT DEFINED ${variable})
        message(FATAL_ERROR "run_browser_test.cmake: ${variable} is not set")
    endif()
endforeach()
foreach(program NODE NPM)
    if(NOT ${program} OR ${program} MATCHES "NOTFOUND$")
        message(FATAL_ERROR "run_browser_test.cmake: no ${program} found when the build was "
            "configured; run scripts/setup-debian.sh --with-test-data, then configure again")
    endif()
endforeach()
if(NOT EXISTS /usr/bin/chromium)
    message(FATAL_ERROR "run_browser_test.cmake: /usr/bin/chromium is missing; run "
        "scripts/setup-debian.sh --with-test-data")
endif()
include(${CMAKE_CURRENT_LIST_DIR}/../../cmake/npm_modules.cmake)
oer_npm_ci(${NPM} ${TESTS_DIR})
execute_process(COMMAND ${NODE} ${TESTS_DIR}/browser_test.mjs --server ${SERVER}
    --artifacts ${ARTIFACTS} RESULT_VARIABLE result)
if(NOT result EQUAL 0)
    message(FATAL_ERROR "browser_test.mjs failed (${result})")
endif()
