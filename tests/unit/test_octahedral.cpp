// OctahedralNormal (the 6-byte normals a tile keeps for shading) against the
// vectors it stores: random directions over the sphere, the axes, the
// octahedron's folds and corners, and zero, which must stay zero.
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include <catch2/catch.hpp>
#include <glm/geometric.hpp>

#include "octahedral_normal.h"

using subdivtrace::Vec3;
using subdivtrace::detail::OctahedralNormal;

namespace {

double angle_between(const Vec3& a, const Vec3& b) {
    return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

}  // namespace

TEST_CASE("octahedral normals keep directions within 4e-7 radians", "[octahedral]") {
    std::mt19937_64 rng(20261203);
    std::normal_distribution<double> gauss;
    std::vector<Vec3> directions;
    for (int i = 0; i < 1000000; ++i) directions.push_back(Vec3(gauss(rng), gauss(rng), gauss(rng)));
    // The axes, the folds (z = 0, x = 0, y = 0) and the octahedron's corners.
    for (double x : {-1.0, 0.0, 1.0})
        for (double y : {-1.0, 0.0, 1.0})
            for (double z : {-1.0, -1e-300, 0.0, 1e-300, 1.0})
                if (x != 0.0 || y != 0.0 || z != 0.0) directions.push_back(Vec3(x, y, z));
    double worst_angle = 0.0, worst_length = 0.0;
    for (const Vec3& d : directions) {
        const Vec3 back = OctahedralNormal::from(d).vector();
        worst_angle = std::max(worst_angle, angle_between(back, d));
        worst_length = std::max(worst_length, std::abs(glm::length(back) - 1.0));
    }
    INFO("worst angle " << worst_angle << " rad, worst length error " << worst_length);
    CHECK(worst_angle <= 4e-7);  // a million random directions: 2.53e-7
    CHECK(worst_length <= 1e-15);
}

TEST_CASE("an octahedral normal of zero or NaN is zero, of any length its direction", "[octahedral]") {
    CHECK(OctahedralNormal::from(Vec3(0.0)).vector() == Vec3(0.0));
    CHECK(OctahedralNormal::from(Vec3(std::nan(""), 0.0, 1.0)).vector() == Vec3(0.0));
    // The lower pole, whose code would be zero's without its second name.
    CHECK(OctahedralNormal::from(Vec3(0.0, 0.0, -1.0)).vector() == Vec3(0.0, 0.0, -1.0));
    const Vec3 d = glm::normalize(Vec3(0.3, -0.4, 0.8));
    CHECK(OctahedralNormal::from(d * 1e-200) == OctahedralNormal::from(d));
    CHECK(OctahedralNormal::from(d * 1e200) == OctahedralNormal::from(d));
    // Stored again, the stored vector keeps its bits (a record passed on).
    const Vec3 once = OctahedralNormal::from(d).vector();
    CHECK(OctahedralNormal::from(once).vector() == once);
}
