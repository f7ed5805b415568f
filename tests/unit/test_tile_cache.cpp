// The scene-wide tile cache (tile_cache.h, DESIGN.md section 5 "Memory"):
// surfaces sharing one cache see exactly what each sees with its own, the
// cache keeps one budget across them and evicts across them, a surface's
// tiles leave with it, and lookup_or_build builds each tile once however many
// threads ask for it at the same time.
#include <catch2/catch.hpp>

#include <atomic>
#include <stdexcept>
#include <thread>
#include <vector>

#include <glm/common.hpp>

#include "lru_cache.h"
#include "node_address.h"
#include "render/render_loop.h"
#include "subdivtrace/hierarchy.h"
#include "subdivtrace/tile_cache.h"
#include "subdivtrace/tracer.h"
#include "test_meshes.h"

using namespace subdivtrace;
using namespace subdivtrace::tools;  // the standalone renderer (Camera, render)

namespace {

/// Every node down to `depth` of the first `faces` base triangles, depth first.
void walk(const Hierarchy& h, std::uint32_t faces, int depth) {
    std::vector<NodeId> stack;
    for (std::uint32_t f = 0; f < faces; ++f) stack.push_back(Hierarchy::root(f));
    std::array<NodeRecord, 4> children;
    while (!stack.empty()) {
        const NodeId id = stack.back();
        stack.pop_back();
        if (id.level >= depth) continue;
        h.children(id, children);
        for (int c = 0; c < 4; ++c) stack.push_back(child_of(id, c));
    }
}

Camera close_camera() {
    Camera cam;
    cam.look_from = Vec3(0.5, 1.5, 2.2);
    cam.look_at = Vec3(0.6, 0.0, 0.0);
    cam.width = 64;
    cam.height = 48;
    return cam;
}

/// Two surfaces in one picture (the nearest hit of either), so every thread's
/// rays move between them all the time.
std::vector<float> render_pair(const AdaptiveSurface& a, const AdaptiveSurface& b, int threads) {
    const Camera cam = close_camera();
    RenderOptions ro;
    ro.threads = threads;
    RenderStats rs;
    Bounds3 bounds = a.bounds();
    bounds.lo = glm::min(bounds.lo, b.bounds().lo);
    bounds.hi = glm::max(bounds.hi, b.bounds().hi);
    return render(
               [&](const Ray& r, Hit& h) {
                   Hit hb;
                   const bool in_a = a.intersect(r, h);
                   Ray rb = r;
                   if (in_a) rb.t_max = h.t;
                   if (b.intersect(rb, hb)) {
                       h = hb;
                       return true;
                   }
                   return in_a;
               },
               cam, ro, bounds, rs)
        .rgb;
}

SurfaceOptions pair_options(std::shared_ptr<TileCache> cache, std::size_t cache_mb) {
    SurfaceOptions o;
    o.max_level = 7;
    o.cache = std::move(cache);
    o.cache_mb = cache_mb;
    o.view.camera = close_camera().look_from;
    o.view.pixel_angle = close_camera().pixel_angle();
    return o;
}

}  // namespace

TEST_CASE("surfaces sharing one small cache render what each renders with its own",
          "[cache][memory][threads]") {
    const Mesh torus = testmesh::torus(8, 6, 1.0, 0.35);
    Mesh sphere = testmesh::icosphere(1);
    for (Vec3& p : sphere.positions) p = 0.4 * p + Vec3(0.9, 0.3, 0.2);

    // Truth: each surface with a roomy cache of its own, kept whole, one thread.
    const auto roomy = [] { return std::make_shared<TileCache>(std::size_t{512} << 20, TileCache::Sizing::whole_budget); };
    const AdaptiveSurface own_t(torus, pair_options(roomy(), 512));
    const AdaptiveSurface own_s(sphere, pair_options(roomy(), 512));
    const std::vector<float> reference = render_pair(own_t, own_s, 1);
    CHECK(own_t.stats().cache_evictions == 0);
    CHECK(own_t.stats().shared_cache.surfaces == 1);

    for (const std::size_t budget : {std::size_t{1}, std::size_t{256} << 10}) {
        for (const int threads : {1, 3}) {
            INFO("budget " << budget << " bytes, " << threads << " threads");
            auto cache = std::make_shared<TileCache>(budget);
            const AdaptiveSurface t(torus, pair_options(cache, 512));
            const AdaptiveSurface s(sphere, pair_options(cache, 512));
            CHECK(render_pair(t, s, threads) == reference);
            const TileCacheStats c = cache->stats();
            CHECK(c.surfaces == 2);
            CHECK(c.evictions > 0);  // the budget is far below what the picture needs
            CHECK(c.duplicate_builds == 0);
            // The cache's own counters are the surfaces' summed.
            const SurfaceStats st = t.stats(), ss = s.stats();
            CHECK(st.cache_evictions + ss.cache_evictions == c.evictions);
            CHECK(st.cache_bytes + ss.cache_bytes == c.bytes);
            CHECK(st.trace.cache_misses + ss.trace.cache_misses == c.misses);
            CHECK(st.trace.cache_hits + ss.trace.cache_hits == c.hits + c.waits);
            CHECK(st.shared_cache.peak_bytes == c.peak_bytes);
            CHECK(st.cache_evictions > 0);  // both surfaces lose tiles to each other
            CHECK(ss.cache_evictions > 0);
        }
    }
}

