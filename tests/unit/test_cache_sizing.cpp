// The cache's working limit (lru_cache.h): the budget is a ceiling, and the
// cache keeps only what its lookups need below it. Truths are counted by
// hand: a cyclic scan over W entries in an LRU cache smaller than W misses on
// every lookup, and in one that holds W misses on none.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cstddef>
#include <utility>

#include "lru_cache.h"
#include "node_address.h"

using namespace subdivtrace;

namespace {

struct MixHash {  // spreads consecutive keys over the shards
    std::size_t operator()(int k) const { return static_cast<std::size_t>(detail::mix64(static_cast<std::uint64_t>(k))); }
};
using Cache = detail::ShardedLruCache<int, int, MixHash>;

/// What each entry owns beyond its bookkeeping: about a tile's size.
constexpr std::size_t k_owned = 16 << 10;
constexpr std::size_t k_cost = Cache::k_entry_bytes + k_owned;

/// Looks up keys [first, first + count) in order; returns the misses.
std::uint64_t scan(Cache& cache, detail::CacheOwnerTally& owner, int first, int count) {
    const std::uint64_t before = cache.counters().misses;
    for (int k = first; k < first + count; ++k)
        cache.lookup_or_build(k, owner, [k] { return std::make_pair(k, k_owned); });
    return cache.counters().misses - before;
}

}  // namespace

TEST_CASE("the cache grows to a working set that comes back, then stops missing",
          "[cache][memory]") {
    // Entries of about 16 kB, four times the start (about 2,000: 33 MB), a
    // quarter of the budget.
    const std::size_t budget = std::size_t{128} << 20;
    Cache cache(budget);
    detail::CacheOwnerTally owner;
    REQUIRE(cache.limit() == Cache::k_start_limit);
    const int working_set = static_cast<int>(4 * Cache::k_start_limit / k_cost) + 64;
    REQUIRE(working_set * k_cost > 4 * Cache::k_start_limit);
    // How many of the set each shard holds: the limit's bound below.
    std::size_t per_shard[Cache::k_shards] = {};
    for (int k = 0; k < working_set; ++k) ++per_shard[Cache::shard_index(k)];
    const std::size_t busiest = *std::max_element(per_shard, per_shard + Cache::k_shards);
    INFO("busiest shard holds " << busiest << " of " << working_set);
    REQUIRE(2 * Cache::k_shards * (busiest + 1) * k_cost < budget);

    // The first pass misses on every entry, and cannot re-miss.
    CHECK(scan(cache, owner, 0, working_set) == working_set);
    CHECK(cache.counters().remisses == 0);
    CHECK(cache.counters().evictions > 0);
    // Later passes re-miss on what the small limit dropped, which grows it
    // until the whole set fits; then a pass misses on nothing.
    std::uint64_t last = working_set;
    int passes = 1;
    while (last > 0 && passes < 50) {
        last = scan(cache, owner, 0, working_set);
        ++passes;
    }
    INFO("passes " << passes << ", limit " << cache.limit());
    CHECK(last == 0);
    CHECK(cache.counters().remisses > 0);
    CHECK(cache.limit() >= working_set * k_cost);
    CHECK(cache.limit() <= budget);
    // It grows only on a re-miss, which needs a shard whose share of the
    // limit is below its part of the set, and at most doubles at a time: so
    // it ends below twice what the busiest shard's part needs in every shard.
    CHECK(cache.limit() <= 2 * Cache::k_shards * (busiest + 1) * k_cost);
    // A further pass still hits everything: the limit stays.
    const std::size_t grown = cache.limit();
    CHECK(scan(cache, owner, 0, working_set) == 0);
    CHECK(cache.limit() == grown);
}

TEST_CASE("keys never asked for again do not grow the cache", "[cache][memory]") {
    // A stream of distinct keys (a render whose rays never come back to a
    // dropped tile): every lookup misses, none re-misses, and the limit stays
    // where it started, as does what the cache holds.
    Cache cache(std::size_t{256} << 20);
    detail::CacheOwnerTally owner;
    const int stream = 8192;  // 134 MB of entries passing through
    CHECK(scan(cache, owner, 0, stream) == stream);
    const detail::CacheCounters c = cache.counters();
    CHECK(c.remisses == 0);
    CHECK(c.limit == Cache::k_start_limit);
    CHECK(c.evictions > 0);
    // Each shard keeps its share, or its two newest entries if that is more.
    CHECK(c.peak_bytes <= Cache::k_start_limit + 2 * Cache::k_shards * k_cost);
}

TEST_CASE("the working limit never passes the budget", "[cache][memory]") {
    // A working set four times the budget re-misses on every pass: the
    // limit climbs to the budget and stops there.
    const std::size_t budget = std::size_t{8} << 20;
    Cache cache(budget);
    detail::CacheOwnerTally owner;
    const int working_set = static_cast<int>(4 * budget / k_cost);
    for (int pass = 0; pass < 6; ++pass) scan(cache, owner, 0, working_set);
    const detail::CacheCounters c = cache.counters();
    CHECK(c.limit == budget);
    CHECK(c.remisses > 0);
    CHECK(c.peak_bytes <= budget + 2 * Cache::k_shards * k_cost);
    // Lowering the budget lowers the limit with it; the next insertions evict down to it.
    cache.set_budget(budget / 4);
    CHECK(cache.limit() == budget / 4);
    scan(cache, owner, working_set, working_set);
    CHECK(cache.counters().bytes <= budget / 4 + 2 * Cache::k_shards * k_cost);
}

TEST_CASE("a whole-budget cache keeps its budget from the start", "[cache][memory]") {
    const std::size_t budget = std::size_t{32} << 20;
    Cache cache(budget, true);
    detail::CacheOwnerTally owner;
    CHECK(cache.limit() == budget);
    // 1,024 entries of 16 kB fit: the second pass hits everything, nothing was dropped.
    scan(cache, owner, 0, 1024);
    CHECK(scan(cache, owner, 0, 1024) == 0);
    CHECK(cache.counters().evictions == 0);
    // A budget below the start: the limit is the budget.
    Cache small(std::size_t{1} << 20);
    CHECK(small.limit() == std::size_t{1} << 20);
}
