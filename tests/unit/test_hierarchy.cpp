// Contract "adaptive == uniform" (DESIGN.md section 3): every vertex and
// normal the lazy hierarchy creates at level k equals uniform level-k
// subdivision of the whole mesh, whatever the cache budget and thread count;
// and, since uniform subdivision is our own code too, every node equals the
// independent references at each level: OpenMesh for Loop and Butterfly, the
// brute-force normal scheme of reference_subdivision.h.
// OpenMesh's VectorT: see test_schemes.cpp (must precede every include).
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numeric>
#include <set>
#include <random>
#include <thread>

#include <glm/geometric.hpp>

#include "subdivtrace/hierarchy.h"
#include "subdivtrace/uniform.h"
#include "tile.h"
#include "test_meshes.h"
#include "unit/openmesh_subdivide.h"
#include "unit/reference_subdivision.h"

using namespace subdivtrace;

namespace {

/// Node of uniform triangle t at `level`: base face t / 4^level, then the
/// base-4 digits of the remainder, most significant first, as child indices.
NodeId node_of_uniform_triangle(std::size_t t, int level) {
    const std::size_t per_base = std::size_t{1} << (2 * level);
    NodeId id = Hierarchy::root(static_cast<std::uint32_t>(t / per_base));
    std::size_t rest = t % per_base;
    for (int k = level - 1; k >= 0; --k) {
        id = child_of(id, static_cast<int>((rest >> (2 * k)) & 3));
    }
    return id;
}

struct Worst {
    double position = 0.0;
    double normal = 0.0;
};

/// How close a record's normals are to the exact ones: tiles keep them in
/// 24 bits (octahedral, within 4e-7 radians: test_octahedral.cpp), the base
/// records in floats. The exact normals are checked where the build holds
/// them ("the levels a tile build derives have uniform subdivision's normals").
constexpr double k_stored_normal = 1e-6;

/// Largest difference between each uniform triangle's corners and its node's:
/// positions of a hierarchy that goes deeper, and normals of one whose
/// max_level is `level` (a record's level-L Gouraud normals are its shading
/// normals only there: elsewhere it shades with the level below's).
Worst compare_with_uniform(const Mesh& mesh, SchemeKind scheme, int level,
                           std::size_t cache_bytes) {
    const SubdividedMesh uniform = subdivide_uniform(mesh, scheme, level);
    const Hierarchy hierarchy(mesh, scheme, level + 2, cache_bytes);
    const Hierarchy at_max_level(mesh, scheme, level, cache_bytes);
    const double scale = testmesh::bbox_diagonal(mesh.positions);
    Worst worst;
    for (std::size_t t = 0; t < uniform.triangles.size(); ++t) {
        const NodeRecord rec = hierarchy.node(node_of_uniform_triangle(t, level));
        const NodeRecord last = at_max_level.node(node_of_uniform_triangle(t, level));
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t v = uniform.triangles[t][k];
            // The node's corners are the triangle's, possibly rotated.
            double best = 1e300;
            int best_c = 0;
            for (int c = 0; c < 3; ++c) {
                const double d = glm::length(rec.position[c] - uniform.positions[v]);
                if (d < best) best = d, best_c = c;
            }
            worst.position = std::max(worst.position, best / scale);
            worst.normal = std::max(worst.normal,
                                    glm::length(last.shading_normal[best_c] - uniform.corner_normal(t, k)));
        }
    }
    return worst;
}

/// Smooth, open, creased, split-normal, given-normal and bounded meshes:
/// what the hierarchy is compared with uniform subdivision on.
std::vector<std::pair<const char*, Mesh>> uniform_comparison_meshes() {
    return {
        {"icosahedron", testmesh::icosahedron()},
        {"torus", testmesh::torus(8, 6, 1.0, 0.35)},
        {"irregular", testmesh::irregular_closed(7)},
        {"open grid", testmesh::open_grid(4)},
        {"faceted cube (creases)", testmesh::faceted_cube()},
        {"cylinder, split rim normals", testmesh::split_normal_cylinder(7, 1.0, 0.6)},
        {"icosphere, given normals", testmesh::icosphere_with_normals(1)},
        {"half sphere (boundary)", testmesh::octasphere_half(1, true)},
    };
}

}  // namespace

