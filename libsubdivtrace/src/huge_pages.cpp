#include "huge_pages.h"

#include <cstdint>
#include <new>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace subdivtrace::detail {

void advise_huge_pages(const void* data, std::size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    constexpr std::uintptr_t k_huge = std::uintptr_t{2} << 20;
    if (data == nullptr || bytes < k_huge) return;
    // The whole huge pages the array touches, not only those inside it: a
    // large block is a mapping of its own that the kernel aligns to 2 MB,
    // and the array starts just past the allocator's header in its first
    // page. What else those pages hold is only advised too.
    const auto begin = reinterpret_cast<std::uintptr_t>(data);
    const std::uintptr_t first = begin & ~(k_huge - 1);
    const std::uintptr_t last = (begin + bytes + k_huge - 1) & ~(k_huge - 1);
    // Errors (no transparent huge pages; a page not mapped) change nothing.
    madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);
#else
    (void)data;
    (void)bytes;
#endif
}

namespace {

std::size_t mapping_bytes(std::size_t bytes) {
    return (bytes + k_huge_block_bytes - 1) & ~(k_huge_block_bytes - 1);
}

}  // namespace

void* allocate_huge_block(std::size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    if (bytes >= k_own_mapping_bytes) {
        const std::size_t size = mapping_bytes(bytes);
        if (size < bytes) throw std::bad_alloc();  // wrapped around
        // Map 2 MB more than needed, then unmap what lies outside the
        // aligned block (the kernel does not promise alignment).
        void* raw = mmap(nullptr, size + k_huge_block_bytes, PROT_READ | PROT_WRITE,
                         MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
        if (raw == MAP_FAILED) throw std::bad_alloc();
        const auto start = reinterpret_cast<std::uintptr_t>(raw);
        const std::uintptr_t aligned = (start + k_huge_block_bytes - 1) & ~(k_huge_block_bytes - 1);
        if (aligned > start) munmap(raw, aligned - start);
        const std::uintptr_t end = start + size + k_huge_block_bytes;
        if (end > aligned + size) munmap(reinterpret_cast<void*>(aligned + size), end - (aligned + size));
        void* block = reinterpret_cast<void*>(aligned);
        madvise(block, size, MADV_HUGEPAGE);  // advice: errors change nothing
        return block;
    }
#endif
    return ::operator new(bytes);
}

void free_huge_block(void* block, std::size_t bytes) noexcept {
    if (block == nullptr) return;
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    if (bytes >= k_own_mapping_bytes) {
        munmap(block, mapping_bytes(bytes));
        return;
    }
#endif
    ::operator delete(block);
}

}  // namespace subdivtrace::detail
