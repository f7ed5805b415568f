// LevelShell (a tile level's shells in 16-bit steps of a grid over the
// level) against the points it must hold: every point a shell was grown by
// lies in its stored box and slab, the stored shell is at most a few grid
// steps wider than the exact one, and empty stays empty. Levels near the
// origin, at 1e6 from it, tiny and flat.
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include <catch2/catch.hpp>
#include <glm/geometric.hpp>

#include "level_shell.h"

using subdivtrace::Shell;
using subdivtrace::Vec3;
using subdivtrace::detail::LevelShell;
using subdivtrace::detail::ShellGrid;
using subdivtrace::detail::storable_axis;

namespace {

struct Level {
    Vec3 origin;
    std::vector<std::vector<Vec3>> points;  ///< what each shell was grown by
    std::vector<Shell> shells;
};

/// `count` shells of random point clouds around `centre` with spread `size`
/// (flat along z where `flat`), each with a slab along a random axis.
Level random_level(std::mt19937_64& rng, const Vec3& centre, double size, int count, bool flat) {
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::normal_distribution<double> gauss;
    Level level;
    level.origin = centre + Vec3(u(rng), u(rng), u(rng)) * (0.1 * size);
    for (int k = 0; k < count; ++k) {
        const Vec3 at = centre + Vec3(u(rng), u(rng), flat ? 0.0 : u(rng)) * size;
        const double spread = size * std::pow(10.0, -3.0 * (u(rng) + 1.0) / 2.0);  // size .. size/1000
        Shell s;
        s.axis = storable_axis(glm::normalize(Vec3(gauss(rng), gauss(rng), gauss(rng))));
        std::vector<Vec3> cloud;
        for (int i = 0; i < 8; ++i) {
            const Vec3 p = at + Vec3(u(rng), u(rng), flat ? 0.0 : u(rng)) * spread;
            if (cloud.empty()) s.slab_min = s.slab_max = glm::dot(s.axis, p);
            s.grow_both(p);
            cloud.push_back(p);
        }
        level.points.push_back(cloud);
        level.shells.push_back(s);
    }
    return level;
}

}  // namespace

TEST_CASE("level shells hold every point their exact shells hold, a few grid steps wider at most",
          "[shells][level_shell]") {
    std::mt19937_64 rng(20261206);
    struct Case {
        const char* name;
        Vec3 centre;
        double size;
        bool flat;
    };
    const Case cases[] = {
        {"unit, at the origin", Vec3(0.0), 1.0, false},
        {"unit, at 1e6", Vec3(1e6, -1e6, 1e6), 1.0, false},
        {"tiny (1e-3), at 1e6", Vec3(1e6, 2e6, -3e6), 1e-3, false},
        {"flat along z", Vec3(0.5, 0.25, 2.0), 1.0, true},
    };
    for (const Case& c : cases) {
        INFO(c.name);
        for (int round = 0; round < 200; ++round) {
            const Level level = random_level(rng, c.centre, c.size, 16, c.flat);
            const ShellGrid grid = ShellGrid::spanning(level.shells.data(), level.shells.size(), level.origin);
            for (std::size_t k = 0; k < level.shells.size(); ++k) {
                const Shell& exact = level.shells[k];
                const Shell stored = LevelShell::from(exact, grid, level.origin).expand(grid, level.origin);
                REQUIRE(stored.axis == exact.axis);
                for (const Vec3& p : level.points[k]) {
                    REQUIRE(stored.contains(p));
                    const double d = glm::dot(stored.axis, p);
                    REQUIRE(d >= stored.slab_min);
                    REQUIRE(d <= stored.slab_max);
                }
                for (int a = 0; a < 3; ++a) {
                    REQUIRE(stored.lo[a] <= exact.lo[a]);
                    REQUIRE(stored.hi[a] >= exact.hi[a]);
                    // One step of rounding each way, and the pad (far below a step).
                    const double step = grid.step[a];
                    CHECK(exact.lo[a] - stored.lo[a] <= 1.01 * step + 1e-9 * std::abs(exact.lo[a]));
                    CHECK(stored.hi[a] - exact.hi[a] <= 1.01 * step + 1e-9 * std::abs(exact.hi[a]));
                }
                REQUIRE(stored.slab_min <= exact.slab_min);
                REQUIRE(stored.slab_max >= exact.slab_max);
                // A slab step is the stored box's extent along the axis / 65535.
                const Vec3 extent = stored.hi - stored.lo;
                const double slab_step = glm::dot(glm::abs(stored.axis), extent) / 65535.0;
                const double magnitude = std::abs(glm::dot(stored.axis, stored.lo)) + glm::dot(glm::abs(stored.axis), extent);
                CHECK(stored.thickness() - exact.thickness() <= 2.01 * slab_step + 1e-9 * magnitude);
            }
        }
    }
}

