#pragma once
// Private: an allocator for the multi-megabyte per-pixel work buffers of the preprocessing.
//
// On the 2-core VMs this service runs on, every first touch of a 4 KiB page costs about 10 us
// (a page fault through the hypervisor): a fresh 8 MiB buffer (one float per pixel of a
// 2048x1024 map) took 21 ms to zero, more than the whole light location should. Large
// allocations are therefore mapped directly, aligned to 2 MiB and advised as transparent huge
// pages (MADV_HUGEPAGE), which makes the same buffer cost about 0.6 ms. Small allocations, and
// systems without madvise, fall back to operator new.
#include <cstddef>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

namespace oer::detail {

// Allocates at least bytes bytes, 2 MiB-aligned and advised for huge pages when bytes is at
// least large_allocation_bytes; throws std::bad_alloc on failure.
inline constexpr std::size_t large_allocation_bytes = std::size_t(1) << 21;
void* allocate_large(std::size_t bytes);
void deallocate_large(void* pointer, std::size_t bytes) noexcept;

template <class T>
struct LargeBufferAllocator {
    using value_type = T;
    LargeBufferAllocator() = default;
    template <class U>
    LargeBufferAllocator(const LargeBufferAllocator<U>&) noexcept {}

    T* allocate(std::size_t n) {
        if (n > std::size_t(-1) / sizeof(T)) {
            throw std::bad_array_new_length();
        }
        return static_cast<T*>(allocate_large(n * sizeof(T)));
    }
    void deallocate(T* p, std::size_t n) noexcept { deallocate_large(p, n * sizeof(T)); }

    // Default-initialises (no zeroing pass over buffers that are about to be overwritten):
    // LargeBuffer<float>(n) holds indeterminate values until written.
    template <class U>
    void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) {
        ::new (static_cast<void*>(p)) U;
    }
    template <class U, class... Args>
    void construct(U* p, Args&&... args) {
        ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
    }

    template <class U>
    bool operator==(const LargeBufferAllocator<U>&) const noexcept {
        return true;
    }
};

template <class T>
using LargeBuffer = std::vector<T, LargeBufferAllocator<T>>;

}  // namespace oer::detail
