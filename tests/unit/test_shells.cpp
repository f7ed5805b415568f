// Bounding shells (DESIGN.md section 4): every descendant of a node, to
// max_level, lies inside the node's shell, checked exhaustively over the
// whole hierarchy of each corpus mesh, and the conservative ray tests never
// drop a ray that grazes a flat box.
#include <catch2/catch.hpp>

#include <algorithm>
#include <functional>
#include <random>

#include <glm/geometric.hpp>

#include "subdivtrace/hierarchy.h"
#include "subdivtrace/shell.h"
#include "subdivtrace/uniform.h"
#include "node_shell.h"
#include "test_meshes.h"

using namespace subdivtrace;

namespace {

struct ContainmentResult {
    std::size_t nodes = 0;
    std::size_t violations = 0;
    double worst_excess = 0.0;  ///< relative to the ancestor's extent
    /// Tightness over the nodes two or more levels above max_level: mean of
    /// (shell box diagonal / diagonal of the box of all descendant corners).
    double diagonal_ratio_sum = 0.0;
    std::size_t ratio_nodes = 0;
};

/// Walks every node to max_level and checks its corners (and drawn corners)
/// against the shells of all its ancestors.
ContainmentResult check_containment(const Mesh& mesh, SchemeKind scheme, int max_level) {
    const Hierarchy h(mesh, scheme, max_level, std::size_t{512} << 20);
    ContainmentResult r;
    std::vector<Shell> ancestors;
    // Returns the box of the node's corners and all its descendants' corners.
    std::function<Shell(const NodeId&)> walk = [&](const NodeId& id) {
        const NodeRecord rec = h.node(id);
        ++r.nodes;
        Shell reached;
        for (int c = 0; c < 3; ++c) {
            reached.grow(rec.position[c]);
            reached.grow(rec.draw_position[c]);
        }
        for (const Shell& s : ancestors) {
            const double extent = glm::length(s.hi - s.lo);
            for (int c = 0; c < 3; ++c) {
                for (const Vec3& p : {rec.position[c], rec.draw_position[c]}) {
                    if (!s.contains(p)) {
                        ++r.violations;
                        // How far outside the box, relative to its size.
                        const Vec3 out = glm::max(s.lo - p, p - s.hi);
                        r.worst_excess = std::max(
                            r.worst_excess, std::max({out.x, out.y, out.z, 0.0}) / extent);
                    }
                }
            }
        }
        if (id.level >= max_level) return reached;
        ancestors.push_back(rec.shell);
        for (int c = 0; c < 4; ++c) {
            const Shell below = walk(child_of(id, c));
            reached.grow(below.lo);
            reached.grow(below.hi);
        }
        ancestors.pop_back();
        const double reached_diagonal = glm::length(reached.hi - reached.lo);
        if (id.level + 2 <= max_level && reached_diagonal > 0.0) {
            r.diagonal_ratio_sum += glm::length(rec.shell.hi - rec.shell.lo) / reached_diagonal;
            ++r.ratio_nodes;
        }
        return reached;
    };
    for (std::uint32_t f = 0; f < mesh.triangles.size(); ++f) walk(Hierarchy::root(f));
    return r;
}

/// A torus whose every vertex has valence 6, each moved by up to half an
/// edge in a random direction (seeded): Loop's patches are all regular, so
/// their shells reach from their own points toward their rings by
/// k_loop_ring_weight (node_shell.h) only.
Mesh rough_regular_torus() {
    Mesh m = testmesh::torus(8, 6, 1.0, 0.35);
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> jitter(-0.18, 0.18);
    for (Vec3& p : m.positions) p += Vec3(jitter(rng), jitter(rng), jitter(rng));
    return m;
}

}  // namespace

