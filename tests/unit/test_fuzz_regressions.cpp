// Inputs the libFuzzer harnesses (tests/fuzz) found, pinned as plain tests so
// they are read without the fuzzer: the tracer harness's crashes, decoded into
// the mesh, options and ray they built. (The readers' inputs are files, read
// by the "[fuzz]" test in test_mesh_io.cpp.)
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "subdivtrace/mesh.h"
#include "subdivtrace/tracer.h"

using namespace subdivtrace;

TEST_CASE("fuzz regression: butterfly on five triangles over one non-manifold edge",
          "[fuzz][tracer]") {
    // tests/fuzz/regressions/trace/butterfly_nonmanifold_fan: intersect()
    // threw std::logic_error "subdivtrace tile: an edge point next to a corner
    // outside the patch's complete region" (the tracing path must never
    // throw): two of the five triangles are the same base triangle twice, and
    // a tile merged their face points. Fixed in patch.cpp (an edge inside a
    // base triangle belongs to that triangle alone).
    MeshArrays a;
    a.positions = {{4060.6980231178895, -10347.809884752507, 9119.986621959024},
                   {21050.576124940693, -3429.1967600287608, 5931.8030970320542},
                   {6611.6042525064713, -20660.143398567012, -1620.9059147124053},
                   {11950.261952028563, -18125.884679736868, 547.4418862542243}};
    a.face_indices = {{1, 0, 2}, {0, 1, 2}, {0, 1, 3}, {2, 0, 1}, {1, 0, 3}};
    const Mesh mesh = mesh_from_arrays(a, "fuzz");
    SurfaceOptions o;
    o.scheme = SchemeKind::butterfly;
    o.max_level = 4;
    o.tolerance = 4.2842462080649835;
    o.cache_mb = 4;
    o.view.pixel_angle = 0.017880425572252522;
    o.view.camera = Vec3(1277.5685992553426, 9772.5930052410822, -8401.7597661918044);
    const AdaptiveSurface surface(mesh, o);
    Ray ray;
    ray.origin = Vec3(24414.613421814065, -1971.5870005094603, 9969.2174446217141);
    ray.direction = Vec3(-0.45748196889175152, -0.58761313530981685, -0.66739871991957955);
    Hit hit;
    bool found = false;
    CHECK_NOTHROW(found = surface.intersect(ray, hit));
    if (found) CHECK(std::isfinite(hit.t));
}

TEST_CASE("fuzz regression: normal scheme on a double-sided triangle beside a third one",
          "[fuzz][tracer]") {
    // tests/fuzz/regressions/trace/normal_double_sided_fan: intersect() threw
    // std::logic_error "subdivtrace tile: a corner's normal or drawn position
    // outside the patch's complete region". Triangles 0 and 2 are one triangle
    // in both windings; edge 0-2 has three triangles. Fixed by the same change
    // in patch.cpp as the butterfly fan above (duplicate base triangles keep
    // their own face points).
    MeshArrays a;
    a.positions = {{4060.6980231178895, -10347.809884752507, 9119.986621959024},
                   {21050.576124940719, -8056.6438911706964, -2556.7432935068091},
                   {18866.325528527177, -22677.46761747263, 16647.767092577691},
                   {6405.6936793747518, -15316.241025654561, 2309.9734077007943}};
    a.face_indices = {{0, 2, 3}, {0, 1, 2}, {3, 2, 0}};
    const Mesh mesh = mesh_from_arrays(a, "fuzz");
    SurfaceOptions o;
    o.scheme = SchemeKind::normal;
    o.max_level = 2;
    o.tolerance = 0.7421355323251646;
    o.cache_mb = 4;
    o.view.pixel_angle = 0.011475934595159349;
    o.view.camera = Vec3(-12207.052146951102, -17880.855125459686, -7050.6603411360547);
    const AdaptiveSurface surface(mesh, o);
    auto ray_of = [](const Vec3& origin, const Vec3& direction) {
        Ray r;
        r.origin = origin;
        r.direction = direction;
        return r;
    };
    const Ray rays[2] = {
        ray_of(Vec3(22732.335006233807, -18577.397191284792, 6548.1328607293017),
               Vec3(0.21952969532525649, 0.69739210392065898, -0.68223966922154056)),
        ray_of(Vec3(24414.613421814065, -1971.585283092425, 17843.137254901962),
               Vec3(-0.80134188551690511, -0.46161795955451412, -0.38047344445169673))};
    // As the harness did: the nearest hit, then all hits, ray after ray.
    for (const Ray& ray : rays) {
        Hit hit;
        bool found = false;
        CHECK_NOTHROW(found = surface.intersect(ray, hit));
        if (found) CHECK(std::isfinite(hit.t));
        std::vector<Hit> all;
        CHECK_NOTHROW(surface.intersect_all(ray, all));
    }
}
