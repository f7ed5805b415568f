// The huge-page helpers (huge_pages.h) only advise the kernel: whatever it
// does with the advice, the arrays must hold exactly what std::vector's own
// reserve, assign and resize give, kept elements included.
#include <cstdint>
#include <numeric>
#include <vector>

#include <catch2/catch.hpp>

#include "huge_pages.h"

using namespace subdivtrace::detail;

TEST_CASE("huge-page reserve, assign and resize keep std::vector's contents", "[huge_pages]") {
    // 24 MB: whole huge pages inside, and a start that is not 2 MB aligned.
    const std::size_t n = std::size_t{3} << 20;
    std::vector<std::uint64_t> kept(1000);
    std::iota(kept.begin(), kept.end(), 7);
    reserve_huge(kept, n);
    REQUIRE(kept.capacity() >= n);
    REQUIRE(kept.size() == 1000);
    for (std::size_t i = 0; i < kept.size(); ++i) CHECK(kept[i] == 7 + i);

    std::vector<std::uint64_t> filled{1, 2, 3};
    assign_huge(filled, n, std::uint64_t{42});
    REQUIRE(filled.size() == n);
    std::size_t wrong = 0;
    for (std::uint64_t x : filled) wrong += x != 42;
    CHECK(wrong == 0);
    // Smaller than it holds: no new block, the same values.
    assign_huge(filled, 10, std::uint64_t{5});
    CHECK(filled == std::vector<std::uint64_t>(10, 5));

    std::vector<double> grown(5, 1.5);
    resize_huge(grown, n);
    REQUIRE(grown.size() == n);
    std::size_t zeros = 0;
    for (std::size_t i = 5; i < n; ++i) zeros += grown[i] == 0.0;
    CHECK(zeros == n - 5);
    CHECK(grown[4] == 1.5);

    // Advice on nothing, or on a small array, changes nothing and fails nowhere.
    advise_huge_pages(nullptr, n);
    std::vector<char> small(100, 'x');
    advise_huge_pages(small.data(), small.size());
    CHECK(small == std::vector<char>(100, 'x'));
}

TEST_CASE("HugeArray keeps its contents as it grows across the block sizes", "[huge_pages]") {
    // From operator new's blocks through mappings of their own below one
    // huge page (k_own_mapping_bytes) to several huge pages: every element
    // survives each reallocation, and every block is aligned for any type.
    HugeArray<std::uint64_t> grown;
    std::size_t last_capacity = 0, reallocations = 0;
    const std::size_t n = 3 * k_huge_block_bytes / sizeof(std::uint64_t);
    for (std::uint64_t i = 0; i < n; ++i) {
        grown.push_back(i * 2654435761u);
        if (grown.capacity() != last_capacity) {
            last_capacity = grown.capacity();
            ++reallocations;
            CHECK(reinterpret_cast<std::uintptr_t>(grown.data()) % 16 == 0);
        }
    }
    CHECK(reallocations > 10);  // it crossed both thresholds
    std::size_t wrong = 0;
    for (std::uint64_t i = 0; i < n; ++i) wrong += grown[i] != i * 2654435761u;
    CHECK(wrong == 0);

    // Exactly at the thresholds, and one element either side of them.
    for (const std::size_t bytes : {k_own_mapping_bytes, k_huge_block_bytes}) {
        for (const std::size_t count : {bytes / 8 - 1, bytes / 8, bytes / 8 + 1}) {
            HugeArray<std::uint64_t> a(count, 9);
            CHECK(a.size() == count);
            CHECK(a.front() == 9);
            CHECK(a.back() == 9);
        }
    }
}
