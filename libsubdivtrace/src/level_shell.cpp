#include "level_shell.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "float_step.h"

namespace subdivtrace::detail {

namespace {

constexpr std::uint16_t k_last = ShellGrid::k_last;

/// The largest q whose value(q) is not above `target` (0 if none is), from
/// the estimate (target - first) / step: a step or two of search at most.
template <class Value>
std::uint16_t step_at_or_below(double target, double first, double step, Value value) {
    if (!(step > 0.0)) return 0;
    const double x = (target - first) / step;
    // Also where x is NaN: no float-to-integer conversion out of range.
    auto q = static_cast<std::uint16_t>(x >= k_last ? k_last : x > 0.0 ? std::floor(x) : 0.0);
    while (q > 0 && value(q) > target) --q;
    return q;
}

/// The smallest q whose value(q) is not below `target` (k_last if none is).
template <class Value>
std::uint16_t step_at_or_above(double target, double first, double step, Value value) {
    if (!(step > 0.0)) return k_last;
    const double x = (target - first) / step;
    auto q = static_cast<std::uint16_t>(x >= k_last ? k_last : x > 0.0 ? std::ceil(x) : 0.0);
    while (q < k_last && value(q) < target) ++q;
    return q;
}

}  // namespace

std::int16_t axis_bits(double coordinate) {
    if (std::isnan(coordinate)) return 0;
    const double scaled = std::round(std::clamp(coordinate, -1.0, 1.0) * 32768.0);
    return static_cast<std::int16_t>(std::clamp(scaled, -32767.0, 32767.0));
}

Vec3 storable_axis(const Vec3& axis) {
    return Vec3(axis_of_bits(axis_bits(axis.x)), axis_of_bits(axis_bits(axis.y)), axis_of_bits(axis_bits(axis.z)));
}

ShellGrid ShellGrid::spanning(const Shell* shells, std::size_t count, const Vec3& origin) {
    Vec3 lo(std::numeric_limits<double>::infinity());
    Vec3 hi(-std::numeric_limits<double>::infinity());
    for (std::size_t k = 0; k < count; ++k) {
        if (shells[k].empty()) continue;
        lo = glm::min(lo, shells[k].lo);
        hi = glm::max(hi, shells[k].hi);
    }
    ShellGrid grid;
    if (!(lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z)) return grid;  // nothing to span
    for (int a = 0; a < 3; ++a) {
        grid.lo[a] = float_below_rounded(lo[a] - origin[a]);
        // k_last - 1 steps reach past the top: the last one is margin for rounding.
        const double extent = hi[a] - (origin[a] + static_cast<double>(grid.lo[a]));
        grid.step[a] = float_above_rounded(extent / (k_last - 1));
    }
    // expand()'s sums: a coordinate (three terms), and the slab's base and
    // step (three products each, then their difference), all below the
    // magnitude of the grid's corners plus the origin.
    double magnitude = 0.0;
    const LevelShell::Frame unshifted(grid, Vec3(0.0));
    for (int a = 0; a < 3; ++a)
        magnitude += std::abs(origin[a]) + std::max(std::abs(static_cast<double>(grid.lo[a])),
                                                    std::abs(unshifted.coordinate(a, k_last)));
    grid.pad = round_up(gamma_bound(16) * 2.0 * magnitude);
    // A level wider than a float reaches (1e38 and up; its magnitude above
    // is then infinite too): its shells hold everything (expand()).
    for (int a = 0; a < 3; ++a)
        if (!std::isfinite(grid.lo[a]) || !std::isfinite(grid.step[a])) grid.pad = std::numeric_limits<float>::infinity();
    return grid;
}

LevelShell LevelShell::from(const Shell& s, const ShellGrid& grid, const Vec3& origin) {
    LevelShell c{};
    if (s.empty()) {
        // expand() gives lo above hi: still empty.
        for (int a = 0; a < 3; ++a) c.lo[a] = k_last;
        return c;
    }
    const Frame frame(grid, origin);
    for (int a = 0; a < 3; ++a) {
        const auto value = [&](std::uint16_t q) { return frame.coordinate(a, q); };
        const double first = origin[a] + static_cast<double>(grid.lo[a]);
        c.lo[a] = step_at_or_below(s.lo[a], first, grid.step[a], value);
        c.hi[a] = step_at_or_above(s.hi[a], first, grid.step[a], value);
        c.axis[a] = axis_bits(s.axis[a]);
    }
    if (c.axis[0] != 0 || c.axis[1] != 0 || c.axis[2] != 0) {
        const SlabSpan span = SlabSpan::of(c.box(frame));
        const auto value = [&](std::uint16_t q) { return span.value(q); };
        c.slab[0] = step_at_or_below(s.slab_min, span.base, span.step, value);
        c.slab[1] = step_at_or_above(s.slab_max, span.base, span.step, value);
    }
    return c;
}

}  // namespace subdivtrace::detail
