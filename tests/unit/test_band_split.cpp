// A tile's next level is split only from the parents its band can reach
// (Patch::parents_of_band): checked against splitting every triangle of the
// level and cutting the band from the result, which must give the same
// triangles in the same order and the same bits at their corners.
#include <catch2/catch.hpp>

#include <algorithm>
#include <numeric>
#include <random>
#include <vector>

#include "patch.h"
#include "subdivtrace/uniform.h"
#include "test_meshes.h"

using namespace subdivtrace;
using namespace subdivtrace::detail;

namespace {

/// Level `level` of every face of `topo`'s mesh, finished.
Patch whole_level(const BaseTopology& topo, const SchemeRules& rules, int level) {
    std::vector<std::uint32_t> faces(topo.face_count());
    std::iota(faces.begin(), faces.end(), 0u);
    Patch p = base_patch(topo, faces.data(), faces.size());
    p.finish(topo, rules);
    for (int k = 0; k < level; ++k) {
        Flags kept;
        p = p.subdivide_band(topo, rules, [](const NodeId&) { return true; }, kept);
        p.keep_only(kept);
        p.finish(topo, rules);
    }
    return p;
}

}  // namespace

TEST_CASE("a band split from the parents it can reach equals the band of the whole split level",
          "[patch][band]") {
    Mesh creased_open = to_mesh(subdivide_uniform(testmesh::faceted_cube(), SchemeKind::normal, 1));
    const std::vector<std::pair<const char*, Mesh>> meshes = {
        {"irregular closed", testmesh::irregular_closed(3)},
        {"open grid", testmesh::open_grid(5)},
        {"faceted cube (creases)", testmesh::faceted_cube()},
        {"faceted cube level 1", creased_open},
    };
    std::mt19937 rng(17);
    for (const auto& [name, mesh] : meshes) {
        const BaseTopology topo(mesh);
        for (SchemeKind scheme : {SchemeKind::normal, SchemeKind::loop, SchemeKind::butterfly}) {
            const SchemeRules& rules = rules_of(scheme);
            const Patch level = whole_level(topo, rules, 2);
            // Every triangle split, then the band cut: the reference.
            Patch all = level;
            Flags unused;
            const Patch whole_split = all.subdivide_band(topo, rules, [](const NodeId&) { return true; }, unused);
            for (int trial = 0; trial < 12; ++trial) {
                // A region of a few nodes of the next level, anywhere: whole
                // families, lone children, neighbours or far apart.
                std::vector<NodeId> region;
                const int size = 1 + trial % 5;
                for (int k = 0; k < size; ++k) {
                    const PatchTriangle& t = level.tris[rng() % level.tris.size()];
                    region.push_back(child_of(t.id, static_cast<int>(rng() % 4)));
                }
                const auto in_region = [&](const NodeId& id) {
                    return std::find(region.begin(), region.end(), id) != region.end();
                };
                INFO(name << " " << scheme_name(scheme) << " trial " << trial);

                const Flags reference = whole_split.band(in_region);
                std::vector<std::uint32_t> reference_tris;
                for (std::uint32_t t = 0; t < reference.size(); ++t)
                    if (reference[t]) reference_tris.push_back(t);

                Patch parent = level;
                Flags kept;
                Patch split = parent.subdivide_band(topo, rules, in_region, kept);
                std::vector<std::uint32_t> kept_tris;
                for (std::uint32_t t = 0; t < kept.size(); ++t)
                    if (kept[t]) kept_tris.push_back(t);

                REQUIRE(kept_tris.size() == reference_tris.size());
                bool same_nodes = true, same_bits = true;
                for (std::size_t k = 0; k < kept_tris.size(); ++k) {
                    const PatchTriangle& a = split.tris[kept_tris[k]];
                    const PatchTriangle& b = whole_split.tris[reference_tris[k]];
                    same_nodes = same_nodes && a.id == b.id;
                    for (int c = 0; c < 3; ++c) {
                        const PatchVertex& va = split.verts[a.v[c]];
                        const PatchVertex& vb = whole_split.verts[b.v[c]];
                        same_bits = same_bits && va.key == vb.key && va.has_position == vb.has_position &&
                                    (!va.has_position || va.position == vb.position);
                    }
                }
                CHECK(same_nodes);
                CHECK(same_bits);
                // Fewer triangles split than the whole level's.
                CHECK(split.tris.size() < whole_split.tris.size());
            }
        }
    }
}
