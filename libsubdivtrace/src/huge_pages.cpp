#include "huge_pages.h"

#include <cstdint>

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

}  // namespace subdivtrace::detail
