// next_float_up / next_float_down against libm's nextafter, the independent
// truth: every special value, and random bit patterns of every class.
#include <cmath>
#include <cstring>
#include <limits>
#include <random>

#include <catch2/catch.hpp>

#include "float_step.h"

using subdivtrace::detail::float_above_rounded;
using subdivtrace::detail::float_below_rounded;
using subdivtrace::detail::next_float_down;
using subdivtrace::detail::next_float_up;

namespace {

constexpr float k_inf = std::numeric_limits<float>::infinity();

/// Same bits, or both NaN.
bool same(float a, float b) {
    if (std::isnan(a) || std::isnan(b)) return std::isnan(a) && std::isnan(b);
    std::uint32_t x, y;
    std::memcpy(&x, &a, sizeof x);
    std::memcpy(&y, &b, sizeof y);
    return x == y;
}

}  // namespace

TEST_CASE("float steps equal nextafter at special values", "[shells][float]") {
    const float lowest = std::numeric_limits<float>::lowest(), highest = std::numeric_limits<float>::max();
    const float tiny = std::numeric_limits<float>::denorm_min(), normal = std::numeric_limits<float>::min();
    for (float f : {0.0f, -0.0f, tiny, -tiny, normal, -normal, 1.0f, -1.0f, highest, lowest, k_inf, -k_inf,
                    std::numeric_limits<float>::quiet_NaN()}) {
        INFO("f = " << f);
        CHECK(same(next_float_up(f), std::nextafter(f, k_inf)));
        CHECK(same(next_float_down(f), std::nextafter(f, -k_inf)));
    }
}

TEST_CASE("float steps equal nextafter on random bit patterns", "[shells][float]") {
    std::mt19937 rng(20261203);
    int mismatches = 0;
    for (int i = 0; i < 4000000; ++i) {
        std::uint32_t bits = rng();
        if (i % 4 == 0) bits &= 0x807fffffu;  // denormals and zeros
        float f;
        std::memcpy(&f, &bits, sizeof f);
        if (!same(next_float_up(f), std::nextafter(f, k_inf))) ++mismatches;
        if (!same(next_float_down(f), std::nextafter(f, -k_inf))) ++mismatches;
    }
    CHECK(mismatches == 0);
}

TEST_CASE("rounded bounds lie one float step beyond the double, on its side", "[shells][float]") {
    // Against std::nextafter from the floats either side of x found by
    // brute force: float_below_rounded(x) is one step below the largest
    // float <= x, float_above_rounded(x) one above the least float >= x.
    std::mt19937_64 rng(20261206);
    std::uniform_real_distribution<double> mantissa(-1.0, 1.0);
    int wrong = 0;
    for (int i = 0; i < 200000; ++i) {
        const double x = std::ldexp(mantissa(rng), static_cast<int>(rng() % 200) - 100);
        float below = static_cast<float>(x);
        while (static_cast<double>(below) > x) below = std::nextafter(below, -k_inf);
        float above = static_cast<float>(x);
        while (static_cast<double>(above) < x) above = std::nextafter(above, k_inf);
        if (!same(float_below_rounded(x), std::nextafter(below, -k_inf))) ++wrong;
        if (!same(float_above_rounded(x), std::nextafter(above, k_inf))) ++wrong;
        if (!(static_cast<double>(float_below_rounded(x)) < x && static_cast<double>(float_above_rounded(x)) > x))
            ++wrong;
    }
    CHECK(wrong == 0);
}