TEST_CASE("adaptive hierarchy equals uniform subdivision", "[hierarchy]") {
    const std::vector<std::pair<const char*, Mesh>> meshes = uniform_comparison_meshes();
    Worst overall;
    for (const auto& [name, mesh] : meshes) {
        for (SchemeKind scheme : {SchemeKind::normal, SchemeKind::loop, SchemeKind::butterfly}) {
            for (int level = 0; level <= 3; ++level) {
                INFO(name << " " << scheme_name(scheme) << " level " << level);
                const Worst w = compare_with_uniform(mesh, scheme, level, std::size_t{256} << 20);
                CHECK(w.position <= 1e-12);
                CHECK(w.normal <= k_stored_normal);
                overall.position = std::max(overall.position, w.position);
                overall.normal = std::max(overall.normal, w.normal);
            }
        }
    }
    WARN("adaptive vs uniform, worst relative position difference " << overall.position
                                                                     << ", normal " << overall.normal);
}

TEST_CASE("the levels a tile build derives have uniform subdivision's normals", "[hierarchy][normals]") {
    // Records keep only what a ray reads (their shading normals, in 24 bits);
    // the level's own Gouraud normals, which the normal scheme's edge rule
    // and the shells read, are checked here where the build holds them: a
    // patch of the whole mesh, subdivided level by level as tiles are.
    for (const auto& [name, mesh] : uniform_comparison_meshes()) {
        const detail::BaseTopology topo(mesh);
        std::vector<std::uint32_t> faces(mesh.triangles.size());
        std::iota(faces.begin(), faces.end(), 0u);
        for (SchemeKind scheme : {SchemeKind::normal, SchemeKind::loop, SchemeKind::butterfly}) {
            const detail::SchemeRules& rules = detail::rules_of(scheme);
            detail::Patch p = detail::base_patch(topo, faces.data(), faces.size());
            for (int level = 0; level <= 3; ++level) {
                INFO(name << " " << scheme_name(scheme) << " level " << level);
                p.finish(topo, rules);
                const SubdividedMesh uniform = subdivide_uniform(mesh, scheme, level);
                REQUIRE(p.tris.size() == uniform.triangles.size());
                double worst = 0.0;
                bool same_nodes = true;
                for (std::uint32_t t = 0; t < p.tris.size(); ++t) {
                    same_nodes = same_nodes && p.tris[t].id == node_of_uniform_triangle(t, level);
                    for (int c = 0; c < 3; ++c) {
                        p.ensure_normal(topo, rules, p.tris[t].v[c]);
                        REQUIRE(p.derived[p.tris[t].v[c]].has_normal);
                        worst = std::max(worst, glm::length(p.corner_normal[3 * t + c] - uniform.corner_normal(t, c)));
                    }
                }
                CHECK(same_nodes);
                CHECK(worst <= 1e-12);
                if (level < 3) {
                    detail::Flags kept;
                    p = p.subdivide_band(topo, rules, [](const NodeId&) { return true; }, kept);
                    p.keep_only(kept);
                }
            }
        }
    }
}

