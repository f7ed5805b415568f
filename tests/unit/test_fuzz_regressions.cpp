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

namespace {

/// What the tracer harness built from one input, besides the mesh.
struct Decoded {
    SchemeKind scheme;
    int max_level;
    double tolerance;
    double pixel_angle;
    Vec3 camera;
};

Ray ray_of(const Vec3& origin, const Vec3& direction) {
    Ray r;
    r.origin = origin;
    r.direction = direction;
    return r;
}

/// As the harness did: build the surface, then the nearest hit and all hits,
/// ray after ray. None may throw; hits are finite.
void trace_decoded(const MeshArrays& arrays, const Decoded& d, const std::vector<Ray>& rays) {
    const Mesh mesh = mesh_from_arrays(arrays, "fuzz");
    SurfaceOptions o;
    o.scheme = d.scheme;
    o.max_level = d.max_level;
    o.tolerance = d.tolerance;
    o.cache_mb = 4;
    o.view.pixel_angle = d.pixel_angle;
    o.view.camera = d.camera;
    const AdaptiveSurface surface(mesh, o);
    for (const Ray& ray : rays) {
        Hit hit;
        bool found = false;
        CHECK_NOTHROW(found = surface.intersect(ray, hit));
        if (found) CHECK(std::isfinite(hit.t));
        std::vector<Hit> all;
        CHECK_NOTHROW(surface.intersect_all(ray, all));
    }
}

}  // namespace

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
    trace_decoded(a,
                  {SchemeKind::butterfly, 4, 4.2842462080649835, 0.017880425572252522,
                   Vec3(1277.5685992553426, 9772.5930052410822, -8401.7597661918044)},
                  {ray_of(Vec3(24414.613421814065, -1971.5870005094603, 9969.2174446217141),
                          Vec3(-0.45748196889175152, -0.58761313530981685,
                               -0.66739871991957955))});
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
    trace_decoded(
        a,
        {SchemeKind::normal, 2, 0.7421355323251646, 0.011475934595159349,
         Vec3(-12207.052146951102, -17880.855125459686, -7050.6603411360547)},
        {ray_of(Vec3(22732.335006233807, -18577.397191284792, 6548.1328607293017),
                Vec3(0.21952969532525649, 0.69739210392065898, -0.68223966922154056)),
         ray_of(Vec3(24414.613421814065, -1971.585283092425, 17843.137254901962),
                Vec3(-0.80134188551690511, -0.46161795955451412, -0.38047344445169673))});
}

TEST_CASE("fuzz regression: Loop on a double-sided triangle beside two others",
          "[fuzz][tracer]") {
    // tests/fuzz/regressions/trace/loop_double_sided_fan: intersect() threw
    // the same std::logic_error as above ("a corner's normal or drawn position
    // outside the patch's complete region"); triangles 2 and 3 are one triangle
    // in both windings. Fixed by the same change in patch.cpp.
    MeshArrays a;
    a.positions = {{-6.2087258137969794, 24.912770792531653, -0.038373841541474718},
                   {-10.944366619435057, 15.412590571489392, -1.1975385720672316},
                   {-11.22513689387292, 22.335770473566424, -5.3837247570565321},
                   {0.48084893561965991, 8.1765521652778066, -16.970719269658666}};
    a.face_indices = {{3, 2, 0}, {0, 2, 1}, {3, 0, 1}, {3, 1, 0}};
    trace_decoded(
        a,
        {SchemeKind::loop, 3, 1.4504364514811192, 0.0029504356461198941,
         Vec3(-21.162312965608336, -6.59623124917049, -1.5439981509338052)},
        {ray_of(Vec3(-5.2634985891792834, 21.972906991829149, -6.866453080578685),
                Vec3(0.96930659179274559, -0.020996977457300375, -0.24495684935267539))});
}
