#include "large_buffer.hpp"

#include <cstdint>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace oer::detail {

namespace {

constexpr std::size_t huge_page = std::size_t(2) << 20;

std::size_t round_up(std::size_t bytes) {
    return (bytes + huge_page - 1) & ~(huge_page - 1);
}

}  // namespace

void* allocate_large(std::size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    if (bytes >= large_allocation_bytes) {
        const std::size_t size = round_up(bytes);
        if (size < bytes || size > std::size_t(-1) - huge_page) {
            throw std::bad_alloc();
        }
        // Map one huge page more than needed, then unmap the unaligned head and the tail.
        void* raw = mmap(nullptr, size + huge_page, PROT_READ | PROT_WRITE,
                         MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
        if (raw == MAP_FAILED) {
            throw std::bad_alloc();
        }
        const auto start = reinterpret_cast<std::uintptr_t>(raw);
        const std::uintptr_t aligned = (start + huge_page - 1) & ~std::uintptr_t(huge_page - 1);
        if (aligned > start) {
            munmap(raw, aligned - start);
        }
        const std::size_t tail = (start + size + huge_page) - (aligned + size);
        if (tail > 0) {
            munmap(reinterpret_cast<void*>(aligned + size), tail);
        }
        void* pointer = reinterpret_cast<void*>(aligned);
        madvise(pointer, size, MADV_HUGEPAGE);  // advice only: failure leaves normal pages
        return pointer;
    }
#endif
    return ::operator new(bytes);
}

void deallocate_large(void* pointer, std::size_t bytes) noexcept {
    if (pointer == nullptr) {
        return;
    }
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    if (bytes >= large_allocation_bytes) {
        munmap(pointer, round_up(bytes));
        return;
    }
#endif
    ::operator delete(pointer);
}

}  // namespace oer::detail
