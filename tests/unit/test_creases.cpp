// Given normals, creases from split normals and the curve rule for boundaries
// (docs/schemes.md, "Given normals" and "Creases and boundaries"): each
// against an independent truth (an analytic shape, a hand-computed stencil,
// the same rule applied to the mesh without normals).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>

#include <glm/geometric.hpp>

#include "creases.h"
#include "subdivtrace/hierarchy.h"
#include "subdivtrace/tracer.h"
#include "subdivtrace/uniform.h"
#include "test_meshes.h"

using namespace subdivtrace;

namespace {

constexpr double k_pi = 3.14159265358979323846;

/// Index of the vertex of `positions` nearest to p, and its distance.
std::pair<std::size_t, double> nearest(const std::vector<Vec3>& positions, const Vec3& p) {
    std::size_t best = 0;
    double best_d = 1e300;
    for (std::size_t v = 0; v < positions.size(); ++v) {
        const double d = glm::length(positions[v] - p);
        if (d < best_d) best = v, best_d = d;
    }
    return {best, best_d};
}

double angle_between(const Vec3& a, const Vec3& b) {
    return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

/// A fold: a crease polyline P0..P4 along a gentle curve, with a strip of
/// triangles on each side meeting at an angle; side A's corners carry one
/// normal and side B's another, so the polyline is a crease.
struct Fold {
    Mesh mesh;
    std::uint32_t crease[5];
};

Fold fold() {
    Fold f;
    Mesh& m = f.mesh;
    const auto crease_point = [](int i) { return Vec3(i, 0.0, 0.1 * i * i); };
    for (int i = 0; i < 5; ++i) {
        f.crease[i] = static_cast<std::uint32_t>(m.positions.size());
        m.positions.push_back(crease_point(i));
    }
    std::uint32_t side_a[5], side_b[5];
    for (int i = 0; i < 5; ++i) {
        // Uneven sides, so that no smooth rule happens to equal a curve rule.
        side_a[i] = static_cast<std::uint32_t>(m.positions.size());
        m.positions.push_back(crease_point(i) + Vec3(0.1 * (i % 2), 1.0, 0.05 * i));
        side_b[i] = static_cast<std::uint32_t>(m.positions.size());
        m.positions.push_back(crease_point(i) + Vec3(0.0, -0.3, -1.0 - 0.1 * (i % 2)));
    }
    const Vec3 normal_a(0.0, 0.0, 1.0), normal_b(0.0, -0.96, 0.28);
    for (int i = 0; i < 4; ++i) {
        const std::uint32_t p = f.crease[i], q = f.crease[i + 1];
        for (const Triangle& t : {Triangle{p, q, side_a[i + 1]}, Triangle{p, side_a[i + 1], side_a[i]}}) {
            m.triangles.push_back(t);
            for (int c = 0; c < 3; ++c) m.corner_normals.push_back(normal_a);
        }
        for (const Triangle& t : {Triangle{q, p, side_b[i]}, Triangle{q, side_b[i], side_b[i + 1]}}) {
            m.triangles.push_back(t);
            for (int c = 0; c < 3; ++c) m.corner_normals.push_back(normal_b);
        }
    }
    return f;
}

/// Boundary vertices (z == 0 exactly) of a subdivided octasphere half, by angle.
std::vector<Vec3> equator(const SubdividedMesh& sub) {
    std::vector<Vec3> out;
    for (const Vec3& p : sub.positions)
        if (p.z == 0.0) out.push_back(p);
    std::sort(out.begin(), out.end(),
              [](const Vec3& a, const Vec3& b) { return std::atan2(a.y, a.x) < std::atan2(b.y, b.x); });
    return out;
}

}  // namespace

TEST_CASE("split normals mark creases, equal ones do not", "[creases]") {
    const Mesh cube = testmesh::faceted_cube();
    const auto masks = detail::crease_masks(cube);
    std::size_t crease_edges = 0;
    for (std::uint8_t m : masks) crease_edges += (m & 1) + (m >> 1 & 1) + (m >> 2 & 1);
    // 12 cube edges (each counted from both sides) plus the 6 face diagonals,
    // whose endpoints carry equal normals on both sides: not creases.
    CHECK(crease_edges == 2 * 12);
    CHECK(detail::crease_masks(testmesh::icosphere_with_normals(1)) ==
          std::vector<std::uint8_t>(80, 0));
    const Mesh cylinder = testmesh::split_normal_cylinder(12, 1.0, 1.0);
    std::size_t rim = 0;
    for (std::uint8_t m : detail::crease_masks(cylinder)) rim += (m & 1) + (m >> 1 & 1) + (m >> 2 & 1);
    CHECK(rim == 2 * 2 * 12);  // two rims of 12 edges, from both sides
}

TEST_CASE("the normal scheme's level-0 normals are the given ones", "[creases][given]") {
    // Normals deliberately bent away from the computed ones (a mesh2 user's own).
    Mesh mesh = testmesh::icosphere(1);
    for (const Triangle& t : mesh.triangles)
        for (std::uint32_t v : t) mesh.corner_normals.push_back(glm::normalize(mesh.positions[v] + Vec3(0.3, 0, 0)));
    const SubdividedMesh level0 = subdivide_uniform(mesh, SchemeKind::normal, 0);
    const Hierarchy hierarchy(mesh, SchemeKind::normal, 3, std::size_t{64} << 20);
    double worst_uniform = 0.0, worst_node = 0.0;
    for (std::uint32_t f = 0; f < mesh.triangles.size(); ++f) {
        const NodeRecord rec = hierarchy.node(Hierarchy::root(f));
        for (int c = 0; c < 3; ++c) {
            const Vec3 given = glm::normalize(mesh.corner_normals[3 * f + c]);
            worst_uniform = std::max(worst_uniform, glm::length(level0.corner_normal(f, c) - given));
            // Shaded with as given, as mesh2 does.
            worst_node = std::max(worst_node, glm::length(rec.shading_normal[c] - given));
        }
    }
    CHECK(worst_uniform <= 1e-15);
    CHECK(worst_node <= 1e-7);  // kept in floats

    // They shape the surface: level 2 moves away from the computed-normal one.
    Mesh plain = mesh;
    plain.corner_normals.clear();
    const SubdividedMesh bent = subdivide_uniform(mesh, SchemeKind::normal, 2);
    const SubdividedMesh computed = subdivide_uniform(plain, SchemeKind::normal, 2);
    double moved = 0.0;
    for (std::size_t v = 0; v < bent.positions.size(); ++v)
        moved = std::max(moved, glm::length(bent.positions[v] - computed.positions[v]));
    CHECK(moved > 1e-3);

    // Loop and Butterfly read positions only: unsplit given normals change nothing.
    for (SchemeKind scheme : {SchemeKind::loop, SchemeKind::butterfly}) {
        const SubdividedMesh a = subdivide_uniform(mesh, scheme, 3);
        const SubdividedMesh b = subdivide_uniform(plain, scheme, 3);
        CHECK(a.positions == b.positions);
    }
}

TEST_CASE("a cube with faceted normals stays a cube in every scheme", "[creases]") {
    const Mesh cube = testmesh::faceted_cube();
    for (SchemeKind scheme : {SchemeKind::normal, SchemeKind::loop, SchemeKind::butterfly}) {
        INFO(scheme_name(scheme));
        SubdividedMesh sub = subdivide_uniform(cube, scheme, 4);
        push_to_limit(sub, scheme);
        double off_surface = 0.0, normal_error = 0.0;
        for (const Vec3& p : sub.positions)
            off_surface = std::max(off_surface, std::abs(std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)}) - 1.0));
        for (std::size_t t = 0; t < sub.triangles.size(); ++t) {
            const auto& tri = sub.triangles[t];
            const Vec3 face = glm::normalize(glm::cross(sub.positions[tri[1]] - sub.positions[tri[0]],
                                                        sub.positions[tri[2]] - sub.positions[tri[0]]));
            for (int c = 0; c < 3; ++c)
                normal_error = std::max(normal_error, glm::length(sub.corner_normal(t, c) - face));
        }
        CHECK(off_surface <= 1e-15);
        CHECK(normal_error <= 1e-15);
    }
    // Without its normals the same cube rounds off (bulges out, here).
    Mesh plain = cube;
    plain.corner_normals.clear();
    const SubdividedMesh round = subdivide_uniform(plain, SchemeKind::normal, 3);
    double off = 0.0;
    for (const Vec3& p : round.positions)
        off = std::max(off, std::abs(std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)}) - 1.0));
    CHECK(off > 0.05);
}

