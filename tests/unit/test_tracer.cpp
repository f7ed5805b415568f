// The tracer's contracts (DESIGN.md sections 5 and 6): each ray's surface is
// closed, no ray slips through a closed mesh, shadow rays see no acne, and
// pixels do not depend on the cache budget or the thread count.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <map>
#include <random>

#include <glm/geometric.hpp>

#include "render/render_loop.h"
#include "subdivtrace/spawn.h"
#include "subdivtrace/tracer.h"
#include "test_meshes.h"

using namespace subdivtrace;
using namespace subdivtrace::tools;  // the standalone renderer (Camera, render)

namespace {

struct NamedMesh {
    const char* name;
    Mesh mesh;
    Vec3 inside;  ///< a point inside (for closed meshes)
};

std::vector<NamedMesh> closed_corpus() {
    return {
        {"icosahedron", testmesh::icosahedron(), Vec3(0.0)},
        {"icosphere", testmesh::icosphere(1), Vec3(0.01, -0.02, 0.03)},
        {"torus", testmesh::torus(8, 6, 1.0, 0.35), Vec3(1.0, 0.0, 0.0)},
        {"irregular 3..12", testmesh::irregular_closed(7), Vec3(0.0)},
        {"high valence 100", testmesh::high_valence_fan(100), Vec3(0.0)},
        {"sliver 1e6", testmesh::sliver_mesh(), Vec3(0.0)},
        {"faceted cube (creases)", testmesh::faceted_cube(), Vec3(0.1, 0.2, -0.3)},
        {"cylinder, split rim normals", testmesh::split_normal_cylinder(9, 1.0, 0.5), Vec3(0.0, 0.1, 0.2)},
        // Written like the Utah teapot (seam vertices once per patch), welded on load.
        {"patch-split sphere, welded",
         mesh_from_arrays(testmesh::patch_split_sphere(3, false), "patch-split sphere"),
         Vec3(0.01, 0.02, -0.03)},
    };
}

SurfaceOptions options_for(const Mesh& mesh, SchemeKind scheme, double pixel_angle,
                           int max_level, RefineRule refine = RefineRule::error) {
    SurfaceOptions o;
    o.scheme = scheme;
    o.refine = refine;
    o.max_level = max_level;
    o.view.pixel_angle = pixel_angle;
    o.view.camera = Vec3(0.0, 0.0, 6.0) * testmesh::bbox_diagonal(mesh.positions);
    return o;
}

/// Number of edges that non-degenerate drawn triangles use an odd number of times.
std::size_t odd_edges(const std::vector<std::array<Vec3, 3>>& triangles) {
    auto bits = [](const Vec3& p) {
        std::array<std::uint64_t, 3> b;
        std::memcpy(b.data(), &p.x, 8);
        std::memcpy(b.data() + 1, &p.y, 8);
        std::memcpy(b.data() + 2, &p.z, 8);
        return b;
    };
    std::map<std::pair<std::array<std::uint64_t, 3>, std::array<std::uint64_t, 3>>, int> uses;
    for (const auto& t : triangles) {
        if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) continue;
        for (int e = 0; e < 3; ++e) {
            auto a = bits(t[e]), b = bits(t[(e + 1) % 3]);
            if (b < a) std::swap(a, b);
            ++uses[{a, b}];
        }
    }
    std::size_t odd = 0;
    for (const auto& u : uses) odd += u.second % 2;
    return odd;
}

/// Non-degenerate drawn triangles that repeat one already drawn (the same
/// three corners, bit for bit, in any order): the snapped rule's double layer
/// (DESIGN.md section 6).
std::size_t drawn_twice(const std::vector<std::array<Vec3, 3>>& triangles) {
    auto bits = [](const Vec3& p) {
        std::array<std::uint64_t, 3> b;
        std::memcpy(b.data(), &p.x, 24);
        return b;
    };
    std::map<std::array<std::array<std::uint64_t, 3>, 3>, int> seen;
    std::size_t repeats = 0;
    for (const auto& t : triangles) {
        if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) continue;
        std::array<std::array<std::uint64_t, 3>, 3> key = {bits(t[0]), bits(t[1]), bits(t[2])};
        std::sort(key.begin(), key.end());
        repeats += seen[key]++ > 0;
    }
    return repeats;
}