TEST_CASE("an empty level shell stays empty, and axes are stored exactly", "[shells][level_shell]") {
    Shell one;
    one.grow(Vec3(1.0, 2.0, 3.0));
    one.grow(Vec3(1.5, 2.5, 3.5));
    const Shell shells[2] = {Shell{}, one};
    const Vec3 origin(1.0, 2.0, 3.0);
    const ShellGrid grid = ShellGrid::spanning(shells, 2, origin);
    CHECK(LevelShell::from(Shell{}, grid, origin).expand(grid, origin).empty());
    const Shell kept = LevelShell::from(one, grid, origin).expand(grid, origin);
    CHECK_FALSE(kept.empty());
    CHECK(kept.axis == Vec3(0.0));  // a box alone stays a box alone
    CHECK(kept.contains(Vec3(1.0, 2.0, 3.0)));
    CHECK(kept.contains(Vec3(1.5, 2.5, 3.5)));

    std::mt19937_64 rng(7);
    std::normal_distribution<double> gauss;
    for (int i = 0; i < 100000; ++i) {
        const Vec3 n = glm::normalize(Vec3(gauss(rng), gauss(rng), gauss(rng)));
        const Vec3 a = storable_axis(n);
        REQUIRE(glm::length(a - n) <= 2.0 * std::sqrt(3.0) / 65536.0);
        // A float holds it exactly (CompactShell stores the slab along it).
        for (int k = 0; k < 3; ++k) REQUIRE(static_cast<double>(static_cast<float>(a[k])) == a[k]);
        REQUIRE(storable_axis(a) == a);
    }
}

TEST_CASE("a level wider than a float reaches keeps shells that hold everything", "[shells][level_shell]") {
    Shell wide;
    wide.axis = storable_axis(glm::normalize(Vec3(1.0, 2.0, 3.0)));
    const Vec3 points[2] = {Vec3(-1e39, 2.0, 3.0), Vec3(1e39, -5e38, 7e38)};
    wide.slab_min = wide.slab_max = glm::dot(wide.axis, points[0]);
    for (const Vec3& p : points) wide.grow_both(p);
    const Vec3 origin(0.0);
    const ShellGrid grid = ShellGrid::spanning(&wide, 1, origin);
    const Shell stored = LevelShell::from(wide, grid, origin).expand(grid, origin);
    // Compared one by one: Shell::contains passes NaN bounds.
    for (const Vec3& p : points)
        for (int a = 0; a < 3; ++a) {
            CHECK(stored.lo[a] <= p[a]);
            CHECK(stored.hi[a] >= p[a]);
        }
    // A level within float's range keeps finite shells.
    Shell near_one;
    near_one.grow(Vec3(1.0));
    near_one.grow(Vec3(2.0));
    const ShellGrid finite = ShellGrid::spanning(&near_one, 1, origin);
    const Shell kept = LevelShell::from(near_one, finite, origin).expand(finite, origin);
    CHECK(std::isfinite(kept.lo.x));
    CHECK(std::isfinite(kept.hi.z));
}

TEST_CASE("level shells expanded two at a time are expand()'s bits", "[shells][level_shell]") {
    // Random levels near the origin and far from it, with shells that have
    // no slab (a zero axis), empty ones, and a level too wide for its grid.
    std::mt19937_64 rng(7);
    const auto same_bits = [](const Shell& x, const Shell& y) {
        const double xs[11] = {x.lo.x, x.lo.y, x.lo.z, x.hi.x, x.hi.y, x.hi.z, x.axis.x, x.axis.y, x.axis.z, x.slab_min, x.slab_max};
        const double ys[11] = {y.lo.x, y.lo.y, y.lo.z, y.hi.x, y.hi.y, y.hi.z, y.axis.x, y.axis.y, y.axis.z, y.slab_min, y.slab_max};
        return std::memcmp(xs, ys, sizeof xs) == 0;
    };
    int pairs = 0;
    for (const Vec3& centre : {Vec3(0.3, -0.2, 0.1), Vec3(1e6, -2e6, 5e5)}) {
        Level level = random_level(rng, centre, 0.5, 40, false);
        level.shells[3].axis = Vec3(0.0);  // a box alone
        level.shells[8] = Shell{};        // empty
        const ShellGrid grid = ShellGrid::spanning(level.shells.data(), level.shells.size(), level.origin);
        std::vector<LevelShell> stored;
        for (const Shell& s : level.shells) stored.push_back(LevelShell::from(s, grid, level.origin));
        const LevelShell::Frame frame(grid, level.origin);
        for (std::size_t a = 0; a < stored.size(); ++a)
            for (std::size_t b = 0; b < stored.size(); b += 3) {
                Shell out_a, out_b;
                LevelShell::expand_pair(frame, stored[a], stored[b], out_a, out_b);
                REQUIRE(same_bits(out_a, stored[a].expand(frame)));
                REQUIRE(same_bits(out_b, stored[b].expand(frame)));
                ++pairs;
            }
    }
    // A level too wide for a float grid: every shell unbounded.
    Shell wide;
    wide.lo = Vec3(-1e300);
    wide.hi = Vec3(1e300);
    const Vec3 origin(0.0);
    const ShellGrid grid = ShellGrid::spanning(&wide, 1, origin);
    const LevelShell one = LevelShell::from(wide, grid, origin);
    Shell out_a, out_b;
    LevelShell::expand_pair(LevelShell::Frame(grid, origin), one, one, out_a, out_b);
    CHECK(same_bits(out_a, one.expand(grid, origin)));
    CHECK(same_bits(out_b, one.expand(grid, origin)));
    CHECK(pairs > 1000);
}
