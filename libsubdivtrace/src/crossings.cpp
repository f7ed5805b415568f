#include "crossings.h"

#include <algorithm>
#include <cmath>

namespace subdivtrace::detail {

namespace {

bool position_less(const Vec3& a, const Vec3& b) {
    return a.x != b.x ? a.x < b.x : a.y != b.y ? a.y < b.y : a.z < b.z;
}

bool feature_less(const CrossingPart& a, const CrossingPart& b) {
    if (a.corners != b.corners) return a.corners < b.corners;
    for (int c = 0; c < a.corners; ++c) {
        if (position_less(a.feature[c], b.feature[c])) return true;
        if (position_less(b.feature[c], a.feature[c])) return false;
    }
    return false;
}

}  // namespace

CrossingPart crossing_part(const WatertightRay& ray, const std::array<Vec3, 3>& t,
                           const TriangleHit& th, std::size_t hit) {
    constexpr double k_two_pi = 6.283185307179586476925;
    const double b[3] = {th.b0, th.b1, th.b2};
    const double sign = th.det > 0.0 ? 1.0 : -1.0;
    CrossingPart part{{Vec3(0.0), Vec3(0.0), Vec3(0.0)}, 0, 0.0, hit};
    for (int c = 0; c < 3; ++c)
        if (b[c] != 0.0) part.feature[part.corners++] = t[c];
    // At most three: sorted by hand (std::sort here trips GCC 12's -Warray-bounds).
    auto order = [&](int x, int y) {
        if (position_less(part.feature[y], part.feature[x])) std::swap(part.feature[x], part.feature[y]);
    };
    if (part.corners >= 2) order(0, 1);
    if (part.corners == 3) {
        order(1, 2);
        order(0, 1);
    }
    if (part.corners == 3) {
        part.turns = sign;
    } else if (part.corners == 2) {
        part.turns = 0.5 * sign;
    } else {
        // The corner's angle in the plane across the ray (the test's shear).
        const int i = b[0] != 0.0 ? 0 : b[1] != 0.0 ? 1 : 2;
        auto project = [&](const Vec3& p) {
            const Vec3 q = p - ray.origin;
            return Vec2(q[ray.kx] - ray.sx * q[ray.kz], q[ray.ky] - ray.sy * q[ray.kz]);
        };
        const Vec2 o = project(t[i]);
        const Vec2 u = project(t[(i + 1) % 3]) - o, v = project(t[(i + 2) % 3]) - o;
        const double angle = std::atan2(std::abs(u.x * v.y - u.y * v.x), u.x * v.x + u.y * v.y);
        part.turns = sign * angle / k_two_pi;
    }
    return part;
}

// The surface's winding number around the ray changes only where the ray
// meets it; a crossing is a step of that number, rounded. Per feature, the
// triangles there add their turns: a shared edge or corner the ray passes
// through winds once (one crossing); a triangle the snapped rule draws twice,
// once each way round (the double layer), and a silhouette edge or corner the
// ray only touches wind zero times (none). A feature the ray meets edge-on
// (a ray along a drawn edge, or in the plane of a face, enters at a corner and
// leaves at an edge) winds a part of a turn only, so the features are walked
// in order along the ray and each reports how far the *running* winding
// number, rounded, moved there: the steps add up to the total winding, so the
// parity of the crossings is right whatever each part rounds to (rounding each
// feature alone counted 0.4999 + 0.5 as one crossing).
void merge_crossings(std::vector<CrossingPart>& parts, std::vector<Hit>& hits) {
    std::sort(parts.begin(), parts.end(), feature_less);
    struct Feature {
        double t;
        double turns;
        std::size_t pick;  ///< the hit reported for its crossings
    };
    std::vector<Feature> features;
    for (std::size_t first = 0; first < parts.size();) {
        std::size_t end = first + 1;
        while (end < parts.size() && !feature_less(parts[first], parts[end])) ++end;
        double turns = 0.0;
        for (std::size_t k = first; k < end; ++k) turns += parts[k].turns;
        // Report the hit of a triangle facing the way the crossing goes, and
        // place the feature along the ray at that hit's t: its parts meet one
        // point, but their t values differ by roundings, and ordering by
        // another part's t let a neighbour's hit fall between (the list came
        // out of order by an ulp; found by the tracer's fuzz harness).
        std::size_t pick = first;
        for (std::size_t k = first; k < end; ++k)
            if ((parts[k].turns > 0.0) == (turns > 0.0)) {
                pick = k;
                break;
            }
        features.push_back({hits[parts[pick].hit].t, turns, parts[pick].hit});
        first = end;
    }
    std::stable_sort(features.begin(), features.end(),
                     [](const Feature& a, const Feature& b) { return a.t < b.t; });
    std::vector<Hit> out;
    out.reserve(hits.size());
    double winding = 0.0;
    long rounded = 0;
    for (const Feature& f : features) {
        winding += f.turns;
        const long now = std::lround(winding);
        for (long c = std::labs(now - rounded); c > 0; --c) out.push_back(hits[f.pick]);
        rounded = now;
    }
    hits.swap(out);
}

}  // namespace subdivtrace::detail