std::vector<Vec3> view_origins(const Mesh& mesh, int count, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    const double d = testmesh::bbox_diagonal(mesh.positions);
    std::vector<Vec3> out;
    while (static_cast<int>(out.size()) < count) {
        Vec3 dir(u(rng), u(rng), u(rng));
        if (glm::length(dir) < 0.1 || glm::length(dir) > 1.0) continue;
        // Distances from touching the mesh to far away, so edges freeze at many levels.
        const double r = d * (0.3 + 3.0 * std::abs(u(rng)));
        out.push_back(glm::normalize(dir) * r);
    }
    return out;
}

}  // namespace

TEST_CASE("each ray's surface is closed: no edge used an odd number of times", "[tracer]") {
    std::size_t all_leaves = 0, all_twice = 0;
    for (const NamedMesh& m : closed_corpus()) {
        for (SchemeKind scheme : {SchemeKind::normal, SchemeKind::loop, SchemeKind::butterfly})
        for (RefineRule rule : {RefineRule::error, RefineRule::size}) {
            const AdaptiveSurface surface(m.mesh, options_for(m.mesh, scheme, 0.02, 4, rule));
            std::size_t worst = 0;
            std::size_t leaves = 0;
            std::size_t twice = 0;
            std::vector<std::array<Vec3, 3>> drawn;
            for (const Vec3& origin : view_origins(m.mesh, 6, 11)) {
                surface.drawn_triangles(origin, 0.0, drawn);
                leaves += drawn.size();
                twice += drawn_twice(drawn);
                worst = std::max(worst, odd_edges(drawn));
            }
            INFO(m.name << " " << scheme_name(scheme) << " " << refine_rule_name(rule)
                        << ", leaves drawn " << leaves << ", drawn twice " << twice);
            CHECK(worst == 0);
            // It did refine (the error rule rightly leaves the cube's flat faces whole).
            if (rule == RefineRule::size || m.name != std::string("faceted cube (creases)"))
                CHECK(leaves > 6 * m.mesh.triangles.size());
            else
                CHECK(leaves == 6 * m.mesh.triangles.size());
            // The double layer is rare (the prototype: ~0.1% of leaves).
            CHECK(twice * 100 <= leaves);
            all_leaves += leaves;
            all_twice += twice;
        }
    }
    WARN("snapped rule's double layer: " << all_twice << " of " << all_leaves
                                         << " drawn triangles drawn twice");
}

TEST_CASE("the paper's per-triangle rule cracks where the snapped rule does not", "[tracer]") {
    const Mesh mesh = testmesh::icosahedron();
    SurfaceOptions o = options_for(mesh, SchemeKind::normal, 0.02, 5);
    o.crack_rule = CrackRule::per_triangle;
    const AdaptiveSurface naive(mesh, o);
    std::size_t odd = 0;
    std::vector<std::array<Vec3, 3>> drawn;
    for (const Vec3& origin : view_origins(mesh, 4, 5)) {
        naive.drawn_triangles(origin, 0.0, drawn);
        odd += odd_edges(drawn);
    }
    WARN("per-triangle rule: " << odd << " odd edges over 4 views");
    CHECK(odd > 0);
}

