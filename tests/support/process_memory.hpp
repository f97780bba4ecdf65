#pragma once
// Memory measurements of this test process, shared by the unit and integration tests.
#include <cstddef>

namespace oer::testing {

// Bytes the heap has handed out and not taken back: memory kept, not memory that the allocator
// caches per thread for reuse, as the resident set would also count (glibc keeps up to 8 arenas
// per core, each holding freed blocks). Under AddressSanitizer, its own count of live bytes,
// which leaves out its quarantine of freed blocks.
std::size_t live_heap_bytes();

// Resident set size, KiB: also counts what the heap does not, such as JIT code and other
// mappings. Under AddressSanitizer it includes the quarantine (up to 256 MiB).
long resident_kib();

}  // namespace oer::testing
