#pragma once
// The angle between two vectors from |a x b| and a . b, as atan2 gives it,
// without libm's atan2: angle-weighted normals take one per triangle corner,
// and libm's general atan2 (any quadrant, infinities, correct rounding
// paths) was 11% of a render of small objects. This is Cephes' rational
// approximation of atan on [-0.2, 0.66] (relative error about 1e-16), after
// reducing the ratio of the two arguments to [0, 1].

#include <cmath>

namespace subdivtrace::detail {

/// atan2(cross_length, dot) for cross_length >= 0 (finite): an angle in
/// [0, pi], within a few ulps of std::atan2's.
inline double corner_angle(double cross_length, double dot) {
    constexpr double pi = 3.14159265358979323846;
    // Bits of pi/2 and pi/4 that a double misses.
    constexpr double half_pi_lo = 6.123233995736765886130e-17;
    // Every operation below runs whatever the case, and the cases only
    // select among results: without branches or conditional arithmetic
    // (which the compiler may not execute speculatively), a loop of corner
    // angles vectorises (angle_weighted_fan).
    const double y = cross_length;
    const double x = std::fabs(dot);
    // A straight corner (y == 0) is 0 or pi, selected at the end.
    const bool straight = !(y > 0.0);
    // The angle of (x, y) in the first quadrant is atan(lo / hi), or pi/2
    // minus it when y > x; atan(t) = pi/4 + atan((t - 1) / (t + 1)) moves a
    // ratio t > 0.66 into (-0.21, 0]. One division either way.
    const bool steep = y > x;
    const double lo = steep ? x : y;
    const double hi = steep ? y : x;
    const bool shifted = lo > 0.66 * hi;
    const double difference = lo - hi, sum = lo + hi;
    // With y == 0 and x == 0 it divides 0 by 1, not by 0.
    const double r = (shifted ? difference : lo) / (shifted ? sum : straight ? 1.0 : hi);
    const double z = r * r;
    const double p = (((-8.750608600031904122785e-1 * z - 1.615753718733365076637e1) * z -
                       7.500855792314704667340e1) * z - 1.228866684490136173410e2) * z -
                     6.485021904942025371773e1;
    const double q = ((((z + 2.485846490142306297962e1) * z + 1.650270098316988542046e2) * z +
                       4.328810604912902668951e2) * z + 4.853903996359136964868e2) * z +
                     1.945506571482613964425e2;
    const double base = shifted ? pi / 4 : 0.0;
    const double base_lo = shifted ? 0.5 * half_pi_lo : 0.0;
    const double a = base + (r + (r * (z * p / q) + base_lo));
    const double from_y_axis = (pi / 2 - a) + half_pi_lo;
    const double first = steep ? from_y_axis : a;
    const double obtuse = (pi - first) + 2 * half_pi_lo;
    const double angle = dot < 0.0 ? obtuse : first;
    return straight ? (dot < 0.0 ? pi : 0.0) : angle;
}

}  // namespace subdivtrace::detail
