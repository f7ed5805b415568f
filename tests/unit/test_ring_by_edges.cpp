// A patch orders Loop's and Butterfly's rings through its edges
// (ring_by_edges), where order_ring searched the pairs: wherever the walk
// answers, it must give order_ring's answer exactly (the same neighbours,
// start, direction and kind), because patches that hold a vertex sum its
// ring in that order and must get the same bits, and copied patches still
// take order_ring's. Checked on every vertex of whole levels and of bands
// cut anywhere, on meshes with boundaries, creases, a non-manifold edge, a
// bowtie vertex, a duplicate and a turned triangle.
#include <catch2/catch.hpp>

#include <numeric>
#include <random>
#include <vector>

#include "patch.h"
#include "ring_order.h"
#include "test_meshes.h"

using namespace subdivtrace;
using namespace subdivtrace::detail;

namespace {

/// A fan of four triangles around vertex 0, with a fifth on one of its
/// edges (three triangles there), another fan touching it at vertex 0 only
/// (a bowtie), a triangle given twice and one turned the other way round,
/// and a closed fan of four around vertex 12 with one of them turned.
Mesh awkward_mesh() {
    Mesh m;
    m.positions = {{0, 0, 0},   {1, 0, 0},  {0, 1, 0},  {-1, 0, 0}, {0, -1, 0},  {0.5, 0.5, 1},
                   {0, 0, -1},  {-1, -1, -1}, {1, -1, -1}, {2, 0, 0}, {2, 1, 0}, {3, 1, 0},
                   {5, 0, 0},   {6, 0, 0},  {5, 1, 0},  {4, 0, 0}, {5, -1, 0}};
    m.triangles = {{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 1},  // a closed fan at 0
                   {0, 1, 5},                                   // a third triangle on edge 0-1
                   {0, 6, 7}, {0, 8, 6},                        // a second fan at 0
                   {1, 9, 10}, {1, 9, 10},                      // given twice
                   {9, 10, 11},                                 // turned against its neighbour
                   {12, 13, 14}, {12, 14, 15}, {12, 16, 15}, {12, 16, 13}};  // a fan, one turned
    return m;
}

/// order_ring of v's pairs in the patch's canonical order (what finish()
/// did before ring_by_edges).
OrderedRing<std::uint32_t> searched_ring(const Patch& p, std::uint32_t v) {
    std::vector<FanPair<std::uint32_t>> pairs;
    for (std::uint32_t k = p.incident_offsets[v]; k < p.incident_offsets[v + 1]; ++k) {
        const std::uint32_t slot = p.incident_slots[k];
        const PatchTriangle& t = p.tris[slot / 3];
        pairs.push_back({t.v[(slot % 3 + 1) % 3], t.v[(slot % 3 + 2) % 3]});
    }
    OrderedRing<std::uint32_t> out;
    order_ring(pairs, out, [](std::uint32_t x, std::uint32_t y) { return x == y; });
    return out;
}

struct Tally {
    std::size_t walked = 0, searched = 0, differ = 0;
};

/// Compares the two on every vertex of p (finished) that has triangles.
void compare_rings(const Patch& p, Tally& tally) {
    for (std::uint32_t v = 0; v < p.verts.size(); ++v) {
        if (p.incident_offsets[v + 1] == p.incident_offsets[v]) continue;
        OrderedRing<std::uint32_t> walked;
        if (!ring_by_edges(p, v, walked)) {
            ++tally.searched;
            continue;
        }
        ++tally.walked;
        const OrderedRing<std::uint32_t> searched = searched_ring(p, v);
        if (walked.nbrs != searched.nbrs || walked.closed != searched.closed || walked.regular != searched.regular)
            ++tally.differ;
    }
}

}  // namespace

TEST_CASE("rings walked through the edges are order_ring's rings", "[patch][rings]") {
    const std::vector<std::pair<const char*, Mesh>> meshes = {
        {"icosahedron", testmesh::icosahedron()},
        {"irregular closed", testmesh::irregular_closed(5)},
        {"open grid", testmesh::open_grid(4)},
        {"valence 12", testmesh::high_valence_fan(12)},
        {"valence 40", testmesh::high_valence_fan(40)},
        {"folded", testmesh::folded()},
        {"faceted cube (creases)", testmesh::faceted_cube()},
        {"non-manifold, bowtie, duplicate, turned", awkward_mesh()},
    };
    const SchemeRules& rules = rules_of(SchemeKind::loop);
    std::mt19937 rng(23);
    Tally all;
    for (const auto& [name, mesh] : meshes) {
        const BaseTopology topo(mesh);
        std::vector<std::uint32_t> faces(topo.face_count());
        std::iota(faces.begin(), faces.end(), 0u);
        Patch p = base_patch(topo, faces.data(), faces.size());
        Tally tally;
        for (int level = 0; level <= 2; ++level) {
            p.finish(topo, rules);
            compare_rings(p, tally);
            // Bands around a few triangles anywhere, cut and finished alone:
            // their border vertices have rings cut open.
            for (int trial = 0; trial < 6; ++trial) {
                std::vector<std::uint32_t> region;
                std::uniform_int_distribution<std::uint32_t> pick(0, static_cast<std::uint32_t>(p.tris.size() - 1));
                for (int k = 0; k < 3; ++k) region.push_back(pick(rng));
                std::sort(region.begin(), region.end());
                region.erase(std::unique(region.begin(), region.end()), region.end());
                Patch band = Patch::copy_of(p, p.band_around(region));
                band.finish(topo, rules);
                compare_rings(band, tally);
            }
            Flags kept;
            Patch next = p.subdivide_band(topo, rules, [](const NodeId&) { return true; }, kept);
            next.keep_only(kept);
            p = std::move(next);
        }
        INFO(name << ": " << tally.walked << " rings walked, " << tally.searched << " searched");
        CHECK(tally.differ == 0);
        CHECK(tally.walked > 0);
        all.walked += tally.walked;
        all.searched += tally.searched;
    }
    // Both ways are taken: the walk for nearly every ring, the search where
    // the walk cannot tell (in the awkward mesh).
    INFO(all.walked << " rings walked, " << all.searched << " searched");
    CHECK(all.searched > 0);
    CHECK(all.walked > 20 * all.searched);
}
