// The certified bound each hit carries (Hit::surface_error) against brute
// force: the distance from the hit point to the surface of uniform subdivision
// at max_level, found by checking every one of its triangles.
#include <catch2/catch.hpp>

#include <algorithm>
#include <random>

#include <glm/geometric.hpp>

#include "subdivtrace/tracer.h"
#include "subdivtrace/uniform.h"
#include "test_meshes.h"

using namespace subdivtrace;

namespace {

/// Closest point of triangle (a, b, c) to p (Ericson, Real-Time Collision
/// Detection, 5.1.5), by Voronoi regions: no division by a zero area.
Vec3 closest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
    if (d1 <= 0.0 && d2 <= 0.0) return a;
    const Vec3 bp = p - b;
    const double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
    if (d3 >= 0.0 && d4 <= d3) return b;
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return a + ab * (d1 / (d1 - d3));
    const Vec3 cp = p - c;
    const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
    if (d6 >= 0.0 && d5 <= d6) return c;
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return a + ac * (d2 / (d2 - d6));
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0)
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    const double denom = 1.0 / (va + vb + vc);
    return a + ab * (vb * denom) + ac * (vc * denom);
}

double distance_to_mesh(const Vec3& p, const SubdividedMesh& m) {
    double best = 1e300;
    for (const Triangle& t : m.triangles) {
        const Vec3 q = closest_on_triangle(p, m.positions[t[0]], m.positions[t[1]], m.positions[t[2]]);
        best = std::min(best, glm::length(p - q));
    }
    return best;
}

}  // namespace

TEST_CASE("every hit's certified bound holds against brute force at max_level", "[error-bound]") {
    struct Case {
        const char* name;
        Mesh mesh;
    };
    const std::vector<Case> corpus = {
        {"icosahedron", testmesh::icosahedron()},
        {"torus", testmesh::torus(8, 6, 1.0, 0.35)},
        {"irregular 3..12", testmesh::irregular_closed(7)},
        {"open grid (boundary)", testmesh::open_grid(4)},
        {"faceted cube (creases)", testmesh::faceted_cube()},
        {"cylinder, split rim normals (creases)", testmesh::split_normal_cylinder(9, 1.0, 0.5)},
    };
    const int max_level = 3;
    std::size_t checked = 0;
    for (const Case& c : corpus) {
        for (SchemeKind scheme : {SchemeKind::normal, SchemeKind::loop, SchemeKind::butterfly}) {
            SubdividedMesh uniform = subdivide_uniform(c.mesh, scheme, max_level);
            // Loop's leaves draw every vertex at its limit point.
            if (scheme == SchemeKind::loop) push_to_limit(uniform, scheme);
            const double d = testmesh::bbox_diagonal(c.mesh.positions);
            for (RefineRule rule : {RefineRule::error, RefineRule::size}) {
                for (double pixel_angle : {0.002, 0.02, 0.1}) {
                    SurfaceOptions o;
                    o.scheme = scheme;
                    o.refine = rule;
                    o.max_level = max_level;
                    o.view.pixel_angle = pixel_angle;
                    o.view.camera = Vec3(0.3, 0.5, 2.0) * d;
                    const AdaptiveSurface surface(c.mesh, o);
                    std::mt19937 rng(7);
                    std::uniform_real_distribution<double> u(0.0, 1.0);
                    double worst_ratio = 0.0;
                    std::size_t hits = 0;
                    for (int k = 0; k < 60; ++k) {
                        // Aim at a random point of a random base triangle, from
                        // the camera or from a point beside the mesh.
                        const Triangle& t = c.mesh.triangles[rng() % c.mesh.triangles.size()];
                        double w1 = u(rng), w2 = u(rng);
                        if (w1 + w2 > 1.0) w1 = 1.0 - w1, w2 = 1.0 - w2;
                        const Vec3 target = (1.0 - w1 - w2) * c.mesh.positions[t[0]] +
                                            w1 * c.mesh.positions[t[1]] + w2 * c.mesh.positions[t[2]];
                        Ray ray;
                        ray.origin = k % 2 ? o.view.camera : Vec3(-1.5, 0.7, -0.9) * d;
                        ray.direction = target - ray.origin;
                        Hit hit;
                        if (!surface.intersect(ray, hit)) continue;
                        ++hits;
                        const double distance = distance_to_mesh(hit.point, uniform);
                        INFO(c.name << " " << scheme_name(scheme) << " " << refine_rule_name(rule)
                                    << " pixel angle " << pixel_angle << ": level " << hit.level
                                    << ", distance " << distance << ", bound " << hit.surface_error);
                        CHECK(distance <= hit.surface_error);
                        CHECK(std::isfinite(hit.surface_error_px));
                        CHECK(hit.surface_error_px >= 0.0);
                        if (hit.surface_error > 0.0)
                            worst_ratio = std::max(worst_ratio, distance / hit.surface_error);
                    }
                    CHECK(hits >= 15);  // of 60: a few miss the open grid
                    checked += hits;
                }
            }
        }
    }
    CHECK(checked > 2000);
}

TEST_CASE("the bound in pixels is the bound over the ray's footprint at the hit", "[error-bound]") {
    const Mesh mesh = testmesh::torus(8, 6, 1.0, 0.35);
    SurfaceOptions o;
    o.max_level = 6;
    o.view.pixel_angle = 0.004;
    o.view.camera = Vec3(0.2, 0.4, 3.0);
    const AdaptiveSurface surface(mesh, o);
    Ray ray;
    ray.origin = o.view.camera;
    ray.direction = Vec3(1.0, 0.0, 0.0) - ray.origin;  // on the tube, half a unit long
    Hit hit;
    REQUIRE(surface.intersect(ray, hit));
    const double distance = hit.t * glm::length(ray.direction);
    CHECK(hit.surface_error_px == Approx(hit.surface_error / (o.view.pixel_angle * distance)));
    // The error rule stopped it where its bound is within the tolerance (1 px).
    CHECK(hit.surface_error_px > 0.0);
    CHECK(hit.surface_error_px <= 1.0);
    CHECK_FALSE(hit.capped_by_max_level);
    // At max_level 1 the rule wants more than it may have: the hit says so.
    o.max_level = 1;
    const AdaptiveSurface capped(mesh, o);
    REQUIRE(capped.intersect(ray, hit));
    CHECK(hit.capped_by_max_level);
    CHECK(capped.stats().trace.hits_at_max_level == 1);
}
