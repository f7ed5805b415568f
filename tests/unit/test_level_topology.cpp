// LevelTopology::refined (a level's connectivity derived from its parent's in
// linear time) against the sorting constructor run on the same children from
// scratch: the same edges with the same triangles, orientation and opposite
// vertices, the same ordered rings (up to where a closed ring starts), curves,
// sectors and normals, on closed, open, creased and mis-oriented meshes, over
// three levels.
#include <catch2/catch.hpp>

#include <algorithm>
#include <map>
#include <random>
#include <utility>

#include "creases.h"
#include "level_topology.h"
#include "test_meshes.h"

using namespace subdivtrace;

namespace {

/// One level's arrays: what LevelTopology is built from.
struct Level {
    std::vector<Vec3> positions;
    std::vector<Triangle> triangles;
    std::vector<std::uint8_t> creases;
};

/// The 1-to-4 split in uniform.h's layout (vertex V + e on edge e, children
/// 4t..4t+3, middle child rotated for odd t so both middle orders occur),
/// edge points at midpoints nudged apart, crease halves kept.
Level split(const Level& parent, const LevelTopology& topo, std::mt19937& rng) {
    Level child;
    const auto old_count = static_cast<std::uint32_t>(parent.positions.size());
    child.positions = parent.positions;
    std::uniform_real_distribution<double> nudge(-0.01, 0.01);
    for (std::uint32_t e = 0; e < topo.edge_count(); ++e) {
        const LevelTopology::Edge& edge = topo.edge(e);
        child.positions.push_back((parent.positions[edge.a] + parent.positions[edge.b]) * 0.5 +
                                  Vec3(nudge(rng), nudge(rng), nudge(rng)));
    }
    for (std::size_t t = 0; t < parent.triangles.size(); ++t) {
        const Triangle& p = parent.triangles[t];
        const std::uint32_t ab = old_count + topo.face_edge(t, 0);
        const std::uint32_t bc = old_count + topo.face_edge(t, 1);
        const std::uint32_t ca = old_count + topo.face_edge(t, 2);
        child.triangles.push_back({p[0], ab, ca});
        child.triangles.push_back({ab, p[1], bc});
        child.triangles.push_back({ca, bc, p[2]});
        if (t % 2 == 1) child.triangles.push_back({ca, ab, bc});
        else child.triangles.push_back({ab, bc, ca});
        if (!parent.creases.empty()) {
            const std::uint8_t m = parent.creases[t];
            for (std::uint8_t c : {std::uint8_t(m & 0b101), std::uint8_t(m & 0b011),
                                   std::uint8_t(m & 0b110), std::uint8_t(0)})
                child.creases.push_back(c);
        }
    }
    return child;
}

std::pair<std::uint32_t, std::uint32_t> unordered(std::uint32_t a, std::uint32_t b) {
    return {std::min(a, b), std::max(a, b)};
}

/// v's ring as a list, rotated to start at its smallest neighbour when closed.
std::vector<std::uint32_t> ring_of(const LevelTopology& topo, std::uint32_t v) {
    std::vector<std::uint32_t> ring;
    for (std::size_t k = 0; k < topo.valence(v); ++k) ring.push_back(topo.ring_neighbour(v, k));
    if (topo.ring_closed(v) && !ring.empty())
        std::rotate(ring.begin(), std::min_element(ring.begin(), ring.end()), ring.end());
    return ring;
}

void check_same(const LevelTopology& derived, const LevelTopology& sorted, const Level& level) {
    REQUIRE(derived.edge_count() == sorted.edge_count());
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> by_ends;
    for (std::uint32_t e = 0; e < sorted.edge_count(); ++e)
        by_ends[unordered(sorted.edge(e).a, sorted.edge(e).b)] = e;
    for (std::uint32_t e = 0; e < derived.edge_count(); ++e) {
        const LevelTopology::Edge& d = derived.edge(e);
        const auto it = by_ends.find(unordered(d.a, d.b));
        REQUIRE(it != by_ends.end());
        const LevelTopology::Edge& s = sorted.edge(it->second);
        CHECK(d.a == s.a);
        CHECK(d.b == s.b);
        CHECK(d.c == s.c);
        CHECK(d.face_count == s.face_count);
        CHECK(d.interior == s.interior);
        CHECK(d.curve == s.curve);
        CHECK(d.face == s.face);
        CHECK(d.corner == s.corner);
        if (s.interior) CHECK(d.d == s.d);
        if (s.face_count >= 2) {
            CHECK(d.face2 == s.face2);
            CHECK(d.corner2 == s.corner2);
        }
    }
    for (std::size_t t = 0; t < level.triangles.size(); ++t) {
        for (int i = 0; i < 3; ++i) {
            const LevelTopology::Edge& d = derived.edge(derived.face_edge(t, i));
            CHECK(unordered(d.a, d.b) ==
                  unordered(level.triangles[t][i], level.triangles[t][(i + 1) % 3]));
        }
    }
    for (std::uint32_t v = 0; v < level.positions.size(); ++v) {
        CHECK(ring_of(derived, v) == ring_of(sorted, v));
        CHECK(derived.ring_closed(v) == sorted.ring_closed(v));
        CHECK(derived.ring_regular(v) == sorted.ring_regular(v));
        CHECK(derived.single_sector(v) == sorted.single_sector(v));
        CHECK(derived.curve_count(v) == sorted.curve_count(v));
        for (std::size_t k = 0; k < derived.valence(v); ++k) {
            const LevelTopology::Edge& e = derived.edge(derived.ring_edge(v, k));
            CHECK(unordered(e.a, e.b) == unordered(v, derived.ring_neighbour(v, k)));
        }
    }
    CHECK(derived.sector_normals(level.positions, level.triangles) ==
          sorted.sector_normals(level.positions, level.triangles));
}

/// `mesh` with triangle `t` turned over (its neighbours then disagree on
/// the orientation of their shared edges).
Mesh with_flipped(Mesh mesh, std::size_t t) {
    std::swap(mesh.triangles[t][1], mesh.triangles[t][2]);
    return mesh;
}

}  // namespace

