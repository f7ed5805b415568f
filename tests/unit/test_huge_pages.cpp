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
