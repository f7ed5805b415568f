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

}  // namespace subdivtrace::detail
