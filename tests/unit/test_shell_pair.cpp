// The tracer tests a node's children's shells two at a time: each must get
// the verdict and entry distance ray_hits_shell gives it alone, bit for bit.
#include <catch2/catch.hpp>

#include <cstring>
#include <random>

#include "shell_pair.h"

using namespace subdivtrace;

namespace {

/// A random box with, three times in four, a slab along a random axis that
/// cuts into it (or lies flat on one of its faces).
Shell random_shell(std::mt19937& rng) {
    std::uniform_real_distribution<double> coordinate(-2.0, 2.0), size(0.0, 0.5), unit(-1.0, 1.0);
    const Vec3 c(coordinate(rng), coordinate(rng), coordinate(rng));
    const Vec3 e(size(rng), size(rng), size(rng));
    Shell s;
    s.lo = c - e;
    s.hi = c + e;
    switch (rng() % 4) {
    case 0: return s;  // a box alone
    case 1: s.axis = Vec3(0.0, 0.0, 1.0); break;
    default: s.axis = glm::normalize(Vec3(unit(rng), unit(rng), unit(rng))); break;
    }
    const double middle = glm::dot(s.axis, c);
    const double half = glm::length(e) * std::abs(unit(rng));
    s.slab_min = middle - half;
    s.slab_max = middle + half * std::abs(unit(rng));
    return s;
}

}  // namespace

TEST_CASE("Shell pairs: each shell gets ray_hits_shell's verdict and entry, bit for bit", "[shells]") {
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> coordinate(-3.0, 3.0);
    int hits = 0, misses = 0, slab_only_misses = 0;
    for (const ShellKind kind : {ShellKind::aabb_slab, ShellKind::aabb}) {
        for (int r = 0; r < 40000; ++r) {
            const Shell a = random_shell(rng), b = random_shell(rng);
            Vec3 origin(coordinate(rng), coordinate(rng), coordinate(rng));
            Vec3 dir(coordinate(rng), coordinate(rng), coordinate(rng));
            // Half of the rays aimed near a's centre, so both verdicts are common.
            if (r % 2 == 0) dir = 0.5 * (a.lo + a.hi) + 0.1 * dir - origin;
            // Rays parallel to an axis (infinite inverse directions) and to a's
            // slab (a zero denominator), now and then.
            if (r % 5 == 0) dir[r % 3] = 0.0;
            // And in the plane of one of a's faces (a NaN product there).
            if (r % 10 == 0) origin[r % 3] = r % 20 == 0 ? a.lo[r % 3] : a.hi[r % 3];
            if (r % 11 == 0 && a.axis != Vec3(0.0)) dir -= glm::dot(dir, a.axis) * a.axis;
            if (r % 13 == 0 && a.axis == Vec3(0.0, 0.0, 1.0)) dir.z = 0.0;
            const RayBoxQuery q = make_ray_box_query(origin, dir, 0.0, r % 7 == 0 ? 1.0 : 1e300);
            bool hit_a = false, hit_b = false;
            double t_a = -1.0, t_b = -1.0, want_t_a = -1.0, want_t_b = -1.0;
            detail::ray_hits_shell_pair(q, a, b, kind, hit_a, hit_b, t_a, t_b);
            const bool want_a = ray_hits_shell(q, a, kind, want_t_a);
            const bool want_b = ray_hits_shell(q, b, kind, want_t_b);
            REQUIRE(hit_a == want_a);
            REQUIRE(hit_b == want_b);
            if (want_a) REQUIRE(std::memcmp(&t_a, &want_t_a, sizeof t_a) == 0);
            if (want_b) REQUIRE(std::memcmp(&t_b, &want_t_b, sizeof t_b) == 0);
            (want_a ? hits : misses) += 1;
            double box_t = 0.0;
            if (!want_a && ray_hits_box(q, a.lo, a.hi, box_t)) ++slab_only_misses;
        }
    }
    // Every verdict was exercised: hits, misses, and misses the slab alone decides.
    CHECK(hits > 10000);
    CHECK(misses > 10000);
    CHECK(slab_only_misses > 1000);
}
