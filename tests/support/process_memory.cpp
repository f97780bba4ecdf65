#include "process_memory.hpp"

#include <fstream>

#include <malloc.h>
#include <unistd.h>

#if defined(__SANITIZE_ADDRESS__)
// Declared in <sanitizer/allocator_interface.h>, which GCC 12 does not ship.
extern "C" std::size_t __sanitizer_get_current_allocated_bytes();
#endif

namespace oer::testing {

std::size_t live_heap_bytes() {
#if defined(__SANITIZE_ADDRESS__)
    return __sanitizer_get_current_allocated_bytes();  // ASan replaces glibc's allocator
#else
    const struct mallinfo2 heap = mallinfo2();
    return heap.uordblks + heap.hblkhd;  // in arenas, plus blocks mmap-ed on their own
#endif
}

long resident_kib() {
    std::ifstream statm("/proc/self/statm");
    long size = 0, resident = 0;
    statm >> size >> resident;
    return resident * (sysconf(_SC_PAGESIZE) / 1024);
}

}  // namespace oer::testing
