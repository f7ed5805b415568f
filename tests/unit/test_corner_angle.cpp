// corner_angle (the angle-weighted normals' atan2) against libm's atan2, the
// independent truth: random pairs over sixty binary orders of magnitude, the
// branch points of its range reduction, and the degenerate ends.
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include <catch2/catch.hpp>

#include "corner_angle.h"
#include "subdivtrace/scheme.h"

using subdivtrace::detail::corner_angle;

namespace {

double ulps_apart(double a, double b) {
    if (a == b) return 0.0;
    return std::abs(a - b) / (std::nextafter(b, INFINITY) - b);
}

}  // namespace

TEST_CASE("corner_angle is within 2 ulps of atan2 for every quadrant and scale", "[schemes][angle]") {
    std::mt19937_64 rng(20261203);
    std::uniform_real_distribution<double> unit(-1.0, 1.0), exponent(-30.0, 30.0);
    double worst = 0.0;
    for (int i = 0; i < 2000000; ++i) {
        const double y = std::abs(unit(rng)) * std::exp2(exponent(rng));
        double x = unit(rng) * std::exp2(exponent(rng));
        if (i % 3 == 0) x = y * unit(rng);                       // ratios near 1 and 0.66
        if (i % 5 == 0) x = -y * (1.0 + 1e-9 * unit(rng));       // near 3 pi / 4
        worst = std::max(worst, ulps_apart(corner_angle(y, x), std::atan2(y, x)));
    }
    CHECK(worst <= 2.0);
}

TEST_CASE("corner_angle at its reduction's seams and degenerate ends", "[schemes][angle]") {
    for (double t : {0.0, 1e-300, 1e-9, 0.5, 0.66, std::nextafter(0.66, 1.0), 0.999999, 1.0}) {
        for (double sign : {1.0, -1.0}) {
            CHECK(ulps_apart(corner_angle(t, sign), std::atan2(t, sign)) <= 2.0);
            if (t > 0.0) CHECK(ulps_apart(corner_angle(1.0, sign * t), std::atan2(1.0, sign * t)) <= 2.0);
        }
    }
    CHECK(corner_angle(0.0, 0.0) == 0.0);
    CHECK(corner_angle(0.0, 2.0) == 0.0);
    CHECK(corner_angle(0.0, -2.0) == std::atan2(0.0, -2.0));
    CHECK(corner_angle(3.0, 0.0) == std::atan2(3.0, 0.0));
    CHECK(corner_angle(1e300, 1e-300) == std::atan2(1e300, 1e-300));
}

TEST_CASE("angle_weighted_fan gives angle_weighted_normal's bits for every triangle of a fan",
          "[schemes][angle]") {
    using subdivtrace::Vec3;
    std::mt19937_64 rng(20261203);
    std::uniform_real_distribution<double> unit(-1.0, 1.0), exponent(-20.0, 20.0);
    const auto point = [&] {
        const double scale = std::exp2(exponent(rng));
        return Vec3(unit(rng), unit(rng), unit(rng)) * scale;
    };
    const double inf = std::numeric_limits<double>::infinity();
    std::size_t compared = 0, differing = 0;
    for (int fan = 0; fan < 20000; ++fan) {
        const std::size_t count = static_cast<std::size_t>(fan % 21);  // across the blocks of eight
        const Vec3 centre = point();
        std::vector<Vec3> from(count), to(count), out(count, Vec3(-7.0));
        for (std::size_t k = 0; k < count; ++k) {
            from[k] = point();
            to[k] = point();
            switch ((fan + k) % 13) {  // the degenerate corners
                case 0: to[k] = from[k]; break;
                case 1: from[k] = centre; break;
                case 2: to[k] = centre + (from[k] - centre) * 3.0; break;   // straight
                case 3: to[k] = centre - (from[k] - centre) * 0.5; break;   // straight, opposite
                case 4: from[k].x = inf; break;
                case 5: to[k].y = std::numeric_limits<double>::quiet_NaN(); break;
                default: break;
            }
        }
        subdivtrace::angle_weighted_fan(centre, from.data(), to.data(), count, out.data());
        for (std::size_t k = 0; k < count; ++k) {
            const Vec3 one = subdivtrace::angle_weighted_normal(centre, from[k], to[k]);
            ++compared;
            if (std::memcmp(&one, &out[k], sizeof one) != 0) ++differing;
        }
    }
    CHECK(compared > 100000);
    CHECK(differing == 0);
}
