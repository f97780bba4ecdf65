#include "process_memory.hpp"

#include <fstream>
#include <string>

#include <malloc.h>
#include <unistd.h>

#if defined(OER_ADDRESS_SANITIZER)
// Declared in <sanitizer/allocator_interface.h>, which GCC 12 does not ship.
extern "C" std::size_t __sanitizer_get_current_allocated_bytes();
#endif

namespace oer::testing {

std::size_t live_heap_bytes() {
#if defined(OER_ADDRESS_SANITIZER)
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

long peak_resident_kib() {
    std::ifstream status("/proc/self/status");
    std::string key;
    long value = 0;
    while (status >> key) {
        if (key == "VmHWM:") {
            status >> value;
            return value;
        }
        status.ignore(1 << 10, '\n');
    }
    return 0;
}

bool reset_peak_resident() {
    std::ofstream clear_refs("/proc/self/clear_refs");
    clear_refs << "5";
    clear_refs.flush();
    return bool(clear_refs);
}

}  // namespace oer::testing