TEST_CASE("a shared cache keeps one budget across surfaces, evicting the least recent",
          "[cache][memory]") {
    const Mesh mesh = testmesh::icosphere(2);
    // What one walk costs, measured with room to spare; the shared budget
    // then holds it once and a half.
    const Hierarchy probe(mesh, SchemeKind::normal, 7, std::size_t{256} << 20);
    walk(probe, 20, 5);
    const std::size_t need = probe.counters().bytes;
    const std::size_t budget = need * 3 / 2;
    // Each of the 64 shards keeps budget / 64 and at least 2 tiles: the
    // total may pass the budget by those 128 tiles. The largest are tiles
    // built to their deepest level, which keep the band their child tiles
    // start from: their mean, measured, twice over for their spread.
    const Hierarchy deepest(mesh, SchemeKind::normal, 7, std::size_t{256} << 20);
    walk(deepest, 160, 3);
    const std::size_t largest_tile = 2 * deepest.counters().bytes / deepest.counters().tiles_built;
    const std::size_t slack = 128 * largest_tile;
    auto cache = std::make_shared<TileCache>(budget);
    auto a = std::make_unique<Hierarchy>(mesh, SchemeKind::normal, 7, cache);
    const Hierarchy b(mesh, SchemeKind::normal, 7, cache);
    CHECK(cache->stats().surfaces == 2);

    walk(*a, 20, 5);
    const HierarchyCounters a_alone = a->counters();
    // Shards fill unevenly, so a few of its tiles may already have gone.
    CHECK(a_alone.bytes >= need * 9 / 10);
    CHECK(cache->stats().bytes == a_alone.bytes);

    // b's walk needs the same again and more: the budget holds, and what goes
    // is a's (least recently used), not b's.
    walk(b, 80, 5);
    const TileCacheStats c = cache->stats();
    const HierarchyCounters a_after = a->counters(), b_after = b.counters();
    CHECK(c.evictions > 0);
    CHECK(a_after.evictions > 0);
    CHECK(a_after.bytes < a_alone.bytes);
    CHECK(a_after.bytes + b_after.bytes == c.bytes);
    // Each of the 64 shards keeps budget / 64 and at least 2 tiles, so the
    // total can pass the budget by at most those 128 tiles.
    CHECK(c.bytes <= budget + slack);
    CHECK(c.peak_bytes >= c.bytes);
    CHECK(c.peak_bytes <= budget + slack);

    // A destroyed surface's tiles leave the cache with it.
    a.reset();
    const TileCacheStats gone = cache->stats();
    CHECK(gone.surfaces == 1);
    CHECK(gone.bytes == b.counters().bytes);

    // A smaller budget applies from the next insertion on.
    cache->set_budget(1);
    CHECK(cache->budget() == 1);
    walk(b, 160, 3);
    CHECK(cache->stats().bytes <= slack);
}

TEST_CASE("lookup_or_build builds each tile once however many threads ask at once",
          "[cache][threads]") {
    const Mesh mesh = testmesh::icosphere(2);
    // Truth: the tiles and records one thread builds for the walk.
    // Caches that keep their whole budget from the start: nothing is evicted,
    // so every tile is built exactly once.
    const auto roomy = [] { return std::make_shared<TileCache>(std::size_t{256} << 20, TileCache::Sizing::whole_budget); };
    const Hierarchy alone(mesh, SchemeKind::normal, 6, roomy());
    walk(alone, 80, 5);
    const HierarchyCounters truth = alone.counters();
    REQUIRE(truth.node_misses > 100);

    // Four threads walk the same nodes in the same order at the same time, so
    // they keep asking for tiles another is building.
    auto cache = roomy();
    const Hierarchy shared(mesh, SchemeKind::normal, 6, cache);
    std::atomic<int> ready{0};
    std::vector<std::thread> threads;
    for (int k = 0; k < 4; ++k)
        threads.emplace_back([&] {
            ++ready;
            while (ready.load() < 4) {
            }
            walk(shared, 80, 5);
        });
    for (std::thread& t : threads) t.join();
    const TileCacheStats c = cache->stats();
    const HierarchyCounters h = shared.counters();
    // Every tile built exactly once. A miss on a base triangle's tile builds
    // its chunk's other tiles too, unless another thread builds them, so the
    // misses themselves depend on timing: tiles built and insertions do not.
    CHECK(h.tiles_built == truth.tiles_built);
    CHECK(c.insertions == truth.tiles_built);
    CHECK(h.node_misses == c.misses);
    CHECK(c.misses <= truth.tiles_built);
    CHECK(h.nodes_built == truth.nodes_built);
    CHECK(c.duplicate_builds == 0);
    CHECK(c.evictions == 0);
}