namespace {

/// Rays from inside a closed mesh: every one must hit. Directions are random,
/// and aimed exactly at the drawn vertices and edge midpoints of what this
/// origin sees, where a crack would be.
std::size_t leaks_from_inside(const AdaptiveSurface& surface, const Vec3& origin,
                              std::size_t random_rays, unsigned seed, std::size_t& shot) {
    std::size_t misses = 0;
    Hit hit;
    auto shoot = [&](const Vec3& dir) {
        if (!(glm::length(dir) > 0.0)) return;
        Ray ray;
        ray.origin = origin;
        ray.direction = dir;
        ray.origin_distance = 0.0;
        ++shot;
        if (!surface.intersect(ray, hit)) ++misses;
    };
    std::vector<std::array<Vec3, 3>> drawn;
    surface.drawn_triangles(origin, 0.0, drawn);
    const std::size_t stride = std::max<std::size_t>(1, drawn.size() / random_rays);
    for (std::size_t k = 0; k < drawn.size(); k += stride) {
        shoot(drawn[k][0] - origin);
        shoot((drawn[k][0] + drawn[k][1]) * 0.5 - origin);
    }
    std::mt19937 rng(seed);
    std::normal_distribution<double> g;
    for (std::size_t k = 0; k < random_rays; ++k) shoot(Vec3(g(rng), g(rng), g(rng)));
    return misses;
}

std::size_t leak_ray_budget() {
    // The full 10^6-ray run: SUBDIVTRACE_LEAK_RAYS=1000000 (see docs/testing.md).
    const char* env = std::getenv("SUBDIVTRACE_LEAK_RAYS");
    return env ? std::strtoull(env, nullptr, 10) : 120000;
}

}  // namespace

TEST_CASE("no ray slips through a closed mesh", "[tracer][leak]") {
    const std::size_t budget = leak_ray_budget();
    std::size_t shot = 0, misses = 0;
    const auto corpus = closed_corpus();
    const std::size_t per_case = budget / (corpus.size() * 3 * 2 * 2);
    for (const NamedMesh& m : corpus) {
        for (SchemeKind scheme : {SchemeKind::normal, SchemeKind::loop, SchemeKind::butterfly})
        for (RefineRule rule : {RefineRule::error, RefineRule::size}) {
            // The camera sits at the inside point, so rays refine around it.
            SurfaceOptions o = options_for(m.mesh, scheme, 0.02, 4, rule);
            o.view.camera = m.inside;
            const AdaptiveSurface surface(m.mesh, o);
            std::size_t case_misses = leaks_from_inside(surface, m.inside, per_case, 3, shot);
            // Rays from outside through the inside point must cross the surface.
            std::mt19937 rng(17);
            std::normal_distribution<double> g;
            const double d = testmesh::bbox_diagonal(m.mesh.positions);
            Hit hit;
            for (std::size_t k = 0; k < per_case; ++k) {
                const Vec3 from = m.inside + glm::normalize(Vec3(g(rng), g(rng), g(rng))) * (2.0 * d);
                Ray ray;
                ray.origin = from;
                ray.direction = m.inside - from;
                ++shot;
                if (!surface.intersect(ray, hit)) ++case_misses;
            }
            INFO(m.name << " " << scheme_name(scheme) << " " << refine_rule_name(rule));
            CHECK(case_misses == 0);
            misses += case_misses;
        }
    }
    WARN("leak test: " << shot << " rays, " << misses << " passed through");
    CHECK(shot >= budget / 2);
}

TEST_CASE("shadow rays from a lit smooth mesh see no acne", "[tracer]") {
    const Mesh mesh = testmesh::icosphere(1);
    for (RefineRule rule : {RefineRule::error, RefineRule::size})
    for (double tolerance : {0.25, 1.0, 4.0}) {
        Camera cam;
        cam.look_from = Vec3(0.3, 0.4, 3.2);
        cam.look_at = Vec3(0.0);
        cam.width = 96;
        cam.height = 72;
        SurfaceOptions o;
        o.refine = rule;
        o.tolerance = tolerance;
        o.max_level = 8;
        o.view.camera = cam.look_from;
        o.view.pixel_angle = cam.pixel_angle();
        const AdaptiveSurface surface(mesh, o);
        const Vec3 light(2.0, 3.0, 4.0);
        std::size_t lit = 0, acne = 0;
        for (int y = 0; y < cam.height; ++y) {
            for (int x = 0; x < cam.width; ++x) {
                const Ray ray = cam.ray(x, y);
                Hit hit;
                if (!surface.intersect(ray, hit)) continue;
                // The mesh is convex: a point facing the light cannot be shadowed.
                if (glm::dot(hit.geometric_normal, glm::normalize(light - hit.point)) < 0.2)
                    continue;
                ++lit;
                Hit blocker;
                if (surface.intersect(spawn_shadow_ray(ray, hit, light), blocker)) {
                    ++acne;
                    WARN("acne at " << x << "," << y << " level " << hit.level << " face "
                         << hit.base_face << " err " << hit.error_bound << " blocker t "
                         << blocker.t << " level " << blocker.level << " face " << blocker.base_face
                         << " cos " << glm::dot(hit.geometric_normal, glm::normalize(light - hit.point))
                         << " blocker cos " << glm::dot(blocker.geometric_normal, glm::normalize(light - hit.point)));
                }
            }
        }
        INFO(refine_rule_name(rule) << " rule, tolerance " << tolerance << ": " << lit << " lit pixels");
        CHECK(lit > 500);
        CHECK(acne == 0);
    }
}

