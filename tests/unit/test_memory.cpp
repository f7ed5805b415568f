// What the surface reports it holds (SurfaceStats::memory and the cache
// counters) against counts made by hand from the mesh: the parts outside the
// cache are exact for a known mesh, the per-thread fronts come and go with
// their threads, and evictions count tiles.
#include <catch2/catch.hpp>

#include <random>
#include <thread>

#include <glm/geometric.hpp>

#include "subdivtrace/hierarchy.h"
#include "subdivtrace/tracer.h"
#include "test_meshes.h"

using namespace subdivtrace;

namespace {

/// Rays from a close camera towards random points of the mesh's bounding box:
/// close enough that they refine several levels.
void trace_close_rays(const AdaptiveSurface& surface, unsigned seed, int count) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-0.8, 0.8);
    for (int k = 0; k < count; ++k) {
        Ray ray;
        ray.origin = Vec3(0.3, 0.2, 1.6);
        ray.direction = Vec3(u(rng), u(rng), 0.0) - ray.origin;
        Hit hit;
        surface.intersect(ray, hit);
    }
}

SurfaceOptions close_view_options() {
    SurfaceOptions o;
    o.scheme = SchemeKind::normal;
    o.max_level = 6;
    o.view.camera = Vec3(0.3, 0.2, 1.6);
    o.view.pixel_angle = 1e-3;
    return o;
}

}  // namespace

TEST_CASE("the surface's memory outside the cache matches a count by hand", "[memory]") {
    Mesh mesh = testmesh::icosahedron();  // 12 vertices, 20 triangles, no normals or UVs
    mesh.positions.shrink_to_fit();
    mesh.triangles.shrink_to_fit();
    const std::size_t V = mesh.positions.size(), F = mesh.triangles.size();
    REQUIRE(V == 12);
    REQUIRE(F == 20);
    const AdaptiveSurface surface(mesh, close_view_options());
    const SurfaceMemory m = surface.stats().memory;
    // Mesh: a position (3 doubles) per vertex, 3 indices per triangle.
    CHECK(m.mesh == V * 24 + F * 12);
    // Topology: an offset per vertex plus one, a face index per corner.
    CHECK(m.topology == (V + 1) * 4 + 3 * F * 4);
    // Level-0 records, normal scheme: a normal (double), a shading normal
    // (float) and a displacement (float) per vertex; a 40-byte shell (box and
    // slab in float, a 16-bit axis, padded) and three midpoint normals
    // (float) per triangle.
    CHECK(m.roots == V * (24 + 12 + 4) + F * (40 + 36));
    // BVH: 32-byte nodes (at least the root, at most 2F - 1) and an item index per triangle.
    CHECK(m.bvh >= 32 + F * 4);
    CHECK(m.bvh <= (2 * F - 1) * 32 + F * 4);
    CHECK(m.base() == m.mesh + m.topology + m.bvh + m.roots);
    // No ray yet: no front, nothing cached.
    CHECK(m.front_threads == 0);
    CHECK(m.fronts == 0);
    CHECK(surface.stats().cache_bytes == 0);
}

TEST_CASE("per-thread fronts are counted while their threads hold them", "[memory][threads]") {
    // A cache that keeps the whole budget from the start, so nothing is evicted (below).
    SurfaceOptions options = close_view_options();
    options.cache = std::make_shared<TileCache>(std::size_t{32} << 20, TileCache::Sizing::whole_budget);
    const AdaptiveSurface surface(testmesh::icosphere(2), options);
    trace_close_rays(surface, 1, 200);
    const SurfaceStats one = surface.stats();
    REQUIRE(one.nodes_built > 0);  // the rays refined
    CHECK(one.memory.front_threads == 1);
    CHECK(one.memory.fronts > 0);
    // A front is its table (64 slots of a node id and a pointer, about
    // 2 kB) and the tiles it holds, each charged as in the cache; with no
    // eviction every tile is in the cache, so they cannot add up to more.
    REQUIRE(one.cache_evictions == 0);
    CHECK(one.memory.fronts > 4096);  // the table and at least one tile
    CHECK(one.memory.fronts <= 4096 + one.cache_bytes);
    CHECK(one.cache_bytes > 0);
    // A second thread adds its front, and drops it when it exits.
    std::size_t during = 0;
    std::thread other([&] {
        trace_close_rays(surface, 2, 200);
        during = surface.stats().memory.front_threads;
    });
    other.join();
    CHECK(during == 2);
    const SurfaceStats after = surface.stats();
    CHECK(after.memory.front_threads == 1);
    CHECK(after.memory.fronts == one.memory.fronts);  // this thread's front, unchanged
    // So are the levels below parent tiles this thread keeps; the other
    // thread's went with it.
    CHECK(after.memory.levels_below == one.memory.levels_below);
}

TEST_CASE("cache evictions count tiles dropped, never more than tiles built", "[memory][cache]") {
    // One thread: every tile built is inserted (a miss builds its tile and
    // those of its group), and what was not evicted is still cached: at most
    // 2 tiles in each of the 64 shards under a 1-byte budget.
    const Mesh mesh = testmesh::icosphere(2);
    const Hierarchy tiny(mesh, SchemeKind::normal, 6, 1);
    const Hierarchy roomy(mesh, SchemeKind::normal, 6, std::size_t{256} << 20);
    // Every node down to level 5 of the first 10 base triangles, depth first.
    for (const Hierarchy* h : {&tiny, &roomy}) {
        std::vector<NodeId> stack;
        for (std::uint32_t f = 0; f < 10; ++f) stack.push_back(Hierarchy::root(f));
        std::array<NodeRecord, 4> children;
        while (!stack.empty()) {
            const NodeId id = stack.back();
            stack.pop_back();
            if (id.level >= 5) continue;
            h->children(id, children);
            for (int c = 0; c < 4; ++c) stack.push_back(child_of(id, c));
        }
    }
    const HierarchyCounters t = tiny.counters(), r = roomy.counters();
    CHECK(r.evictions == 0);
    CHECK(t.evictions > 0);
    CHECK(t.evictions <= t.tiles_built);
    CHECK(t.evictions + 2 * 64 >= t.tiles_built);
    CHECK(t.node_misses <= t.tiles_built);
    // A tile holds at least 4 records (its first level), so tiles evicted
    // stay well below records built.
    CHECK(4 * t.evictions <= t.nodes_built);
}