TEST_CASE("a refined level's topology equals the one sorted from scratch", "[topology][uniform]") {
    const Mesh cube = testmesh::faceted_cube();
    const std::vector<std::pair<const char*, Level>> meshes = {
        {"icosahedron", {testmesh::icosphere(0).positions, testmesh::icosphere(0).triangles, {}}},
        {"irregular", {testmesh::irregular_closed(3).positions, testmesh::irregular_closed(3).triangles, {}}},
        {"open grid", {testmesh::open_grid(3).positions, testmesh::open_grid(3).triangles, {}}},
        {"faceted cube (creases)", {cube.positions, cube.triangles, detail::crease_masks(cube)}},
        {"torus, one face flipped",
         {testmesh::torus(6, 5, 1.0, 0.3).positions,
          with_flipped(testmesh::torus(6, 5, 1.0, 0.3), 7).triangles, {}}},
    };
    std::mt19937 rng(5);
    for (const auto& [name, base] : meshes) {
        SECTION(name) {
            Level level = base;
            LevelTopology topo(level.positions, level.triangles, level.creases);
            for (int k = 0; k < 3; ++k) {
                REQUIRE(topo.manifold_edges());
                const Level child = split(level, topo, rng);
                const LevelTopology derived = LevelTopology::refined(
                    topo, level.triangles, level.positions.size(), child.triangles, child.creases);
                const LevelTopology sorted(child.positions, child.triangles, child.creases);
                check_same(derived, sorted, child);
                level = child;
                topo = derived;
            }
        }
    }
}

TEST_CASE("an edge with three triangles keeps uniform subdivision on the sorting path",
          "[topology][uniform]") {
    // Three triangles on edge (0, 1): refined() does not apply.
    const std::vector<Vec3> positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
    const std::vector<Triangle> triangles = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
    CHECK_FALSE(LevelTopology(positions, triangles).manifold_edges());
    CHECK(LevelTopology(positions, {{0, 1, 2}, {1, 0, 3}}).manifold_edges());
}
