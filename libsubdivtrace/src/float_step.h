#pragma once
// One float step up or down, as std::nextafter(f, +/-infinity) but inline:
// the shells round every coordinate outward this way, and libm's call was
// 1.6% of a tile build's instructions.

#include <cstdint>
#include <cstring>
#include <limits>

namespace subdivtrace::detail {

/// The next float above f; +infinity and NaN stay, either zero gives the
/// smallest denormal.
inline float next_float_up(float f) {
    if (!(f < std::numeric_limits<float>::infinity())) return f;
    if (f == 0.0f) return std::numeric_limits<float>::denorm_min();
    std::uint32_t bits;
    std::memcpy(&bits, &f, sizeof bits);
    // Floats of one sign are ordered as their bit patterns: a larger
    // magnitude above zero, a smaller one below.
    bits = f > 0.0f ? bits + 1u : bits - 1u;
    std::memcpy(&f, &bits, sizeof bits);
    return f;
}

/// The next float below f; -infinity and NaN stay.
inline float next_float_down(float f) { return -next_float_up(-f); }

/// The float nearest x that is not below x.
inline float round_up(double x) {
    float f = static_cast<float>(x);
    if (static_cast<double>(f) < x) f = next_float_up(f);
    return f;
}

/// The float nearest x that is not above x.
inline float round_down(double x) {
    float f = static_cast<float>(x);
    if (static_cast<double>(f) > x) f = next_float_down(f);
    return f;
}

/// A float one step below round_down(x): for an x that is itself a rounded
/// double (a coordinate minus an origin, say), the extra step covers that
/// rounding, so the float stays below the exact value (the compact and the
/// level shells store their lower bounds so).
inline float float_below_rounded(double x) { return next_float_down(round_down(x)); }

/// A float one step above round_up(x), as float_below_rounded.
inline float float_above_rounded(double x) { return next_float_up(round_up(x)); }

}  // namespace subdivtrace::detail
