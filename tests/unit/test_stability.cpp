// The stability table's cases and measurements (libsubdivtrace/tools/stability,
// `subdivtrace stability`): the reference intersection and the rounding bound
// against known answers, then the stiff cases traced small, holding the
// table's invariants (0 non-finite hits, 0 leaks, every hit's distance within
// the double-precision rounding bound of an exact intersection).
#include <catch2/catch.hpp>

#include <cmath>
#include <stdexcept>

#include "stability/stability.h"

using namespace subdivtrace;
using namespace subdivtrace::tools;

namespace {

Hit hit_on(const std::array<Vec3, 3>& triangle, double t) {
    Hit h;
    h.triangle = triangle;
    h.t = t;
    return h;
}

}  // namespace

TEST_CASE("stability: the reference intersection and the rounding bound", "[stability]") {
    // A plane z = 0 at distance 5 along a unit ray, and a tilted plane
    // z = x at distance 4 along a ray of length 2: known exactly.
    Ray ray;
    ray.origin = Vec3(0.25, 0.5, -5.0);
    ray.direction = Vec3(0.0, 0.0, 1.0);
    const std::array<Vec3, 3> flat = {Vec3(-1.0, -1.0, 0.0), Vec3(1.0, -1.0, 0.0),
                                      Vec3(0.0, 1.0, 0.0)};
    CHECK(reference_t(ray, hit_on(flat, 5.0)) == 5.0L);
    ray.origin = Vec3(0.5, 0.0, -7.5);
    ray.direction = Vec3(0.0, 0.0, 2.0);
    const std::array<Vec3, 3> tilted = {Vec3(-1.0, -1.0, -1.0), Vec3(1.0, -1.0, 1.0),
                                        Vec3(0.0, 1.0, 0.0)};
    CHECK(reference_t(ray, hit_on(tilted, 4.0)) == 4.0L);

    // The bound is a few ulps of the distances involved: a t off by one ulp
    // of 4 passes, one off by 1e-12 does not.
    const double bound = t_rounding_bound(ray, hit_on(tilted, 4.0));
    CHECK(bound > 0.0);
    CHECK(bound < 1e-13);
    CHECK(bound >= std::nextafter(4.0, 5.0) - 4.0);
}

TEST_CASE("stability: every stiff case builds, unknown names are refused", "[stability]") {
    const std::vector<std::string> names = stiff_case_names();
    CHECK(names.size() == 15);
    for (const std::string& n : names) {
        const StiffCase c = make_stiff_case(n, 8, 6);
        INFO(n);
        CHECK(c.name == n);
        CHECK_NOTHROW(AdaptiveSurface(c.mesh, c.options));
    }
    CHECK_THROWS_AS(make_stiff_case("no such case", 8, 6), std::invalid_argument);
}

TEST_CASE("stability: stiff cases give finite hits, no leaks, distances within rounding",
          "[stability]") {
    // The two slow ones (valence 200, the 1e6 offset) run in the CLI's quick
    // table (ctest stability_table).
    for (const char* name : {"sliver 1e6", "zero-area", "duplicate triangles", "valence 100",
                             "folds", "crease (cube)", "boundary (open)", "non-manifold edge",
                             "scale 1e-6", "scale 1e6", "grazing rays", "camera on surface",
                             "max_level forced"}) {
        const StiffCase c = make_stiff_case(name, 24, 18);
        const StabilityRow r = run_stiff_case(c, 100);
        INFO(name << ": " << r.hits << " hits of " << r.rays << " rays, deepest level "
                  << r.max_level << ", deviation " << r.max_deviation << " = "
                  << r.max_deviation_ratio << " of the rounding bound");
        CHECK(r.rays == 24 * 18 + (c.has_inside ? 100 : 0));
        CHECK(r.hits > 0);
        CHECK(r.max_level > 0);
        CHECK(r.non_finite == 0);
        if (c.has_inside || c.camera_rays_must_hit) CHECK(r.leaks == 0);
        else CHECK(r.leaks == -1);
        CHECK(r.max_deviation_ratio <= 1.0);
    }
    // Forced to the cap, the rays reach it.
    CHECK(run_stiff_case(make_stiff_case("max_level forced", 8, 6), 0).max_level ==
          k_max_level_cap);
}