TEST_CASE("pixels do not depend on cache budget or thread count", "[tracer][threads]") {
    const Mesh mesh = testmesh::torus(8, 6, 1.0, 0.35);
    Camera cam;
    cam.look_from = Vec3(0.5, 1.5, 2.2);
    cam.look_at = Vec3(0.6, 0.0, 0.0);
    cam.width = 64;
    cam.height = 48;
    auto render_with = [&](std::size_t cache_mb, int threads) {
        SurfaceOptions o;
        o.max_level = 7;
        o.cache_mb = cache_mb;
        o.view.camera = cam.look_from;
        o.view.pixel_angle = cam.pixel_angle();
        const AdaptiveSurface surface(mesh, o);
        RenderOptions ro;
        ro.threads = threads;
        RenderStats rs;
        return render([&](const Ray& r, Hit& h) { return surface.intersect(r, h); }, cam, ro,
                      surface.bounds(), rs)
            .rgb;
    };
    const std::vector<float> reference = render_with(512, 1);
    CHECK(render_with(1, 1) == reference);
    CHECK(render_with(512, 2) == reference);
    CHECK(render_with(1, 3) == reference);
}

TEST_CASE("all hits report each crossing once and inside() follows parity", "[tracer]") {
    const Mesh mesh = testmesh::torus(8, 6, 1.0, 0.35);
    SurfaceOptions o = options_for(mesh, SchemeKind::normal, 0.005, 6);
    const AdaptiveSurface surface(mesh, o);
    // A ray along the x axis crosses the tube twice on each side: 4 crossings.
    Ray ray;
    ray.origin = Vec3(-3.0, 0.0, 0.0);
    ray.direction = Vec3(1.0, 0.0, 0.0);
    std::vector<Hit> hits;
    surface.intersect_all(ray, hits);
    REQUIRE(hits.size() == 4);
    for (std::size_t k = 1; k < hits.size(); ++k) CHECK(hits[k].t > hits[k - 1].t);
    CHECK(surface.inside(Vec3(1.0, 0.0, 0.0)));
    CHECK(surface.inside(Vec3(-1.0, 0.01, 0.0)));
    CHECK_FALSE(surface.inside(Vec3(0.0, 0.0, 0.0)));   // the hole
    CHECK_FALSE(surface.inside(Vec3(0.0, 0.0, 2.0)));
    CHECK(surface.is_closed());
}

