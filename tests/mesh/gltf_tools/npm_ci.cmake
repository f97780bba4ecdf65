# glTF-Transform's CLI in this folder, pinned by package-lock.json, installed when missing or
# older than the lock file (cmake/npm_modules.cmake), for tests/mesh/compressed_gltf_tools_test.cpp:
#   cmake -DNPM=npm -DFOLDER=tests/mesh/gltf_tools -P npm_ci.cmake
foreach(variable NPM FOLDER)
    if(NOT DEFINED ${variable} OR ${variable} MATCHES "NOTFOUND$")
        message(FATAL_ERROR "npm_ci.cmake: ${variable} is not set; run "
            "scripts/setup-debian.sh --with-test-data, then configure again")
    endif()
endforeach()
include(${CMAKE_CURRENT_LIST_DIR}/../../../cmake/npm_modules.cmake)
oer_npm_ci(${NPM} ${FOLDER})