TEST_CASE("shells contain every descendant up to max_level", "[shells][slow]") {
    struct Case {
        const char* name;
        Mesh mesh;
        int levels;
    };
    const std::vector<Case> corpus = {
        {"icosahedron", testmesh::icosahedron(), 6},
        {"torus", testmesh::torus(8, 6, 1.0, 0.35), 5},
        {"rough torus, every vertex of valence 6", rough_regular_torus(), 5},
        {"irregular 3..12", testmesh::irregular_closed(7), 4},
        {"open grid", testmesh::open_grid(4), 5},
        {"sliver 1e6", testmesh::sliver_mesh(), 5},
        {"high valence 100", testmesh::high_valence_fan(100), 4},
        {"folded", testmesh::folded(), 5},
        {"faceted cube (creases)", testmesh::faceted_cube(), 5},
        {"cylinder, split rim normals", testmesh::split_normal_cylinder(9, 1.0, 0.5), 5},
        {"half sphere (boundary)", testmesh::octasphere_half(1, true), 5},
        {"offset 1e6, detail 1e-3",
         testmesh::offset_mesh(testmesh::icosahedron(), Vec3(1e6, -1e6, 1e6), 1e-3), 5},
        {"scale 1e-6", testmesh::offset_mesh(testmesh::icosahedron(), Vec3(0.0), 1e-6), 5},
    };
    for (const Case& c : corpus) {
        for (SchemeKind scheme : {SchemeKind::normal, SchemeKind::loop, SchemeKind::butterfly}) {
            const ContainmentResult r = check_containment(c.mesh, scheme, c.levels);
            const double tightness = r.diagonal_ratio_sum / std::max<std::size_t>(1, r.ratio_nodes);
            INFO(c.name << " " << scheme_name(scheme) << ": " << r.nodes << " nodes, worst excess "
                        << r.worst_excess);
            CHECK(r.violations == 0);
            // Containment makes every shell at least as large as what it holds.
            CHECK(tightness >= 1.0);
            WARN(c.name << " " << scheme_name(scheme) << ": shell / descendants diagonal "
                        << tightness << " (mean over " << r.ratio_nodes << " nodes)");
        }
    }
}

TEST_CASE("Loop's ring around a regular triangle weighs at most k_loop_ring_weight below it", "[shells]") {
    // Loop is linear: subdividing the mesh with one coordinate raised by 1 at
    // the nine vertices around base triangle T, and subtracting the plain
    // mesh's subdivision, leaves that coordinate equal to the nine's weight
    // in every point below T, control point or limit point. Regular: every
    // vertex of the torus has valence 6.
    const Mesh plain = testmesh::torus(12, 12, 1.0, 0.35);
    const std::uint32_t t = 40;
    const Triangle& tri = plain.triangles[t];
    std::vector<bool> around(plain.positions.size(), false);
    for (const Triangle& other : plain.triangles) {
        const bool touches = std::any_of(tri.begin(), tri.end(), [&](std::uint32_t v) {
            return std::count(other.begin(), other.end(), v) != 0;
        });
        if (touches)
            for (std::uint32_t v : other) around[v] = true;
    }
    for (std::uint32_t v : tri) around[v] = false;
    REQUIRE(std::count(around.begin(), around.end(), true) == 9);
    Mesh raised = plain;
    for (std::size_t v = 0; v < raised.positions.size(); ++v)
        if (around[v]) raised.positions[v].x += 1.0;
    for (bool limit : {false, true}) {
        SubdividedMesh a = subdivide_uniform(plain, SchemeKind::loop, 5);
        SubdividedMesh b = subdivide_uniform(raised, SchemeKind::loop, 5);
        if (limit) {
            push_to_limit(a, SchemeKind::loop);
            push_to_limit(b, SchemeKind::loop);
        }
        double heaviest = 0.0;
        for (std::size_t k = 0; k < a.triangles.size(); ++k) {
            if (a.base_face[k] != t) continue;
            for (std::uint32_t v : a.triangles[k]) heaviest = std::max(heaviest, b.positions[v].x - a.positions[v].x);
        }
        INFO((limit ? "limit points" : "control points at level 5") << ": the ring weighs " << heaviest);
        CHECK(heaviest <= detail::k_loop_ring_weight);
        // Tight: at T's corners the limit point takes exactly 1/3 from the ring.
        CHECK(heaviest >= (limit ? 1.0 / 3.0 - 1e-12 : 0.33));
    }
}

TEST_CASE("conservative slab test keeps rays that graze flat boxes", "[shells]") {
    // A box flat in z (a triangle lying in the plane z = 0.1) and rays that
    // skim it at shallow angles: the plain slab test loses some of these.
    const Vec3 lo(-1.0, -1.0, 0.1), hi(1.0, 1.0, 0.1);
    std::size_t kept = 0, total = 0;
    for (int k = 1; k <= 2000; ++k) {
        const double s = k * 1e-4;
        const Vec3 origin(-3.0, 0.3 * s, 0.1 + s * 1e-9);
        const Vec3 target(0.5, 0.2, 0.1);
        const RayBoxQuery q = make_ray_box_query(origin, target - origin, 0.0, 1e300);
        double t = 0.0;
        ++total;
        kept += ray_hits_box(q, lo, hi, t) ? 1 : 0;
    }
    CHECK(kept == total);
}