TEST_CASE("all hits tell crossings apart by structure, not by distance", "[tracer]") {
    // Two unit boxes stacked with a gap of 1e-12, far below the 1e-10 of the
    // scene size a distance tolerance used to merge; at max_level 0 the drawn
    // triangles are the base ones, so every crossing below is known exactly.
    const double gap = 1e-12;
    Mesh mesh;
    testmesh::add_box(mesh, Vec3(-1.0), Vec3(1.0));
    testmesh::add_box(mesh, Vec3(-1.0, -1.0, 1.0 + gap), Vec3(1.0, 1.0, 3.0 + gap));
    const AdaptiveSurface surface(mesh, options_for(mesh, SchemeKind::normal, 0.01, 0));
    std::vector<Hit> hits;
    Ray ray;
    ray.direction = Vec3(0.0, 0.0, 1.0);

    SECTION("two crossings 1e-12 apart are both reported") {
        ray.origin = Vec3(0.3, 0.2, -5.0);
        surface.intersect_all(ray, hits);
        REQUIRE(hits.size() == 4);
        CHECK(hits[0].t == 4.0);
        CHECK(hits[1].t == 6.0);
        CHECK(hits[2].t == 6.0 + gap);
        CHECK(hits[3].t == Approx(8.0 + gap));
        // Inside the lower box just under its top: the fixed ray of inside()
        // leaves it and enters the upper box ~1e-12 later, then leaves that.
        CHECK(surface.inside(Vec3(0.0, 0.0, 1.0 - 0.5 * gap)));
        CHECK_FALSE(surface.inside(Vec3(0.0, 0.0, 1.0 + 0.5 * gap)));
    }
    SECTION("a ray along shared edges meets two triangles on each, reports one crossing") {
        // (0.25, 0.25) lies on the diagonal edge of the bottom and top faces.
        ray.origin = Vec3(0.25, 0.25, -5.0);
        surface.intersect_all(ray, hits);
        REQUIRE(hits.size() == 4);
        CHECK(hits[0].t == 4.0);
        CHECK(hits[2].t == 6.0 + gap);
        TraceCounters counters;
        Hit nearest;
        REQUIRE(surface.intersect(ray, nearest, &counters));
        CHECK(nearest.t == 4.0);
    }
    SECTION("a ray through two corners of a box reports each corner once") {
        // Along the lower box's diagonal: in at (-1, -1, -1), out at (1, 1, 1),
        // passing the upper box's corner 1e-12 outside it.
        ray.origin = Vec3(-3.0);
        ray.direction = Vec3(1.0);
        surface.intersect_all(ray, hits);
        REQUIRE(hits.size() == 2);
        CHECK(hits[0].t == 2.0);
        CHECK(hits[1].t == 4.0);
        CHECK(glm::dot(hits[0].geometric_normal, ray.direction) < 0.0);
        CHECK(glm::dot(hits[1].geometric_normal, ray.direction) > 0.0);
    }
}

TEST_CASE("all hits: rays at drawn corners cross a closed mesh an even number of times, "
          "from inside an odd one", "[tracer]") {
    // Aimed at the corners the ray's own surface draws, where many leaves
    // meet: each crossing there must count once for parity to hold.
    std::size_t rays = 0, even_from_outside = 0, odd_from_inside = 0;
    for (const NamedMesh& m : closed_corpus()) {
        for (SchemeKind scheme : {SchemeKind::normal, SchemeKind::loop})
        for (RefineRule rule : {RefineRule::error, RefineRule::size}) {
            const SurfaceOptions o = options_for(m.mesh, scheme, 0.02, 4, rule);
            const AdaptiveSurface surface(m.mesh, o);
            const double d = testmesh::bbox_diagonal(m.mesh.positions);
            std::vector<std::array<Vec3, 3>> drawn;
            std::vector<Hit> hits;
            for (const Vec3& dir : view_origins(m.mesh, 3, 5)) {
                const Vec3 origin = glm::normalize(dir) * (3.0 * d);
                surface.drawn_triangles(origin, glm::length(origin - o.view.camera), drawn);
                const std::size_t step = std::max<std::size_t>(1, drawn.size() / 60);
                for (std::size_t k = 0; k < drawn.size(); k += step) {
                    for (const Vec3& corner : drawn[k]) {
                        Ray ray;
                        ray.origin = origin;
                        ray.direction = corner - origin;
                        surface.intersect_all(ray, hits);
                        ++rays;
                        even_from_outside += hits.size() % 2 == 0;
                        ray.origin = m.inside;
                        ray.direction = corner - m.inside;
                        surface.intersect_all(ray, hits);
                        odd_from_inside += hits.size() % 2 == 1;
                    }
                }
            }
            // The normal scheme keeps base vertices bit for bit and every leaf
            // around one draws it: an axis-aligned ray through one meets it
            // exactly (the shear leaves the other two coordinates as they are).
            if (scheme == SchemeKind::normal) {
                for (const Vec3& v : m.mesh.positions) {
                    for (int axis = 0; axis < 3; ++axis) {
                        for (double sign : {-1.0, 1.0}) {
                            Ray ray;
                            ray.direction = Vec3(0.0);
                            ray.direction[axis] = sign;
                            ray.origin = v - 3.0 * d * ray.direction;
                            surface.intersect_all(ray, hits);
                            ++rays;
                            ++odd_from_inside;  // no inside ray for these
                            even_from_outside += hits.size() % 2 == 0;
                        }
                    }
                }
            }
            INFO(m.name << " " << scheme_name(scheme) << " " << refine_rule_name(rule));
            CHECK(even_from_outside == rays);
            CHECK(odd_from_inside == rays);
        }
    }
    CHECK(rays > 5000);
}

