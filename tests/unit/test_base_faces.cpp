// What a caller needs to keep per-face data of its own beside the library
// (the POV-Ray adapter's texture indices, issue 16): which input face each
// kept triangle came from, and each hit's barycentric weights on its base
// triangle, checked against the geometry and the uvs they must reproduce.
#include <catch2/catch.hpp>

#include <random>

#include <glm/geometric.hpp>

#include "subdivtrace/mesh.h"
#include "subdivtrace/tracer.h"
#include "test_meshes.h"

using namespace subdivtrace;

TEST_CASE("kept_faces names the input face of every triangle built", "[mesh][weld]") {
    // Six faces: 1 repeats a vertex index, 3 collapses once vertices 4 and
    // 5 (the same position) are welded, 5 is a plain triangle after them.
    MeshArrays a;
    a.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1, 1, 0), Vec3(2, 2, 0),
                   Vec3(2, 2, 0), Vec3(3, 0, 0)};
    a.face_indices = {{0, 1, 2}, {1, 1, 3}, {1, 3, 2}, {4, 5, 6}, {3, 6, 4}, {1, 6, 3}};
    std::vector<std::string> warnings;
    WeldReport report;
    const Mesh m = mesh_from_arrays(a, "test", &warnings, WeldOptions{}, &report);
    REQUIRE(m.triangles.size() == 4);
    CHECK(report.kept_faces == std::vector<std::uint32_t>{0, 2, 4, 5});
    // Each kept triangle is its input face, welded (4 and 5 become one vertex).
    for (std::size_t t = 0; t < m.triangles.size(); ++t)
        for (int c = 0; c < 3; ++c)
            CHECK(m.positions[m.triangles[t][c]] ==
                  a.positions[static_cast<std::size_t>(a.face_indices[report.kept_faces[t]][c])]);
    CHECK(warnings.size() == 2);

    // Without welding only the repeated index goes; a second call starts afresh.
    WeldOptions off;
    off.enabled = false;
    mesh_from_arrays(a, "test", nullptr, off, &report);
    CHECK(report.kept_faces == std::vector<std::uint32_t>{0, 2, 3, 4, 5});
}

TEST_CASE("a hit's base barycentric weights locate it on its base triangle", "[tracer]") {
    // Base corner uvs (0,0), (1,0), (0,1) on every triangle make the library's
    // uv the barycentric pair itself: base_barycentric must equal it, at
    // every level. At max_level 0 the drawn triangle is the base one, so the
    // weights must also rebuild the hit point from the base corners.
    Mesh mesh = testmesh::icosphere(1);
    mesh.corner_uvs.clear();
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        mesh.corner_uvs.push_back(Vec2(0, 0));
        mesh.corner_uvs.push_back(Vec2(1, 0));
        mesh.corner_uvs.push_back(Vec2(0, 1));
    }
    for (const int max_level : {0, 5}) {
        INFO("max_level " << max_level);
        SurfaceOptions o;
        o.max_level = max_level;
        o.view.camera = Vec3(0.2, 0.3, 3.0);
        o.view.pixel_angle = 1e-3;
        const AdaptiveSurface surface(mesh, o);
        std::mt19937 rng(7);
        std::uniform_real_distribution<double> u(-0.7, 0.7);
        int hits = 0, refined = 0;
        for (int k = 0; k < 300; ++k) {
            Ray ray;
            ray.origin = o.view.camera;
            ray.direction = Vec3(u(rng), u(rng), 0.0) - ray.origin;
            Hit hit;
            if (!surface.intersect(ray, hit)) continue;
            ++hits;
            refined += hit.level > 0;
            const Vec2 b = hit.base_barycentric;
            CHECK(b.x >= -1e-12);
            CHECK(b.y >= -1e-12);
            CHECK(b.x + b.y <= 1.0 + 1e-12);
            CHECK(glm::length(b - hit.uv) < 1e-12);
            if (max_level == 0) {
                const Triangle& t = mesh.triangles[hit.base_face];
                const Vec3 p = (1.0 - b.x - b.y) * mesh.positions[t[0]] + b.x * mesh.positions[t[1]] +
                               b.y * mesh.positions[t[2]];
                CHECK(glm::length(p - hit.point) < 1e-9);
            }
        }
        CHECK(hits > 100);
        if (max_level > 0) CHECK(refined > 0);
    }
}