TEST_CASE("a cylinder with split rim normals keeps sharp rims and round sides", "[creases]") {
    const double r = 1.0, h = 0.8;
    const Mesh cylinder = testmesh::split_normal_cylinder(12, r, h);
    const SubdividedMesh sub = subdivide_uniform(cylinder, SchemeKind::normal, 4);
    double rim_radius_error = 0.0, side_radius_error = 0.0, cap_flatness = 0.0;
    double smallest_rim_angle = k_pi;
    std::size_t rim_vertices = 0;
    // Per vertex: the spread of its corner normals.
    std::vector<Vec3> first_normal(sub.positions.size(), Vec3(0.0));
    std::vector<double> spread(sub.positions.size(), 0.0);
    for (std::size_t t = 0; t < sub.triangles.size(); ++t)
        for (int c = 0; c < 3; ++c) {
            const std::uint32_t v = sub.triangles[t][c];
            const Vec3 n = sub.corner_normal(t, c);
            if (first_normal[v] == Vec3(0.0)) first_normal[v] = n;
            spread[v] = std::max(spread[v], angle_between(first_normal[v], n));
        }
    for (std::uint32_t v = 0; v < sub.positions.size(); ++v) {
        const Vec3& p = sub.positions[v];
        const double radius = std::hypot(p.x, p.y);
        if (std::abs(std::abs(p.z) - h) > 1e-12) {
            side_radius_error = std::max(side_radius_error, std::abs(radius - r));
            continue;
        }
        if (radius < 0.97 * r) {  // on a cap (level 4: its points nearest the rim are at 15/16 r)
            cap_flatness = std::max(cap_flatness, std::abs(std::abs(p.z) - h));
            continue;
        }
        ++rim_vertices;
        rim_radius_error = std::max(rim_radius_error, std::abs(radius - r));
        smallest_rim_angle = std::min(smallest_rim_angle, spread[v]);
    }
    INFO("rim radius error " << rim_radius_error << ", side " << side_radius_error
                             << ", smallest normal jump at the rim " << smallest_rim_angle);
    CHECK(rim_vertices == 2 * 12 * 16);
    // 12 segments: the Hermite curve of the circle's tangents stays within
    // 3e-3 of it, where the 12-gon's edges are 0.034 inside it.
    CHECK(rim_radius_error < 3e-3);
    CHECK(side_radius_error < 3e-3);
    CHECK(cap_flatness <= 1e-15);
    // The rim stays sharp at every vertex on it: the two sides' normals
    // differ by about 90 degrees.
    CHECK(smallest_rim_angle > 0.45 * k_pi);
}

