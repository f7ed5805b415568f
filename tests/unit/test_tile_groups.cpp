// Tiles start from a level shared with their neighbours (tile.h, LevelBelow):
// base triangles' tiles from their chunk's level 1 (chunks of connected
// faces, face_chunks.h), tiles below a tile from the level below their
// parent's deepest, after siblings finished it. A tile built so must hold
// exactly the bits it holds when built alone, or the two sides of an edge
// between tiles built from different levels would not meet.
#include <catch2/catch.hpp>

#include <algorithm>
#include <atomic>
#include <vector>

#include <glm/geometric.hpp>

#include "face_chunks.h"
#include "root_records.h"
#include "subdivtrace/uniform.h"
#include "test_meshes.h"
#include "tile.h"

using namespace subdivtrace;
using namespace subdivtrace::detail;

namespace {

/// Two meshes of several chunks: a closed irregular one and an open,
/// creased one with two components.
std::vector<std::pair<const char*, Mesh>> chunked_meshes() {
    Mesh two_parts = to_mesh(subdivide_uniform(testmesh::faceted_cube(), SchemeKind::normal, 1));
    const Mesh grid = testmesh::open_grid(6);
    const auto offset = static_cast<std::uint32_t>(two_parts.positions.size());
    for (const Vec3& p : grid.positions) two_parts.positions.push_back(p + Vec3(3.0, 0.0, 0.0));
    for (Triangle t : grid.triangles) {
        for (auto& v : t) v += offset;
        two_parts.triangles.push_back(t);
        // The cube's corner normals (its creases) must cover every triangle.
        const Vec3 n = glm::normalize(glm::cross(two_parts.positions[t[1]] - two_parts.positions[t[0]],
                                                 two_parts.positions[t[2]] - two_parts.positions[t[0]]));
        if (!two_parts.corner_normals.empty())
            for (int c = 0; c < 3; ++c) two_parts.corner_normals.push_back(n);
        if (!two_parts.corner_uvs.empty())
            for (int c = 0; c < 3; ++c) two_parts.corner_uvs.push_back(Vec2(0.0));
    }
    REQUIRE_NOTHROW(validate_mesh(two_parts, "creased cube and open grid"));
    return {{"irregular, level 1", to_mesh(subdivide_uniform(testmesh::irregular_closed(5), SchemeKind::normal, 1))},
            {"creased cube and open grid", two_parts}};
}

bool same(const NodeRecord& a, const NodeRecord& b) {
    bool eq = a.linear_shading == b.linear_shading && a.shell.lo == b.shell.lo && a.shell.hi == b.shell.hi &&
              a.shell.axis == b.shell.axis && a.shell.slab_min == b.shell.slab_min && a.shell.slab_max == b.shell.slab_max;
    for (int c = 0; c < 3; ++c)
        eq = eq && a.position[c] == b.position[c] &&
             a.draw_position[c] == b.draw_position[c] && a.shading_normal[c] == b.shading_normal[c] &&
             a.edge_normal[c] == b.edge_normal[c] && a.displacement[c] == b.displacement[c];
    return eq;
}

/// Every descendant of `root` at levels root.level + 1 .. root.level + depth.
template <class Visit>
void for_each_descendant(const NodeId& root, int depth, Visit visit) {
    std::vector<NodeId> level{root};
    for (int d = 1; d <= depth; ++d) {
        std::vector<NodeId> next;
        for (const NodeId& id : level)
            for (int c = 0; c < 4; ++c) next.push_back(child_of(id, c));
        for (const NodeId& id : next) visit(id);
        level = std::move(next);
    }
}

}  // namespace

TEST_CASE("face chunks partition the base faces into small connected groups", "[hierarchy]") {
    for (const auto& [name, mesh] : chunked_meshes()) {
        INFO(name);
        const BaseTopology topo(mesh);
        for (std::size_t size : {std::size_t{1}, std::size_t{5}, k_face_chunk_size}) {
            const FaceChunks chunks(topo, size);
            CHECK(chunks.chunk_count() >= (mesh.triangles.size() + size - 1) / size);
            std::vector<int> seen(mesh.triangles.size(), 0);
            for (std::uint32_t f = 0; f < mesh.triangles.size(); ++f) {
                const auto [begin, end] = chunks.chunk_of(f);
                const std::vector<std::uint32_t> members(begin, end);
                REQUIRE(!members.empty());
                CHECK(members.size() <= size);
                CHECK(std::is_sorted(members.begin(), members.end()));
                CHECK(std::count(members.begin(), members.end(), f) == 1);
                if (members.front() == f) ++seen[f];  // count each chunk once, by its first face
                for (std::uint32_t g : members) {
                    const auto [b2, e2] = chunks.chunk_of(g);
                    CHECK(std::vector<std::uint32_t>(b2, e2) == members);  // one chunk per face
                }
                // Connected through shared vertices.
                std::vector<std::uint32_t> reached{members.front()};
                for (std::size_t k = 0; k < reached.size(); ++k)
                    for (std::uint32_t g : members) {
                        if (std::count(reached.begin(), reached.end(), g)) continue;
                        bool touches = false;
                        for (std::uint32_t v : mesh.triangles[reached[k]])
                            for (std::uint32_t w : mesh.triangles[g]) touches = touches || v == w;
                        if (touches) reached.push_back(g);
                    }
                CHECK(reached.size() == members.size());
            }
            std::size_t chunk_firsts = 0;
            for (int s : seen) chunk_firsts += static_cast<std::size_t>(s);
            CHECK(chunk_firsts == chunks.chunk_count());
        }
    }
}

