#pragma once
// Large arrays on transparent huge pages. The kernel maps fresh memory a
// 4 kB page at a time, each on a fault; on the virtual machines we measure
// on a fault costs about 10 us, and uniform subdivision to level 4 (arrays
// of 5-90 MB, each written once) spent more time in them than subdividing
// (docs/benchmarks.md, "Huge pages for uniform subdivision"). Advised
// before its first write, a large array faults once per 2 MB. Embree
// allocates its BVH the same way.
//
// Arrays of our own (a level's topology, scratch) take HugeArray, whose
// large blocks are mappings of their own, aligned to 2 MB and advised
// before use: every page of them is huge. Arrays handed to callers are
// std::vectors; reserve_huge and its kin advise those where they lie, which
// helps where the allocator mapped them afresh and not where it reuses
// memory it already touched.

#include <cstddef>
#include <vector>

namespace subdivtrace::detail {

/// The size of a huge page.
constexpr std::size_t k_huge_block_bytes = std::size_t{2} << 20;
/// Blocks from 256 kB up are mappings of their own (allocate_huge_block),
/// rounded up to whole huge pages. Below 2 MB that keeps up to twice the
/// block's bytes (a huge page is allocated whole on its first write), but a
/// level's per-vertex arrays are 0.3-2 MB: as operator new's they faulted
/// a 4 kB page at a time, about 10 us each here, and were most of uniform
/// subdivision's faults (docs/benchmarks.md, "Page faults in uniform
/// subdivision").
constexpr std::size_t k_own_mapping_bytes = std::size_t{256} << 10;

/// `bytes` of memory aligned to 16 bytes: from k_own_mapping_bytes up a
/// mapping of its own aligned to 2 MB and advised onto huge pages, below
/// that operator new's. Throws std::bad_alloc when there is none.
void* allocate_huge_block(std::size_t bytes);
/// Frees a block of allocate_huge_block(bytes).
void free_huge_block(void* block, std::size_t bytes) noexcept;

/// std::allocator, with large blocks on huge pages (allocate_huge_block).
template <class T>
struct HugePageAllocator {
    using value_type = T;
    HugePageAllocator() = default;
    template <class U>
    HugePageAllocator(const HugePageAllocator<U>&) noexcept {}
    T* allocate(std::size_t n) { return static_cast<T*>(allocate_huge_block(n * sizeof(T))); }
    void deallocate(T* p, std::size_t n) noexcept { free_huge_block(p, n * sizeof(T)); }
    template <class U>
    bool operator==(const HugePageAllocator<U>&) const noexcept { return true; }
    template <class U>
    bool operator!=(const HugePageAllocator<U>&) const noexcept { return false; }
};

/// An array of our own that may grow large (a level's topology, scratch).
template <class T>
using HugeArray = std::vector<T, HugePageAllocator<T>>;

/// Asks the kernel to back the whole 2 MB pages inside [data, data + bytes)
/// with huge pages. Advice only: where the kernel has none (or the range
/// holds no whole huge page) nothing changes.
void advise_huge_pages(const void* data, std::size_t bytes);

/// Room for n elements in v, advised before anything writes it: call before
/// filling v (resize, assign, push_back). Nothing if v has the room already.
template <class T>
void reserve_huge(std::vector<T>& v, std::size_t n) {
    if (n <= v.capacity()) return;
    v.reserve(n);
    advise_huge_pages(v.data(), n * sizeof(T));
}

/// v.assign(n, value) on advised memory.
template <class T>
void assign_huge(std::vector<T>& v, std::size_t n, const T& value) {
    if (n > v.capacity()) std::vector<T>().swap(v);  // nothing to copy into the new block
    reserve_huge(v, n);
    v.assign(n, value);
}

/// v.resize(n) (new elements value-initialised) on advised memory.
template <class T>
void resize_huge(std::vector<T>& v, std::size_t n) {
    reserve_huge(v, n);
    v.resize(n);
}

}  // namespace subdivtrace::detail