TEST_CASE("a failed build reaches the thread that waited for it and caches nothing",
          "[cache][threads]") {
    struct IntHash {
        std::size_t operator()(int k) const { return static_cast<std::size_t>(k) << 7; }
    };
    detail::ShardedLruCache<int, int, IntHash> cache(1 << 20);
    detail::CacheOwnerTally owner;
    std::atomic<bool> building{false}, release{false};
    std::atomic<int> waiter_saw{0};
    std::thread builder([&] {
        CHECK_THROWS_AS(cache.lookup_or_build(7, owner,
                                              [&]() -> std::pair<int, std::size_t> {
                                                  building = true;
                                                  while (!release.load()) std::this_thread::yield();
                                                  throw std::runtime_error("out of memory");
                                              }),
                        std::runtime_error);
    });
    while (!building.load()) std::this_thread::yield();
    // The builder holds the pending entry until released, so the waiter finds
    // it and waits.
    std::thread waiter([&] {
        try {
            cache.lookup_or_build(7, owner, [] { return std::make_pair(1, std::size_t{0}); });
            waiter_saw = 1;
        } catch (const std::runtime_error&) {
            waiter_saw = 2;
        }
    });
    while (cache.counters().waits == 0) std::this_thread::yield();
    release = true;
    builder.join();
    waiter.join();
    CHECK(waiter_saw.load() == 2);
    // Nothing failed is cached: the next lookup builds.
    const int v = cache.lookup_or_build(7, owner, [] { return std::make_pair(42, std::size_t{0}); });
    CHECK(v == 42);
    CHECK(cache.counters().misses == 2);
    CHECK(cache.counters().duplicate_builds == 0);
}

TEST_CASE("a grown entry is charged its new size, within the budget", "[cache][memory]") {
    // Tiles build their levels after they are cached; the cache is told
    // (recharge) and charges what they hold, evicting to keep its budget.
    struct MixHash {  // spreads consecutive keys over the shards
        std::size_t operator()(int k) const { return static_cast<std::size_t>(detail::mix64(static_cast<std::uint64_t>(k))); }
    };
    using Cache = detail::ShardedLruCache<int, int, MixHash>;
    const std::size_t entry = Cache::k_entry_bytes;
    const std::size_t budget = Cache::k_shards * 8 * (entry + 100);
    Cache cache(budget);
    detail::CacheOwnerTally owner;
    const int count = static_cast<int>(Cache::k_shards * 2);
    for (int k = 0; k < count; ++k) cache.lookup_or_build(k, owner, [&] { return std::make_pair(k, std::size_t{100}); });
    REQUIRE(cache.counters().evictions == 0);
    CHECK(cache.counters().bytes == count * (entry + 100));

    // Another value under the key, or a key not cached: nothing changes.
    cache.recharge(0, [](int v) { return v != 0; }, 5000);
    cache.recharge(-1, [](int) { return true; }, 5000);
    CHECK(cache.counters().bytes == count * (entry + 100));
    CHECK(owner.bytes.load() == count * (entry + 100));

    // Growing and shrinking one entry moves the totals by exactly that much.
    cache.recharge(1, [](int v) { return v == 1; }, 700);
    CHECK(cache.counters().bytes == count * (entry + 100) + 600);
    cache.recharge(1, [](int v) { return v == 1; }, 100);
    CHECK(cache.counters().bytes == count * (entry + 100));
    CHECK(owner.bytes.load() == count * (entry + 100));

    // A charge is the value's size, whatever was reported before: shrinking
    // an entry charged 100 to 40 (its growth to 7,000 was never told, as
    // when a value grows before it is inserted) leaves it charged 40, and
    // nothing is evicted. Told as a change from 7,000 to 40, the shard's
    // count wrapped below zero and it evicted every entry but two.
    cache.recharge(2, [](int v) { return v == 2; }, 40);
    CHECK(cache.counters().bytes == count * (entry + 100) - 60);
    CHECK(owner.bytes.load() == count * (entry + 100) - 60);
    CHECK(cache.counters().evictions == 0);
    cache.recharge(2, [](int v) { return v == 2; }, 100);

    // Every entry grows tenfold: the cache evicts to stay within its budget
    // (each shard keeps at least 2 entries).
    for (int k = 0; k < count; ++k) cache.recharge(k, [k](int v) { return v == k; }, 1000);
    const detail::CacheCounters c = cache.counters();
    CHECK(c.evictions > 0);
    CHECK(c.bytes <= budget + 2 * Cache::k_shards * (entry + 1000));
    CHECK(c.peak_bytes >= c.bytes);
    CHECK(owner.bytes.load() == c.bytes);
    CHECK(owner.evictions.load() == c.evictions);
}
