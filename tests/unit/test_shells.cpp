// Bounding shells (DESIGN.md section 4): every descendant of a node, to
// max_level, lies inside the node's shell, checked exhaustively over the
// whole hierarchy of each corpus mesh, and the conservative ray tests never
// drop a ray that grazes a flat box.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <optional>
#include <random>

#include <glm/geometric.hpp>

#include "subdivtrace/hierarchy.h"
#include "subdivtrace/shell.h"
#include "subdivtrace/uniform.h"
#include "loop_patch.h"
#include "node_shell.h"
#include "test_meshes.h"

using namespace subdivtrace;

namespace {

struct ContainmentResult {
    std::size_t nodes = 0;
    std::size_t violations = 0;
    double worst_excess = 0.0;  ///< relative to the ancestor's extent
    /// Tightness over the nodes two or more levels above max_level: mean of
    /// (shell box diagonal / diagonal of the box of all descendant drawn corners).
    double diagonal_ratio_sum = 0.0;
    std::size_t ratio_nodes = 0;
};

/// Walks every node to max_level and checks its drawn corners against the
/// shells of all its ancestors: what a ray meets below a node are the
/// triangles its descendants draw (DESIGN.md section 4). The interpolating
/// schemes draw their control points; Loop draws limit points, and its
/// control points, which no ray meets, may lie outside (a regular node's
/// shell is the box of its Bezier net, loop_patch.h).
ContainmentResult check_containment(const Mesh& mesh, SchemeKind scheme, int max_level) {
    const Hierarchy h(mesh, scheme, max_level, std::size_t{512} << 20);
    ContainmentResult r;
    std::vector<Shell> ancestors;
    // Returns the box of the node's drawn corners and all its descendants'.
    std::function<Shell(const NodeId&)> walk = [&](const NodeId& id) {
        const NodeRecord rec = h.node(id);
        ++r.nodes;
        Shell reached;
        for (int c = 0; c < 3; ++c) reached.grow(rec.draw_position[c]);
        for (const Shell& s : ancestors) {
            const double extent = glm::length(s.hi - s.lo);
            for (int c = 0; c < 3; ++c) {
                const Vec3& p = rec.draw_position[c];
                if (!s.contains(p)) {
                    ++r.violations;
                    // How far outside the box, relative to its size.
                    const Vec3 out = glm::max(s.lo - p, p - s.hi);
                    r.worst_excess = std::max(r.worst_excess, std::max({out.x, out.y, out.z, 0.0}) / extent);
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
/// their shells are the boxes of their Bezier nets (loop_patch.h).
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

TEST_CASE("Loop's regular patch is the Bezier triangle of its net", "[shells]") {
    // The limit surface over a triangle whose corners have valence 6 is one
    // quartic polynomial: its Bezier net (loop_patch.h) must reproduce every
    // limit point uniform subdivision draws inside the triangle. Level 4
    // gives 153 points per triangle, far more than the 15 that fix a quartic.
    constexpr int levels = 4;
    for (const Mesh& mesh : {testmesh::torus(8, 6, 1.0, 0.35), rough_regular_torus()}) {
        const detail::BaseTopology topo(mesh);
        const detail::SchemeRules& rules = detail::rules_of(SchemeKind::loop);
        std::vector<std::uint32_t> faces(mesh.triangles.size());
        for (std::uint32_t f = 0; f < faces.size(); ++f) faces[f] = f;
        detail::Patch p = detail::base_patch(topo, faces.data(), faces.size());
        p.finish(topo, rules);
        SubdividedMesh limit = subdivide_uniform(mesh, SchemeKind::loop, levels);
        push_to_limit(limit, SchemeKind::loop);
        // The node of each uniform triangle: children 4t .. 4t + 3 (uniform.h).
        std::vector<NodeId> node(limit.triangles.size());
        const std::size_t per_face = std::size_t{1} << (2 * levels);
        for (std::size_t k = 0; k < node.size(); ++k) {
            NodeId id = Hierarchy::root(static_cast<std::uint32_t>(k / per_face));
            for (int level = levels - 1; level >= 0; --level)
                id = child_of(id, static_cast<int>((k >> (2 * level)) & 3u));
            node[k] = id;
        }
        double worst = 0.0;
        std::size_t checked = 0;
        for (std::uint32_t t = 0; t < p.tris.size(); ++t) {
            detail::LoopPatchPoints points;
            REQUIRE(detail::loop_patch_points(p, t, points));
            const detail::LoopBezierNet net = detail::loop_bezier_net(points);
            const std::uint32_t face = p.tris[t].id.face;
            const double size = glm::length(points[1] - points[0]);
            for (std::size_t k = face * per_face; k < (face + 1) * per_face; ++k) {
                const auto grid = node_corner_grid(node[k]);
                for (int c = 0; c < 3; ++c) {
                    // Grid point (i, j) weighs n - i - j on corner 0, i on 1, j on 2.
                    const double n = 1 << levels;
                    const double u = (n - grid[c][0] - grid[c][1]) / n, v = grid[c][0] / n, w = grid[c][1] / n;
                    Vec3 at(0.0);
                    for (int q = 0; q < 15; ++q) {
                        const auto& e = detail::k_loop_bezier_index[q];
                        const double multinomial = 24.0 / (std::tgamma(e[0] + 1) * std::tgamma(e[1] + 1) * std::tgamma(e[2] + 1));
                        at += multinomial * std::pow(u, e[0]) * std::pow(v, e[1]) * std::pow(w, e[2]) * net[q];
                    }
                    worst = std::max(worst, glm::length(at - limit.positions[limit.triangles[k][c]]) / size);
                    ++checked;
                }
            }
        }
        INFO(checked << " limit points checked");
        CHECK(checked == 3 * mesh.triangles.size() * per_face);
        CHECK(worst <= 1e-12);
    }
    // A corner of valence 5 (every vertex of the icosahedron): not regular.
    const Mesh ico = testmesh::icosahedron();
    const detail::BaseTopology topo(ico);
    const std::uint32_t all[20] = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19};
    detail::Patch p = detail::base_patch(topo, all, 20);
    p.finish(topo, detail::rules_of(SchemeKind::loop));
    detail::LoopPatchPoints points;
    CHECK_FALSE(detail::loop_patch_points(p, 0, points));
}

TEST_CASE("a node's regular children one level down are Bezier triangles of its neighbourhood", "[shells]") {
    // Loop's shells bound a node child by child (loop_patch.h): the middle
    // child always, and each corner's child where that corner is regular,
    // by the Bezier net of its 12 points gathered from the node's level.
    // A net's corners are the limit points of its triangle's corners, so
    // they must be uniform subdivision's limit points there: every one of
    // the 12 lies in the ring of a corner, so a point put in the wrong place
    // moves one of them.
    for (const Mesh& mesh : {testmesh::icosahedron(), testmesh::irregular_closed(7), rough_regular_torus()}) {
        const detail::BaseTopology topo(mesh);
        const detail::SchemeRules& rules = detail::rules_of(SchemeKind::loop);
        std::vector<std::uint32_t> faces(mesh.triangles.size());
        for (std::uint32_t f = 0; f < faces.size(); ++f) faces[f] = f;
        detail::Patch p = detail::base_patch(topo, faces.data(), faces.size());
        for (int level = 0; level <= 1; ++level) {
            p.finish(topo, rules);
            detail::Patch next;
            p.next_positions(topo, rules, nullptr, next);
            const SubdividedMesh control = subdivide_uniform(mesh, SchemeKind::loop, level + 1);
            SubdividedMesh limit = control;
            push_to_limit(limit, SchemeKind::loop);
            const auto limit_of = [&](const Vec3& at) {
                for (std::size_t v = 0; v < control.positions.size(); ++v)
                    if (glm::length(control.positions[v] - at) <= 1e-9) return limit.positions[v];
                FAIL("no vertex of uniform level " << level + 1 << " at a child's corner");
                return Vec3(0.0);
            };
            std::size_t nets = 0, corner_children = 0;
            double worst = 0.0;
            for (std::uint32_t t = 0; t < p.tris.size(); ++t) {
                detail::LoopChildren ch;
                REQUIRE(detail::loop_children_points(p, next, t, ch));
                for (int k = 0; k < 4; ++k) {
                    if (k < 3 && !ch.regular[k]) continue;
                    corner_children += k < 3 ? 1 : 0;
                    const detail::LoopBezierNet net = detail::loop_bezier_net(ch.points[k]);
                    // b400, b040 and b004: the limit points of corners P0, P1, P2.
                    const int corner_of[3] = {0, 14, 4};
                    for (int c = 0; c < 3; ++c)
                        worst = std::max(worst, glm::length(net[corner_of[c]] - limit_of(ch.points[k][c])));
                    ++nets;
                }
            }
            INFO(nets << " nets, " << corner_children << " of them corner children, level " << level);
            CHECK(nets >= p.tris.size());
            CHECK(worst <= 1e-12);
            detail::Flags kept;
            p = p.subdivide_band(topo, rules, [](const NodeId&) { return true; }, kept);
            p.keep_only(kept);
        }
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

TEST_CASE("an irregular corner's child refined level by level: Bezier triangles and the corner's frame", "[shells]") {
    // Where a node's corner is not regular, its child there is bounded by
    // the frame of control points it depends on (loop_corner_frame),
    // refined level by level (refine_corner_frame): three Bezier triangles
    // a level, and the frame of the child left at the corner. Every point
    // of a frame must be a vertex of uniform subdivision at its level, each
    // net's corners the limit points of its triangle's corners there (a
    // point in the wrong place moves one), and every corner a descendant
    // draws, two levels below, must lie in the box of its net, or of the
    // last frame for the child at the corner.
    constexpr int refinements = 2, below = 2;
    for (const Mesh& mesh : {testmesh::icosahedron(), testmesh::irregular_closed(7), testmesh::high_valence_fan(12)}) {
        const detail::BaseTopology topo(mesh);
        const detail::SchemeRules& rules = detail::rules_of(SchemeKind::loop);
        std::vector<std::uint32_t> faces(mesh.triangles.size());
        for (std::uint32_t f = 0; f < faces.size(); ++f) faces[f] = f;
        detail::Patch p = detail::base_patch(topo, faces.data(), faces.size());
        const Hierarchy h(mesh, SchemeKind::loop, 2 + refinements + below, std::size_t{512} << 20);
        // Uniform levels 1 .. 2 + refinements: control points, sorted by x
        // to be found, and their limit points.
        struct Level {
            SubdividedMesh control, limit;
            std::vector<std::pair<double, std::size_t>> by_x;
        };
        std::vector<Level> uniform(3 + refinements);
        for (int level = 1; level < static_cast<int>(uniform.size()); ++level) {
            Level& u = uniform[level];
            u.control = subdivide_uniform(mesh, SchemeKind::loop, level);
            u.limit = u.control;
            push_to_limit(u.limit, SchemeKind::loop);
            for (std::size_t v = 0; v < u.control.positions.size(); ++v) u.by_x.push_back({u.control.positions[v].x, v});
            std::sort(u.by_x.begin(), u.by_x.end());
        }
        // The vertex of uniform level `level` at `at`, or none.
        const auto vertex_at = [&](int level, const Vec3& at) -> std::optional<std::size_t> {
            const Level& u = uniform[level];
            for (auto it = std::lower_bound(u.by_x.begin(), u.by_x.end(), std::make_pair(at.x - 1e-9, std::size_t{0}));
                 it != u.by_x.end() && it->first <= at.x + 1e-9; ++it)
                if (glm::length(u.control.positions[it->second] - at) <= 1e-9) return it->second;
            return std::nullopt;
        };
        for (int level = 0; level <= 1; ++level) {
            p.finish(topo, rules);
            detail::Patch next;
            p.next_positions(topo, rules, nullptr, next);
            std::size_t corners = 0, nets = 0, drawn = 0, outside = 0, not_vertices = 0;
            double worst = 0.0;
            const auto check_frame = [&](const detail::LoopCornerFrame& f, int at_level) {
                for (const Vec3& x : {f.P, f.X, f.Y, f.M, f.XB, f.YC, f.XD1, f.XD2, f.YF1, f.YF2})
                    not_vertices += vertex_at(at_level, x) ? 0 : 1;
                for (const Vec3& x : f.ring) not_vertices += vertex_at(at_level, x) ? 0 : 1;
            };
            // Every corner drawn below `id`, `below` levels down, in `box`.
            const auto check_descendants = [&](const NodeId& top, const Shell& box) {
                const double slack = 1e-12 * glm::length(box.hi - box.lo);
                std::function<void(const NodeId&)> walk = [&](const NodeId& id) {
                    for (const Vec3& x : h.node(id).draw_position) {
                        ++drawn;
                        const Vec3 out = glm::max(box.lo - x, x - box.hi);
                        if (std::max({out.x, out.y, out.z}) > slack) ++outside;
                    }
                    if (id.level < top.level + below)
                        for (int q = 0; q < 4; ++q) walk(child_of(id, q));
                };
                walk(top);
            };
            for (std::uint32_t t = 0; t < p.tris.size(); ++t) {
                detail::LoopChildren ch;
                REQUIRE(detail::loop_children_points(p, next, t, ch));
                for (int c = 0; c < 3; ++c) {
                    detail::LoopCornerFrame frame, refined;
                    if (ch.regular[c] || !detail::loop_corner_frame(p, next, t, c, ch, frame)) continue;
                    ++corners;
                    check_frame(frame, level + 1);
                    NodeId node = child_of(p.tris[t].id, c);  // the corner's child
                    for (int r = 1; r <= refinements; ++r) {
                        std::array<detail::LoopPatchPoints, 3> points;
                        detail::refine_corner_frame(frame, points, refined);
                        frame = refined;
                        const int at_level = level + 1 + r;
                        check_frame(frame, at_level);
                        // The node's children: three by their nets, told
                        // apart by their corners, the fourth at the corner.
                        NodeId at_corner = node;
                        for (int k = 0; k < 4; ++k) {
                            const NodeId child = child_of(node, k);
                            const NodeRecord rec = h.node(child);
                            int which = -1;
                            for (int n = 0; n < 3; ++n) {
                                int shared = 0;
                                for (const Vec3& x : rec.position)
                                    for (int q = 0; q < 3; ++q) shared += glm::length(x - points[n][q]) <= 1e-12 ? 1 : 0;
                                if (shared == 3) which = n;
                            }
                            if (which < 0) {
                                at_corner = child;
                                continue;
                            }
                            const detail::LoopBezierNet net = detail::loop_bezier_net(points[which]);
                            const int corner_of[3] = {0, 14, 4};
                            for (int q = 0; q < 3; ++q) {
                                const std::optional<std::size_t> v = vertex_at(at_level, points[which][q]);
                                REQUIRE(v);
                                worst = std::max(worst, glm::length(net[corner_of[q]] - uniform[at_level].limit.positions[*v]));
                            }
                            Shell box;
                            for (const Vec3& b : net) box.grow(b);
                            check_descendants(child, box);
                            ++nets;
                        }
                        REQUIRE_FALSE(at_corner == node);
                        node = at_corner;
                    }
                    Shell hull;
                    frame.grow(hull);
                    check_descendants(node, hull);
                }
            }
            INFO(corners << " irregular corners, " << nets << " nets, " << drawn << " drawn corners, level " << level);
            CHECK(corners > 0);
            CHECK(nets == 3 * refinements * corners);
            CHECK(not_vertices == 0);
            CHECK(worst <= 1e-12);
            CHECK(outside == 0);
            detail::Flags kept;
            p = p.subdivide_band(topo, rules, [](const NodeId&) { return true; }, kept);
            p.keep_only(kept);
        }
    }
}
