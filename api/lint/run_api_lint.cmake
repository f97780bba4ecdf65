# Lints api/openapi.yaml (the ctest api_lint, tests/CMakeLists.txt) with Redocly's recommended
# rules (redocly.yaml, .redocly.lint-ignore.yaml) and Spectral's spectral:oas (.spectral.yaml),
# both pinned by package-lock.json and installed first when needed; fails on any error of
# either and on any warning of Spectral:
#   cmake -DNODE=node -DNPM=npm -DLINT_DIR=api/lint -P run_api_lint.cmake
foreach(variable NODE NPM LINT_DIR)
    if(NOT DEFINED ${variable})
        message(FATAL_ERROR "run_api_lint.cmake: ${variable} is not set")
    endif()
endforeach()
foreach(program NODE NPM)
    if(NOT ${program} OR ${program} MATCHES "NOTFOUND$")
        message(FATAL_ERROR "run_api_lint.cmake: no ${program} found when the build was "
            "configured; run scripts/setup-debian.sh --with-test-data, then configure again")
    endif()
endforeach()
include(${CMAKE_CURRENT_LIST_DIR}/../../cmake/npm_modules.cmake)
oer_npm_ci(${NPM} ${LINT_DIR})

# No usage reports, no update notices: a test talks to no one.
set(ENV{REDOCLY_TELEMETRY} off)
set(ENV{REDOCLY_SUPPRESS_UPDATE_NOTICE} true)
execute_process(COMMAND ${NODE} node_modules/@redocly/cli/bin/cli.js lint ../openapi.yaml
    --config redocly.yaml --format=stylish
    WORKING_DIRECTORY ${LINT_DIR} RESULT_VARIABLE redocly)
execute_process(COMMAND ${NODE} node_modules/@stoplight/spectral-cli/dist/index.js lint
    --ruleset .spectral.yaml --fail-severity=warn ../openapi.yaml
    WORKING_DIRECTORY ${LINT_DIR} RESULT_VARIABLE spectral)
if(NOT redocly EQUAL 0 OR NOT spectral EQUAL 0)
    message(FATAL_ERROR "api/openapi.yaml does not pass its linters (redocly: ${redocly}, "
        "spectral: ${spectral})")
endif()