TEST_CASE("a tile holds the same bits built alone or with its group", "[hierarchy]") {
    for (const auto& [name, mesh] : chunked_meshes()) {
        const BaseTopology topo(mesh);
        const FaceChunks chunks(topo, k_face_chunk_size);
        for (SchemeKind scheme : {SchemeKind::normal, SchemeKind::loop, SchemeKind::butterfly}) {
            INFO(name << ", " << scheme_name(scheme));
            std::atomic<std::uint64_t> records{0}, ns{0};
            TileContext ctx{topo, detail::rules_of(scheme), ShellKind::aabb_slab, 6, &records, &ns, nullptr, {}, {}, {}};
            const RootRecords roots(ctx);
            ctx.roots = &roots;
            // The child tiles below build their later levels from their
            // parent's band: the base tile built alone.
            const Tile* parent = nullptr;
            ctx.child_start = [&](const NodeId& root) { return parent->band_of_child(root); };
            std::size_t compared = 0, differing = 0;
            const auto compare = [&](const Tile& a, const Tile& b, const NodeId& root, int depth) {
                for_each_descendant(root, depth, [&](const NodeId& id) {
                    ++compared;
                    if (!same(a.record(id), b.record(id))) ++differing;
                });
            };
            for (std::uint32_t face = 0; face < mesh.triangles.size(); face += 3) {
                // Alone: from the level 1 of its own face. With its chunk:
                // from the chunk's level 1, finished by the tiles of the
                // chunk's other faces first.
                const auto [begin, end] = chunks.chunk_of(face);
                const NodeId root = root_node(face);
                LevelBelow own_level(chunk_level(ctx, &face, 1));
                TileGroup alone_group(ctx, own_level, {root});
                LevelBelow chunk(chunk_level(ctx, begin, static_cast<std::size_t>(end - begin)));
                std::vector<NodeId> chunk_others;
                for (const std::uint32_t* f = begin; f != end; ++f)
                    if (*f != face) chunk_others.push_back(root_node(*f));
                const TileGroup others_first(ctx, chunk, chunk_others);
                TileGroup from_chunk(ctx, chunk, {root});
                const Tile alone(ctx, root, alone_group);
                const Tile with_chunk(ctx, root, from_chunk);
                parent = &alone;
                compare(alone, with_chunk, root, 3);
                // A base tile's later levels start from its face's band: the
                // level 1 of its face alone (above), or that band cut from
                // its chunk's level, finished by other tiles (the hierarchy's
                // TileContext::base_start where the chunk's level is kept).
                TileContext cut_from_chunk = ctx;
                cut_from_chunk.base_start = [&](std::uint32_t f) { return band_of_roots(chunk.patch(), {root_node(f)}); };
                TileGroup from_chunk_again(cut_from_chunk, chunk, {root});
                const Tile with_chunk_start(cut_from_chunk, root, from_chunk_again);
                compare(alone, with_chunk_start, root, 3);
                // Tiles below: alone, and with their group, from either tile's
                // last patch.
                const NodeId child_root = child_of(child_of(child_of(root, 1), 3), 0);
                REQUIRE(tile_group_of(child_root).size() == std::size_t{1} << (2 * k_group_levels));
                // A group of the 4 roots under one node, whatever size the
                // hierarchy's groups have.
                const NodeId above = ancestor_at(child_root, child_root.level - 1);
                const std::vector<NodeId> siblings{child_of(above, 0), child_of(above, 1), child_of(above, 2),
                                                   child_of(above, 3)};
                REQUIRE(std::count(siblings.begin(), siblings.end(), child_root) == 1);
                // Alone: from its own band, cut and finished as if nothing
                // else were below the parent. With siblings: from the whole
                // level below the parent, after siblings finished it and
                // computed the points and normals they share with it.
                LevelBelow own_band(band_of_roots(alone.below_deepest(), {child_root}));
                LevelBelow below_with_chunk(with_chunk.below_deepest());
                TileGroup child_alone_group(ctx, own_band, {child_root});
                std::vector<NodeId> others;
                for (const NodeId& s : siblings)
                    if (!(s == child_root)) others.push_back(s);
                const TileGroup siblings_first(ctx, below_with_chunk, others);
                TileGroup child_siblings(ctx, below_with_chunk, {child_root});
                const Tile child_alone(ctx, child_root, child_alone_group);
                const Tile child_with_siblings(ctx, child_root, child_siblings);
                compare(child_alone, child_with_siblings, child_root, 3);
                // A tile keeps no band between its levels; its later levels
                // start from the parent's band around its root (above) or,
                // where the hierarchy still has it, from the level below the
                // parent: the same bits either way.
                TileContext from_below = ctx;
                const Patch below = alone.below_deepest();
                from_below.child_start = [&](const NodeId& r) { return band_of_roots(below, {r}); };
                LevelBelow level_below(below);
                TileGroup child_from_below_group(from_below, level_below, {child_root});
                const Tile child_from_below(from_below, child_root, child_from_below_group);
                compare(child_alone, child_from_below, child_root, 3);
            }
            CHECK(compared > 0);
            CHECK(differing == 0);
        }
    }
}