TEST_CASE("crease stencils: Loop midpoint and (1,6,1)/8, Butterfly 4-point, by hand", "[creases]") {
    const Fold f = fold();
    const Mesh& m = f.mesh;
    const auto P = [&](int i) { return m.positions[f.crease[i]]; };
    Mesh plain = m;
    plain.corner_normals.clear();
    {
        const SubdividedMesh loop = subdivide_uniform(m, SchemeKind::loop, 1);
        const SubdividedMesh smooth = subdivide_uniform(plain, SchemeKind::loop, 1);
        for (int i = 1; i <= 3; ++i) {
            INFO("crease vertex " << i);
            const Vec3 expected = (P(i - 1) + 6.0 * P(i) + P(i + 1)) / 8.0;
            CHECK(glm::length(loop.positions[f.crease[i]] - expected) <= 1e-15);
            CHECK(glm::length(smooth.positions[f.crease[i]] - expected) > 1e-3);  // the smooth rule differs
        }
        for (int i = 0; i < 4; ++i) {
            INFO("crease edge " << i);
            CHECK(nearest(loop.positions, (P(i) + P(i + 1)) * 0.5).second <= 1e-15);
        }
        // The fold's ends are boundary corners (three curve edges): they stay.
        CHECK(loop.positions[f.crease[0]] == P(0));
    }
    {
        const SubdividedMesh butterfly = subdivide_uniform(m, SchemeKind::butterfly, 1);
        const SubdividedMesh smooth = subdivide_uniform(plain, SchemeKind::butterfly, 1);
        for (int i = 1; i <= 2; ++i) {
            INFO("crease edge " << i);
            const Vec3 expected = (P(i) + P(i + 1)) * (9.0 / 16.0) - (P(i - 1) + P(i + 2)) * (1.0 / 16.0);
            CHECK(nearest(butterfly.positions, expected).second <= 1e-15);
            CHECK(nearest(smooth.positions, expected).second > 1e-3);
        }
        // Next to a corner the curve has no far point there: the midpoint.
        CHECK(nearest(butterfly.positions, (P(0) + P(1)) * 0.5).second <= 1e-15);
    }
    {
        // The normal scheme follows the Hermite curve of the polyline's
        // tangents: the crease samples the parabola z = 0.1 x^2 (where the
        // direction between a point's neighbours is the exact tangent), so
        // the new point on P1-P2 lies on it to 2e-4, where the chord's
        // midpoint is 0.025 off. It stays in the crease's plane y = 0.
        const SubdividedMesh normal = subdivide_uniform(m, SchemeKind::normal, 1);
        const auto [v, d] = nearest(normal.positions, Vec3(1.5, 0.0, 0.225));
        const Vec3 p = normal.positions[v];
        CHECK(d < 0.01);
        CHECK(p.y == 0.0);
        CHECK(std::abs(p.z - 0.1 * p.x * p.x) < 2e-4);
    }
}

