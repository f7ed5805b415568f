#pragma once
// Large arrays on transparent huge pages. The kernel maps fresh memory a
// 4 kB page at a time, each on a fault; on the virtual machines we measure
// on a fault costs about 10 us, and uniform subdivision to level 4 (arrays
// of 5-90 MB, each written once) spent more time in them than subdividing
// (docs/benchmarks.md, "Huge pages"). Advised before its first write, a
// large array faults once per 2 MB. Embree allocates its BVH the same way.

#include <cstddef>
#include <vector>

namespace subdivtrace::detail {

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
