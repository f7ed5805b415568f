// corner_angle (the angle-weighted normals' atan2) against libm's atan2, the
// independent truth: random pairs over sixty binary orders of magnitude, the
// branch points of its range reduction, and the degenerate ends.
#include <cmath>
#include <random>

#include <catch2/catch.hpp>

#include "corner_angle.h"

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