TEST_CASE("two open meshes that share a boundary meet along one curve at every level", "[creases][boundary]") {
    const Mesh upper = testmesh::octasphere_half(2, true);
    const Mesh lower = testmesh::octasphere_half(2, false);
    for (SchemeKind scheme : {SchemeKind::normal, SchemeKind::loop, SchemeKind::butterfly}) {
        for (int level = 1; level <= 4; ++level) {
            INFO(scheme_name(scheme) << " level " << level);
            SubdividedMesh a = subdivide_uniform(upper, scheme, level);
            SubdividedMesh b = subdivide_uniform(lower, scheme, level);
            push_to_limit(a, scheme);
            push_to_limit(b, scheme);
            const std::vector<Vec3> ea = equator(a), eb = equator(b);
            REQUIRE(ea.size() == 16u << level);
            REQUIRE(eb.size() == ea.size());
            double gap = 0.0;
            for (std::size_t k = 0; k < ea.size(); ++k) gap = std::max(gap, glm::length(ea[k] - eb[k]));
            CHECK(gap <= 1e-15);
        }
    }
}

TEST_CASE("print given normals kept at every level against level 0 only", "[.][given-normals-table]") {
    // docs/schemes.md, "Given normals": spheres with exact sphere normals.
    // The icosahedral ones are symmetric enough that Gouraud normals are
    // radial too; the irregular one (valences 3..12, vertices on the sphere) is not.
    Mesh irregular = testmesh::irregular_closed(7);
    for (Vec3& p : irregular.positions) p = glm::normalize(p);
    for (const Triangle& t : irregular.triangles)
        for (std::uint32_t v : t) irregular.corner_normals.push_back(irregular.positions[v]);
    const std::vector<std::pair<const char*, Mesh>> meshes = {
        {"icosahedron (20)", testmesh::icosphere_with_normals(0)},
        {"icosphere (80)", testmesh::icosphere_with_normals(1)},
        {"irregular sphere (320)", irregular},
    };
    for (const auto& [name, mesh] : meshes) {
        for (bool every_level : {true, false}) {
            const SubdividedMesh sub = detail::subdivide_uniform(mesh, SchemeKind::normal, 4, every_level);
            double radial = 0.0, centroid = 0.0, dihedral = 0.0;
            for (const Vec3& p : sub.positions) radial = std::max(radial, std::abs(glm::length(p) - 1.0));
            std::map<std::pair<std::uint32_t, std::uint32_t>, Vec3> edge_normal;
            for (const Triangle& t : sub.triangles) {
                const Vec3 c = (sub.positions[t[0]] + sub.positions[t[1]] + sub.positions[t[2]]) / 3.0;
                centroid = std::max(centroid, std::abs(glm::length(c) - 1.0));
                const Vec3 n = glm::normalize(glm::cross(sub.positions[t[1]] - sub.positions[t[0]],
                                                         sub.positions[t[2]] - sub.positions[t[0]]));
                for (int e = 0; e < 3; ++e) {
                    const auto key = std::minmax(t[e], t[(e + 1) % 3]);
                    const auto [it, inserted] = edge_normal.emplace(key, n);
                    if (!inserted) dihedral = std::max(dihedral, angle_between(it->second, n));
                }
            }
            std::printf("| %s | %s | %.3g | %.3g | %.3g |\n", name,
                        every_level ? "every level" : "level 0 only", radial, centroid,
                        dihedral * 180.0 / k_pi);
        }
    }
}