TEST_CASE("all hits: a triangle drawn twice, once each way round, is no crossing", "[tracer]") {
    // The double layer in its plainest form: a square drawn both ways round,
    // below a closed box. It encloses nothing, so a ray through it does not
    // change sides; one hit for it (what merging by distance gave) would turn
    // every inside test through it around.
    Mesh mesh;
    testmesh::add_box(mesh, Vec3(-1.0), Vec3(1.0));
    const auto a = static_cast<std::uint32_t>(mesh.positions.size());
    for (const Vec2 c : {Vec2(-2.0, -2.0), Vec2(2.0, -2.0), Vec2(2.0, 2.0), Vec2(-2.0, 2.0)})
        mesh.positions.push_back({c.x, c.y, -3.0});
    mesh.triangles.push_back({a, a + 1, a + 2});
    mesh.triangles.push_back({a, a + 2, a + 3});
    mesh.triangles.push_back({a, a + 2, a + 1});
    mesh.triangles.push_back({a, a + 3, a + 2});
    const AdaptiveSurface surface(mesh, options_for(mesh, SchemeKind::normal, 0.01, 0));
    Ray ray;
    ray.origin = Vec3(0.3, 0.2, -5.0);
    ray.direction = Vec3(0.0, 0.0, 1.0);
    Hit nearest;
    REQUIRE(surface.intersect(ray, nearest));
    CHECK(nearest.t == 2.0);  // the nearest hit still sees the square
    std::vector<Hit> hits;
    surface.intersect_all(ray, hits);
    REQUIRE(hits.size() == 2);
    CHECK(hits[0].t == 4.0);
    CHECK(hits[1].t == 6.0);
    CHECK(surface.inside(Vec3(0.1, 0.1, 0.0)));
    CHECK_FALSE(surface.inside(Vec3(0.0, 0.0, -4.0)));
}

TEST_CASE("bad options and bad rays give clear errors, never NaN", "[tracer]") {
    const Mesh mesh = testmesh::icosahedron();
    SurfaceOptions o;
    o.tolerance = -1.0;
    CHECK_THROWS_WITH(AdaptiveSurface(mesh, o), Catch::Contains("tolerance"));
    o.tolerance = 1.0;
    o.max_level = k_max_level_cap + 1;
    CHECK_THROWS_WITH(AdaptiveSurface(mesh, o), Catch::Contains("max_level"));
    o.max_level = 4;
    const AdaptiveSurface surface(mesh, o);
    Hit hit;
    Ray nan_ray;
    nan_ray.origin = Vec3(std::nan(""), 0.0, 0.0);
    CHECK_FALSE(surface.intersect(nan_ray, hit));
    Ray zero;
    zero.direction = Vec3(0.0);
    CHECK_FALSE(surface.intersect(zero, hit));
    // A camera touching the surface forces max_level and stays finite.
    Ray touching;
    touching.origin = mesh.positions[0] * 1.0000001;
    touching.direction = -mesh.positions[0];
    touching.origin_distance = 0.0;
    REQUIRE(surface.intersect(touching, hit));
    CHECK(std::isfinite(hit.t));
    CHECK(std::isfinite(hit.normal.x));
}