TEST_CASE("base records built on several threads equal uniform subdivision", "[hierarchy][threads]") {
    // The base level's records are built in chunks of 4096 triangles, on
    // one thread per core, and a vertex keeps its first corner's values:
    // meshes of several chunks, with creases (corners whose normals differ
    // from their vertex's first one, often in another chunk) and with the
    // faces shuffled so that nearly every vertex spans chunks.
    Mesh creased = to_mesh(subdivide_uniform(testmesh::faceted_cube(), SchemeKind::normal, 5));
    Mesh shuffled = creased;
    std::mt19937 rng(5);
    std::vector<std::size_t> order(shuffled.triangles.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::shuffle(order.begin(), order.end(), rng);
    for (std::size_t i = 0; i < order.size(); ++i) {
        shuffled.triangles[i] = creased.triangles[order[i]];
        for (int c = 0; c < 3; ++c) shuffled.corner_normals[3 * i + c] = creased.corner_normals[3 * order[i] + c];
    }
    const std::vector<std::pair<const char*, Mesh>> meshes = {
        {"icosphere 5 (20480 triangles)", testmesh::icosphere(5)},
        {"faceted cube level 5 (12288 triangles, creases)", creased},
        {"the same, faces shuffled", shuffled},
    };
    for (const auto& [name, mesh] : meshes) {
        REQUIRE(mesh.triangles.size() > 2 * 4096);
        for (SchemeKind scheme : {SchemeKind::normal, SchemeKind::loop}) {
            INFO(name << " " << scheme_name(scheme));
            const Worst w = compare_with_uniform(mesh, scheme, 0, std::size_t{256} << 20);
            CHECK(w.position <= 1e-12);
            CHECK(w.normal <= k_stored_normal);
            if (scheme == SchemeKind::normal) {
                // Level 1's edge points read the base records' normals (kept
                // in double), so they hold them to 1e-12.
                CHECK(compare_with_uniform(mesh, scheme, 1, std::size_t{256} << 20).position <= 1e-12);
            }
        }
    }
}

namespace {

/// Largest distance (relative to the diagonal) between a level-`level`
/// node's corners and OpenMesh's vertices after `level` steps of the same
/// scheme; negative if a corner has no OpenMesh vertex near it or a node's
/// three corners are not one of OpenMesh's faces, in the same orientation.
double compare_with_openmesh(const Mesh& mesh, SchemeKind scheme, int level) {
    testmesh::OmMesh om = testmesh::to_openmesh(mesh);
    testmesh::openmesh_subdivide(om, scheme, level);
    const Mesh theirs = testmesh::from_openmesh(om);
    const Hierarchy hierarchy(mesh, scheme, level + 2, std::size_t{256} << 20);
    const std::size_t per_base = std::size_t{1} << (2 * level);
    std::vector<Vec3> corners;
    for (std::size_t t = 0; t < mesh.triangles.size() * per_base; ++t) {
        const NodeRecord rec = hierarchy.node(node_of_uniform_triangle(t, level));
        for (int c = 0; c < 3; ++c) corners.push_back(rec.position[c]);
    }
    const double scale = testmesh::bbox_diagonal(theirs.positions);
    double worst = 0.0;
    const std::vector<std::uint32_t> match =
        testmesh::match_positions(corners, theirs.positions, 1e-6 * scale, &worst);
    std::set<Triangle> faces;
    for (const Triangle& t : theirs.triangles) faces.insert(testmesh::canonical(t));
    for (std::size_t i = 0; i < match.size(); i += 3) {
        if (match[i] == UINT32_MAX || match[i + 1] == UINT32_MAX || match[i + 2] == UINT32_MAX)
            return -1.0;
        if (!faces.count(testmesh::canonical({match[i], match[i + 1], match[i + 2]}))) return -1.0;
    }
    return worst / scale;
}

/// Meshes without creases or given normals, closed and open: what the
/// independent references cover.
std::vector<std::pair<const char*, Mesh>> smooth_meshes() {
    return {
        {"icosahedron", testmesh::icosahedron()},
        {"torus", testmesh::torus(8, 6, 1.0, 0.35)},
        {"irregular", testmesh::irregular_closed(7)},
        {"open grid", testmesh::open_grid(4)},
    };
}

}  // namespace

TEST_CASE("adaptive Loop and Butterfly nodes equal OpenMesh's subdivision at every level",
          "[hierarchy][openmesh]") {
    const std::vector<std::pair<const char*, Mesh>> meshes = smooth_meshes();
    for (const auto& [name, mesh] : meshes) {
        for (SchemeKind scheme : {SchemeKind::loop, SchemeKind::butterfly}) {
            for (int level = 1; level <= 3; ++level) {
                INFO(name << " " << scheme_name(scheme) << " level " << level);
                const double rel = compare_with_openmesh(mesh, scheme, level);
                CHECK(rel >= 0.0);
                CHECK(rel <= 1e-12);
            }
        }
    }
}

TEST_CASE("adaptive normal-scheme nodes equal the brute-force reference at every level",
          "[hierarchy][reference]") {
    std::vector<std::pair<const char*, Mesh>> meshes = smooth_meshes();
    meshes.push_back({"half sphere (boundary)", testmesh::octasphere_half(1, true)});
    for (const auto& [name, mesh] : meshes) {
        const Hierarchy hierarchy(mesh, SchemeKind::normal, 5, std::size_t{256} << 20);
        const double scale = testmesh::bbox_diagonal(mesh.positions);
        for (int level = 0; level <= 3; ++level) {
            INFO(name << " level " << level);
            const testmesh::ReferenceLevel ref = testmesh::reference_normal_scheme(mesh, level);
            // The level's own normals are what its records shade with at max_level.
            const Hierarchy at_max_level(mesh, SchemeKind::normal, level, std::size_t{256} << 20);
            Worst worst;
            for (std::size_t t = 0; t < ref.triangles.size(); ++t) {
                const NodeRecord rec = hierarchy.node(node_of_uniform_triangle(t, level));
                const NodeRecord last = at_max_level.node(node_of_uniform_triangle(t, level));
                for (int c = 0; c < 3; ++c) {
                    const std::uint32_t v = ref.triangles[t][c];
                    worst.position = std::max(worst.position,
                                              glm::length(rec.position[c] - ref.positions[v]) / scale);
                    worst.normal = std::max(worst.normal,
                                            glm::length(last.shading_normal[c] - ref.vertex_normals[v]));
                }
            }
            CHECK(worst.position <= 1e-12);
            CHECK(worst.normal <= k_stored_normal);
        }
    }
}

TEST_CASE("hierarchy nodes do not depend on cache budget or threads", "[hierarchy][threads]") {
    const Mesh mesh = testmesh::irregular_closed(3);
    for (SchemeKind scheme : {SchemeKind::normal, SchemeKind::loop, SchemeKind::butterfly}) {
        INFO(scheme_name(scheme));
        const Hierarchy roomy(mesh, scheme, 6, std::size_t{256} << 20);
        const Hierarchy tiny(mesh, scheme, 6, 1);  // evicts almost everything
        const int level = 3;
        const std::size_t count = mesh.triangles.size() << (2 * level);
        std::vector<NodeRecord> from_threads(count);
        {
            // Two threads build the same nodes into one tiny cache at once.
            auto work = [&](std::size_t start) {
                for (std::size_t t = start; t < count; t += 2)
                    from_threads[t] = tiny.node(node_of_uniform_triangle(t, level));
                for (std::size_t t = 1 - start; t < count; t += 2)
                    tiny.node(node_of_uniform_triangle(t, level));
            };
            std::thread a(work, 0), b(work, 1);
            a.join();
            b.join();
        }
        bool identical = true;
        for (std::size_t t = 0; t < count; t += 1) {
            const NodeRecord r = roomy.node(node_of_uniform_triangle(t, level));
            const NodeRecord& s = from_threads[t];
            for (int c = 0; c < 3; ++c) {
                identical = identical && r.position[c] == s.position[c] &&
                            r.shading_normal[c] == s.shading_normal[c] && r.edge_normal[c] == s.edge_normal[c] &&
                            r.draw_position[c] == s.draw_position[c];
            }
            identical = identical && r.shell.lo == s.shell.lo && r.shell.hi == s.shell.hi;
        }
        CHECK(identical);
        CHECK(tiny.counters().evictions > 0);
    }
}

TEST_CASE("Loop leaves are drawn at the limit points of uniform subdivision", "[hierarchy]") {
    // The tracer draws a Loop vertex at its limit point computed from its
    // birth-level ring; push_to_limit computes it from the final level's ring.
    // The limit mask makes both the same point.
    for (const Mesh& mesh : {testmesh::icosahedron(), testmesh::irregular_closed(5)}) {
        const int level = 2;
        SubdividedMesh uniform = subdivide_uniform(mesh, SchemeKind::loop, level);
        push_to_limit(uniform, SchemeKind::loop);
        const Hierarchy hierarchy(mesh, SchemeKind::loop, level, std::size_t{64} << 20);
        const double scale = testmesh::bbox_diagonal(mesh.positions);
        double worst = 0.0;
        for (std::size_t t = 0; t < uniform.triangles.size(); ++t) {
            const NodeRecord rec = hierarchy.node(node_of_uniform_triangle(t, level));
            for (int k = 0; k < 3; ++k) {
            const std::uint32_t v = uniform.triangles[t][k];
                double best = 1e300;
                for (int c = 0; c < 3; ++c)
                    best = std::min(best, glm::length(rec.draw_position[c] - uniform.positions[v]));
                worst = std::max(worst, best / scale);
            }
        }
        CHECK(worst <= 1e-12);
    }
}

TEST_CASE("a node's ancestor by grid arithmetic is the one its child path went through",
          "[hierarchy]") {
    // tile.cpp finds a node's tile root and tests tile membership with
    // ancestor_at (shifts, no walk); the truth is the path of child_of calls.
    std::mt19937 rng(7);
    std::uniform_int_distribution<int> pick(0, 3);
    int checked = 0, wrong = 0;
    for (int trial = 0; trial < 2000; ++trial) {
        std::vector<NodeId> path = {Hierarchy::root(static_cast<std::uint32_t>(trial % 5))};
        for (int level = 1; level <= 9; ++level) path.push_back(child_of(path.back(), pick(rng)));
        for (std::size_t at = 0; at < path.size(); ++at) {
            for (std::size_t below = at; below < path.size(); ++below) {
                wrong += !(detail::ancestor_at(path[below], static_cast<int>(at)) == path[at]);
                ++checked;
            }
        }
    }
    CHECK(checked == 2000 * 55);
    CHECK(wrong == 0);
}

TEST_CASE("depth-first keys follow the child paths: each node's descendants are one contiguous span",
          "[hierarchy]") {
    // A child tile group finds its triangles by binary search over these
    // keys; the truth is a depth-first walk of child_of in child order.
    for (const bool down_root : {false, true}) {
        NodeId root = Hierarchy::root(3);
        if (down_root) root = child_of(child_of(root, 1), 3);  // a "down" node at level 2
        std::vector<NodeId> order;  // every descendant to 4 levels below, depth first
        const std::function<void(const NodeId&, int)> walk = [&](const NodeId& id, int depth) {
            order.push_back(id);
            if (depth < 4)
                for (int c = 0; c < 4; ++c) walk(child_of(id, c), depth + 1);
        };
        walk(root, 0);
        int out_of_order = 0, outside = 0, foreign = 0;
        for (std::size_t k = 1; k < order.size(); ++k)
            out_of_order += order[k].level == order[k - 1].level + 1
                                ? !(detail::depth_first_key(order[k]) == detail::depth_first_key(order[k - 1]))
                                : !(detail::depth_first_key(order[k - 1]) < detail::depth_first_key(order[k]));
        for (const NodeId& a : order) {
            const auto [first, last] = detail::depth_first_span(a);
            for (const NodeId& b : order) {
                const bool inside = first <= detail::depth_first_key(b) && detail::depth_first_key(b) < last;
                const bool descends = b.level >= a.level && detail::ancestor_at(b, a.level) == a;
                outside += descends && !inside;
                foreign += inside && !descends && b.level >= a.level;
            }
        }
        CHECK(order.size() == 341);
        CHECK(out_of_order == 0);
        CHECK(outside == 0);
        CHECK(foreign == 0);
    }
}

TEST_CASE("a depth-first key is the node's path of child indices, at every level up to 31", "[hierarchy]") {
    // The truth is the path itself: walk down from a root by child_of with
    // random child indices and write each index in two bits, level 1 at the top.
    std::mt19937 rng(20261207);
    std::uniform_int_distribution<int> child(0, 3);
    int wrong = 0;
    for (int walk = 0; walk < 2000; ++walk) {
        NodeId id = Hierarchy::root(static_cast<std::uint32_t>(walk));
        std::uint64_t path = 0;
        for (int level = 1; level <= 31; ++level) {
            const int c = child(rng);
            id = child_of(id, c);
            path |= static_cast<std::uint64_t>(c) << (62 - 2 * level);
            wrong += detail::depth_first_key(id) != path;
        }
    }
    CHECK(wrong == 0);
}

TEST_CASE("shading normals are the next level's normals at a node's corners and edge midpoints",
          "[hierarchy][shading]") {
    // The interpolating schemes' shading normals are their normals one level
    // down (Loop's corners use limit normals instead, not checked here): the
    // uniform level-(L+1) mesh is the independent truth, triangle 4t + c
    // being child c of level-L triangle t.
    struct Case {
        const char* name;
        Mesh mesh;
    };
    const std::vector<Case> corpus = {
        {"irregular 3..12", testmesh::irregular_closed(3)},
        {"torus", testmesh::torus(8, 6, 1.0, 0.35)},
        {"open grid (boundary)", testmesh::open_grid(4)},
        {"cylinder, split rim normals (creases)", testmesh::split_normal_cylinder(9, 1.0, 0.5)},
    };
    const auto angle = [](const Vec3& a, const Vec3& b) {
        return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
    };
    for (const Case& c : corpus) {
        for (SchemeKind scheme : {SchemeKind::normal, SchemeKind::butterfly}) {
            const Hierarchy hierarchy(c.mesh, scheme, 4, std::size_t{64} << 20);
            double worst_corner = 0.0, worst_edge = 0.0;
            for (int level = 1; level <= 2; ++level) {
                const SubdividedMesh next = subdivide_uniform(c.mesh, scheme, level + 1);
                const std::size_t count = c.mesh.triangles.size() << (2 * level);
                for (std::size_t t = 0; t < count; ++t) {
                    const NodeId id = node_of_uniform_triangle(t, level);
                    const NodeRecord rec = hierarchy.node(id);
                    std::array<NodeRecord, 4> children;
                    hierarchy.children(id, children);
                    for (int ch = 0; ch < 4; ++ch) {
                        const std::size_t u = 4 * t + static_cast<std::size_t>(ch);
                        const auto& map = child_corners(id.down, ch);
                        for (int k = 0; k < 3; ++k) {
                            // The uniform corner at this child's corner k (same position).
                            int match = 0;
                            double best = 1e300;
                            for (int q = 0; q < 3; ++q) {
                                const double d = glm::length(next.positions[next.triangles[u][q]] -
                                                             children[ch].position[k]);
                                if (d < best) best = d, match = q;
                            }
                            REQUIRE(best < 1e-12);
                            const Vec3 truth = next.corner_normal(u, match);
                            const int index = map[k].index;
                            if (map[k].is_edge) {
                                worst_edge = std::max(worst_edge, angle(Vec3(rec.edge_normal[index]), truth));
                            } else {
                                worst_corner = std::max(worst_corner, angle(rec.shading_normal[index], truth));
                            }
                        }
                    }
                    CHECK_FALSE(rec.linear_shading);
                }
            }
            INFO(c.name << " " << scheme_name(scheme) << ": worst corner " << worst_corner
                        << " rad, worst edge midpoint " << worst_edge << " rad");
            // Stored as float: a few float roundings, nothing more.
            CHECK(worst_corner < 1e-6);
            CHECK(worst_edge < 1e-6);
        }
    }
}

TEST_CASE("child shells alone are the shells of the children's records", "[hierarchy]") {
    // The tracer tests a node's child shells before it asks for the records
    // of the children it enters: both must hold the same bits.
    const Mesh mesh = testmesh::irregular_closed(3);
    for (SchemeKind scheme : {SchemeKind::normal, SchemeKind::loop, SchemeKind::butterfly}) {
        INFO(scheme_name(scheme));
        const Hierarchy h(mesh, scheme, 6, std::size_t{64} << 20);
        std::size_t compared = 0, differing = 0;
        std::vector<NodeId> level;
        for (std::uint32_t f = 0; f < mesh.triangles.size(); ++f) level.push_back(Hierarchy::root(f));
        for (int l = 0; l < 5; ++l) {
            std::vector<NodeId> next;
            for (const NodeId& id : level) {
                std::array<Shell, 4> shells;
                h.child_shells(id, shells);
                std::array<NodeRecord, 4> records;
                h.children(id, records);
                for (int c = 0; c < 4; ++c) {
                    const Shell& a = shells[c];
                    const Shell& b = records[c].shell;
                    ++compared;
                    if (!(a.lo == b.lo && a.hi == b.hi && a.axis == b.axis && a.slab_min == b.slab_min &&
                          a.slab_max == b.slab_max))
                        ++differing;
                    // A sample of each level goes one deeper (every fourth child).
                    if ((id.i + id.j + static_cast<std::uint32_t>(c)) % 4 == 0) next.push_back(child_of(id, c));
                }
            }
            level = std::move(next);
        }
        CHECK(compared > 1000);
        CHECK(differing == 0);
    }
}

TEST_CASE("geometry-only records are the whole records without their normals", "[hierarchy]") {
    // The tracer descends through Part::geometry records and reads the
    // normals of the leaf it hits from node(): everything else must be the
    // same bits, at every level and in base records too.
    const Mesh mesh = testmesh::irregular_closed(3);
    for (SchemeKind scheme : {SchemeKind::normal, SchemeKind::loop, SchemeKind::butterfly}) {
        INFO(scheme_name(scheme));
        const Hierarchy h(mesh, scheme, 5, std::size_t{64} << 20);
        std::size_t compared = 0, differing = 0, with_normals = 0;
        std::vector<NodeId> level;
        for (std::uint32_t f = 0; f < mesh.triangles.size(); ++f) level.push_back(Hierarchy::root(f));
        for (int l = 0; l <= 4; ++l) {
            std::vector<NodeId> next;
            for (const NodeId& id : level) {
                const NodeRecord whole = h.node(id);
                const NodeRecord geometry = h.node(id, Hierarchy::Part::geometry);
                ++compared;
                bool same = whole.linear_shading == geometry.linear_shading && whole.shell.lo == geometry.shell.lo &&
                            whole.shell.hi == geometry.shell.hi && whole.shell.slab_min == geometry.shell.slab_min &&
                            whole.shell.slab_max == geometry.shell.slab_max;
                for (int c = 0; c < 3; ++c) {
                    same = same && whole.position[c] == geometry.position[c] &&
                           whole.draw_position[c] == geometry.draw_position[c] &&
                           whole.displacement[c] == geometry.displacement[c] &&
                           geometry.shading_normal[c] == Vec3(0.0) && geometry.edge_normal[c] == glm::vec3(0.0f);
                    with_normals += whole.shading_normal[c] != Vec3(0.0) ? 1 : 0;
                }
                if (!same) ++differing;
                if (l < 4)
                    for (int c = 0; c < 4; ++c)
                        if ((id.i + id.j + static_cast<std::uint32_t>(c)) % 3 == 0) next.push_back(child_of(id, c));
            }
            level = std::move(next);
        }
        CHECK(compared > 500);
        CHECK(with_normals > 0);
        CHECK(differing == 0);
    }
}
