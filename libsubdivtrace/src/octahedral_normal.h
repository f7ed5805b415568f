#pragma once
// A unit normal in 6 bytes: its octahedral map (Meyer et al., "On Floating-
// Point Normal Vectors", 2010) with 24 bits per coordinate. A tile keeps four
// normals per grid point that only a ray's shading reads; as float vectors
// they were 48 of the point's 104 bytes, and 24 bits keep them about as
// close as float vectors did (within 4e-7 radians; float: 1e-7), which is
// far below what an 8-bit pixel shows (tests/unit/test_octahedral.cpp).

#include <cmath>
#include <cstdint>

#include "subdivtrace/mesh.h"

namespace subdivtrace::detail {

class OctahedralNormal {
public:
    /// Zero stays zero (an edge normal of a ring without area); any other
    /// vector is stored by its direction.
    static OctahedralNormal from(const Vec3& n) {
        OctahedralNormal o;
        const double l1 = std::fabs(n.x) + std::fabs(n.y) + std::fabs(n.z);
        if (!(l1 > 0.0)) return o;
        double u = n.x / l1, v = n.y / l1;
        if (n.z < 0.0) {
            // The lower half folds over the diagonals onto the square's corners.
            const double fu = (1.0 - std::fabs(v)) * sign(u), fv = (1.0 - std::fabs(u)) * sign(v);
            u = fu;
            v = fv;
        }
        std::uint32_t a = quantise(u), b = quantise(v);
        // (0, 0) names zero; its direction, the square's corner (-1, -1), is
        // the lower pole, as the corner (1, 1) is.
        if (a == 0 && b == 0) a = b = k_max;
        o.bits_[0] = static_cast<std::uint16_t>(a);
        o.bits_[1] = static_cast<std::uint16_t>((a >> 16) | (b << 8));
        o.bits_[2] = static_cast<std::uint16_t>(b >> 8);
        return o;
    }

    /// The unit normal it holds, or zero.
    Vec3 vector() const {
        const std::uint32_t a = bits_[0] | (std::uint32_t{bits_[1]} & 0xff) << 16;
        const std::uint32_t b = std::uint32_t{bits_[1]} >> 8 | std::uint32_t{bits_[2]} << 8;
        if (a == 0 && b == 0) return Vec3(0.0);
        double u = a * (2.0 / k_max) - 1.0, v = b * (2.0 / k_max) - 1.0;
        const double z = 1.0 - std::fabs(u) - std::fabs(v);
        if (z < 0.0) {
            const double fu = (1.0 - std::fabs(v)) * sign(u), fv = (1.0 - std::fabs(u)) * sign(v);
            u = fu;
            v = fv;
        }
        const double inv = 1.0 / std::sqrt(u * u + v * v + z * z);
        return Vec3(u * inv, v * inv, z * inv);
    }

    bool operator==(const OctahedralNormal& o) const {
        return bits_[0] == o.bits_[0] && bits_[1] == o.bits_[1] && bits_[2] == o.bits_[2];
    }

private:
    static constexpr std::uint32_t k_max = (1u << 24) - 1;
    static double sign(double x) { return x < 0.0 ? -1.0 : 1.0; }
    /// x in [-1, 1] to the nearest of 2^24 steps (a cast truncates the
    /// non-negative sum: no libm call).
    static std::uint32_t quantise(double x) {
        const double q = (x + 1.0) * (0.5 * k_max) + 0.5;
        return q <= 0.0 ? 0u : q >= k_max ? k_max : static_cast<std::uint32_t>(q);
    }

    std::uint16_t bits_[3] = {0, 0, 0};  ///< 24 bits of u, then 24 of v
};

}  // namespace subdivtrace::detail
