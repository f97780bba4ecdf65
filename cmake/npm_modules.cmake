# The node modules of a test folder (web/tests, api/lint), pinned by its package-lock.json:
# `npm ci` when node_modules is missing or older than the lock file. Install scripts stay off:
# none of these modules needs one, and one of Spectral's dependencies (@scarf/scarf) would
# report the installation to its vendor. scripts/setup-debian.sh --with-test-data installs the
# same folders ahead (install_npm_test_modules).
function(oer_npm_ci npm folder)
    if(EXISTS ${folder}/node_modules/.package-lock.json AND
        NOT ${folder}/package-lock.json IS_NEWER_THAN ${folder}/node_modules/.package-lock.json)
        return()
    endif()
    execute_process(COMMAND ${npm} ci --ignore-scripts --no-audit --no-fund
        WORKING_DIRECTORY ${folder} RESULT_VARIABLE installed)
    if(NOT installed EQUAL 0)
        message(FATAL_ERROR "npm ci in ${folder} failed (${installed})")
    endif()
endfunction()
