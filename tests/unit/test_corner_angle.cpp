// corner_angle (the angle-weighted normals' atan2) against libm's atan2, the
// independent truth: random pairs over sixty binary orders of magnitude, the
// branch points of its range reduction, and the degenerate ends.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include <catch2/catch.hpp>
#include <glm/geometric.hpp>

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

TEST_CASE("angle_weighted_corners: each triangle's bits as alone, and libm's angles at each corner",
          "[schemes][angle]") {
    using subdivtrace::Triangle;
    using subdivtrace::Vec3;
    std::mt19937_64 rng(20261204);
    std::uniform_real_distribution<double> unit(-1.0, 1.0), exponent(-20.0, 20.0);
    const double inf = std::numeric_limits<double>::infinity();
    const std::size_t count = 30011;  // not a multiple of the blocks
    std::vector<Vec3> positions;
    std::vector<Triangle> triangles;
    for (std::size_t t = 0; t < count; ++t) {
        const double scale = std::exp2(exponent(rng));
        Vec3 p[3];
        for (Vec3& q : p) q = Vec3(unit(rng), unit(rng), unit(rng)) * scale;
        switch (t % 11) {  // the degenerate triangles
            case 0: p[2] = p[1]; break;
            case 1: p[2] = p[0] + (p[1] - p[0]) * 3.0; break;  // straight
            case 2: p[1].z = inf; break;
            case 3: p[0].x = std::numeric_limits<double>::quiet_NaN(); break;
            default: break;
        }
        const auto first = static_cast<std::uint32_t>(positions.size());
        positions.insert(positions.end(), p, p + 3);
        triangles.push_back(Triangle{first, first + 1, first + 2});
    }
    std::vector<Vec3> out(3 * count, Vec3(-7.0));
    // From an offset, as callers pass a block of a larger array.
    subdivtrace::angle_weighted_corners(positions.data(), triangles.data() + 5, count - 5, out.data() + 15);

    std::size_t differing = 0, angle_checked = 0, angle_off = 0;
    for (std::size_t t = 5; t < count; ++t) {
        const Triangle& tri = triangles[t];
        const Vec3 &p0 = positions[tri[0]], &p1 = positions[tri[1]], &p2 = positions[tri[2]];
        // Alone: one cross product, two angles, the third from pi.
        const Vec3 n = glm::cross(p1 - p0, p2 - p0);
        const double len = glm::length(n);
        Vec3 expected[3] = {Vec3(0.0), Vec3(0.0), Vec3(0.0)};
        if (len > 0.0 && len <= std::numeric_limits<double>::max()) {
            const double a0 = corner_angle(len, glm::dot(p1 - p0, p2 - p0));
            const double a1 = corner_angle(len, glm::dot(p2 - p1, p0 - p1));
            const double a2 = std::max(0.0, 3.14159265358979323846 - a0 - a1);
            expected[0] = n / len * a0;
            expected[1] = n / len * a1;
            expected[2] = n / len * a2;
            // The independent truth: each corner's weight is libm's angle.
            if (t % 11 > 3) {
                const Vec3* p[3] = {&p0, &p1, &p2};
                for (int c = 0; c < 3; ++c) {
                    const Vec3 e1 = *p[(c + 1) % 3] - *p[c], e2 = *p[(c + 2) % 3] - *p[c];
                    const double truth = std::atan2(glm::length(glm::cross(e1, e2)), glm::dot(e1, e2));
                    ++angle_checked;
                    if (std::abs(glm::length(out[3 * t + c]) - truth) > 1e-12 * (1.0 + truth)) ++angle_off;
                }
            }
        }
        if (std::memcmp(expected, &out[3 * t], sizeof expected) != 0) ++differing;
    }
    for (std::size_t slot = 0; slot < 15; ++slot) CHECK(out[slot] == Vec3(-7.0));  // untouched
    CHECK(differing == 0);
    CHECK(angle_checked > 50000);
    CHECK(angle_off == 0);
}
