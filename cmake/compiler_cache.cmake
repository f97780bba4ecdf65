# Compiler caching with ccache, where it is installed (scripts/setup-debian.sh installs it): a
# rebuild of unchanged sources on the same machine costs a hash per file instead of a compile,
# across build folders and clones. ccache stays correct because it keys each object on the
# compiler, its flags and the preprocessed or hashed sources and headers, and it never caches
# a failure. base_dir is this source tree, so that paths inside it are hashed relative to it
# and two clones at different paths (or a worktree) share their objects.
# The tests' precompiled headers (tests/CMakeLists.txt) are cached too, as ccache's manual asks:
# sloppiness pch_defines and time_macros, the header included with -include (CMake's way).
# OER_COMPILER_CACHE=OFF builds without it.
find_program(OER_CCACHE_PROGRAM ccache)
option(OER_COMPILER_CACHE "Compile through ccache when it is installed" ON)
if(OER_COMPILER_CACHE AND OER_CCACHE_PROGRAM)
    set(oer_launcher ${CMAKE_COMMAND} -E env CCACHE_BASEDIR=${PROJECT_SOURCE_DIR}
        CCACHE_SLOPPINESS=pch_defines,time_macros ${OER_CCACHE_PROGRAM})
    set(CMAKE_CXX_COMPILER_LAUNCHER ${oer_launcher})
    set(CMAKE_C_COMPILER_LAUNCHER ${oer_launcher})
endif()
