# Linking with LLVM's lld where it is installed (scripts/setup-debian.sh installs it): GNU ld
# takes several seconds over each test executable, and a test build links some thirty of them
# (with the sanitizers' runtime, 354 s of CPU of a clean sanitizer build went to linking).
# OER_FAST_LINKER=OFF links with the compiler's default linker.
find_program(OER_LLD_PROGRAM ld.lld)
option(OER_FAST_LINKER "Link with lld when it is installed" ON)
if(OER_FAST_LINKER AND OER_LLD_PROGRAM)
    add_link_options(-fuse-ld=lld)
endif()
