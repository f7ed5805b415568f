// merge_crossings (crossings.h): all hits come out one per crossing, sorted
// by t, even where the parts of one feature (a corner or edge several drawn
// triangles share) report t values a rounding apart.
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "crossings.h"

using namespace subdivtrace;
using namespace subdivtrace::detail;

namespace {

Hit hit_at(double t) {
    Hit h;
    h.t = t;
    return h;
}

CrossingPart part(const Vec3& at, int corners, double turns, std::size_t hit) {
    CrossingPart p{{at, Vec3(0.0), Vec3(0.0)}, corners, turns, hit};
    if (corners >= 2) p.feature[1] = at + Vec3(1.0, 0.0, 0.0);
    if (corners == 3) p.feature[2] = at + Vec3(0.0, 1.0, 0.0);
    return p;
}

}  // namespace

TEST_CASE("merge_crossings reports hits sorted by t when a feature's parts disagree by a rounding",
          "[crossings]") {
    // A corner two triangles share (turns -0.2 and +0.9: one crossing, reported
    // by the triangle facing its way, the later of the two t values), and a
    // triangle's inside met between those two t values: the tracer's fuzz
    // harness found such a ray (tests/fuzz/regressions/trace/loop_corner_order),
    // whose all-hits list came out 1 ulp out of order.
    const double ta = 69.857406693608866;
    const double tb = std::nextafter(ta, 100.0), tc = std::nextafter(tb, 100.0);
    std::vector<Hit> hits = {hit_at(ta), hit_at(tc), hit_at(tb)};
    std::vector<CrossingPart> parts = {part(Vec3(0.0), 1, -0.2, 0), part(Vec3(0.0), 1, 0.9, 1),
                                       part(Vec3(5.0, 0.0, 0.0), 3, 1.0, 2)};
    merge_crossings(parts, hits);
    // Truth: the winding number goes 0 -> 1.7, two crossings in all.
    REQUIRE(hits.size() == 2);
    CHECK(hits[0].t <= hits[1].t);
}

TEST_CASE("merge_crossings: an edge two triangles share is one crossing, a touched corner none",
          "[crossings]") {
    // Along the ray: an edge both its triangles cross the same way (+1/2 each,
    // one crossing), then a corner the ray only touches (+1/4 and -1/4, none),
    // then a triangle's inside (one crossing).
    std::vector<Hit> hits = {hit_at(1.0), hit_at(1.0), hit_at(2.0), hit_at(2.0), hit_at(3.0)};
    std::vector<CrossingPart> parts = {part(Vec3(0.0), 2, 0.5, 0), part(Vec3(0.0), 2, 0.5, 1),
                                       part(Vec3(2.0), 1, 0.25, 2), part(Vec3(2.0), 1, -0.25, 3),
                                       part(Vec3(3.0), 3, 1.0, 4)};
    merge_crossings(parts, hits);
    REQUIRE(hits.size() == 2);
    CHECK(hits[0].t == 1.0);
    CHECK(hits[1].t == 3.0);
}