TEST_CASE("inside() of a refined faceted cube is the cube, every scheme", "[creases][tracer]") {
    // The cube stays a cube at every level, so the parity test has an exact
    // answer: inside iff max(|x|, |y|, |z|) < 1 (points kept 1e-3 off faces).
    const Mesh cube = testmesh::faceted_cube();
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-1.6, 1.6);
    for (SchemeKind scheme : {SchemeKind::normal, SchemeKind::loop, SchemeKind::butterfly}) {
        SurfaceOptions o;
        o.scheme = scheme;
        o.max_level = 4;
        o.tolerance = 0.25;
        o.view.pixel_angle = 1e-3;
        o.view.camera = Vec3(3.0, 2.0, -4.0);
        const AdaptiveSurface surface(cube, o);
        int wrong = 0, tested = 0;
        for (int k = 0; k < 400; ++k) {
            const Vec3 p(u(rng), u(rng), u(rng));
            const double m = std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)});
            if (std::abs(m - 1.0) < 1e-3) continue;
            ++tested;
            if (surface.inside(p) != (m < 1.0)) ++wrong;
        }
        INFO(scheme_name(scheme) << ": " << wrong << " of " << tested << " points wrong");
        CHECK(wrong == 0);
    }
}

TEST_CASE("to_mesh of a temporary gives what the copying to_mesh gives", "[creases][uniform]") {
    // A cube with faceted normals (corners whose normal is not their
    // vertex's) and given UVs, two levels down: the moving conversion must
    // hand over the same positions, triangles, UVs and corner normals, and
    // each corner normal must be SubdividedMesh::corner_normal's.
    Mesh cube = testmesh::faceted_cube();
    for (std::size_t c = 0; c < 3 * cube.triangles.size(); ++c)
        cube.corner_uvs.push_back(Vec2(0.1 * static_cast<double>(c % 7), 0.2 * static_cast<double>(c % 5)));
    for (const SchemeKind scheme : {SchemeKind::normal, SchemeKind::loop, SchemeKind::butterfly}) {
        const SubdividedMesh sub = subdivide_uniform(cube, scheme, 2);
        REQUIRE(!sub.split_corners.empty());
        const Mesh copied = to_mesh(sub);
        const Mesh moved = to_mesh(SubdividedMesh(sub));
        CHECK(moved.positions == copied.positions);
        CHECK(moved.triangles == copied.triangles);
        CHECK(moved.corner_uvs == copied.corner_uvs);
        CHECK(moved.corner_normals == copied.corner_normals);
        REQUIRE(moved.corner_normals.size() == 3 * sub.triangles.size());
        std::size_t wrong = 0;
        for (std::size_t t = 0; t < sub.triangles.size(); ++t)
            for (int c = 0; c < 3; ++c) wrong += moved.corner_normals[3 * t + c] != sub.corner_normal(t, c);
        CHECK(wrong == 0);
    }
}
