#pragma once
// Memory measurements of this test process, shared by the unit and integration tests.
#include <cstddef>

// Defined when this build runs under AddressSanitizer: GCC defines __SANITIZE_ADDRESS__, clang
// answers __has_feature(address_sanitizer) instead.
#if defined(__SANITIZE_ADDRESS__)
#define OER_ADDRESS_SANITIZER 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define OER_ADDRESS_SANITIZER 1
#endif
#endif

namespace oer::testing {

// Whether the resident set measures the program's own memory. Not under AddressSanitizer: its
// redzones around every block, its shadow memory and its quarantine of freed blocks (up to
// 256 MiB) are resident too, so the tests that bound resident growth state their figure there
// without holding it to the bound.
#if defined(OER_ADDRESS_SANITIZER)
inline constexpr bool kResidentMemoryIsTheProgramsOwn = false;
#else
inline constexpr bool kResidentMemoryIsTheProgramsOwn = true;
#endif

// Bytes the heap has handed out and not taken back: memory kept, not memory that the allocator
// caches per thread for reuse, as the resident set would also count (glibc keeps up to 8 arenas
// per core, each holding freed blocks). Under AddressSanitizer, its own count of live bytes,
// which leaves out its quarantine of freed blocks.
std::size_t live_heap_bytes();

// Resident set size, KiB: also counts what the heap does not, such as JIT code and other
// mappings. Under AddressSanitizer it includes the quarantine (up to 256 MiB).
long resident_kib();

// The peak resident set size since the last reset_peak_resident() (or since the process
// started), KiB: /proc/self/status's VmHWM.
long peak_resident_kib();

// Sets the peak resident set size to the current one (writes 5 to /proc/self/clear_refs, Linux
// 4.0 and later), so that peak_resident_kib() measures what follows. False if the kernel refused;
// the peak then still counts from the process's start.
bool reset_peak_resident();

}  // namespace oer::testing
