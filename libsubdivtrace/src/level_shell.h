#pragma once
// A tile level's shells in 22 bytes each (CompactShell: 40): every box
// corner a 16-bit step of a grid that spans the level's shells, and the slab
// a 16-bit fraction of the box's own extent along its axis. A level's shells
// were over half of its bytes at 44 each (docs/tracer.md, "What the surface
// holds"); one step of the grid is 1/65535 of the level's extent, so a shell
// of level 3 of a tile (1/8 of it) grows by about 0.01% per side.
//
// Rounded outwards as CompactShell is: each stored value is checked against
// the very expression expand() evaluates, and expand() pads by that
// expression's rounding besides.

#include <cstddef>
#include <cstdint>
#include <limits>

#include <glm/geometric.hpp>

#include "double_pairs.h"

#include "subdivtrace/shell.h"

namespace subdivtrace::detail {

/// The axis a stored shell keeps: each coordinate the nearest multiple of
/// 2^-15, so 16 bits (and a float) hold it exactly and the slab computed
/// along it keeps its meaning once stored. Within 2e-5 of the unit input.
Vec3 storable_axis(const Vec3& axis);
/// Coordinate a of an axis of storable_axis in 16 bits, and back.
std::int16_t axis_bits(double coordinate);
inline double axis_of_bits(std::int16_t bits) { return bits * (1.0 / 32768.0); }

/// The grid a level's shells are quantised on: its lowest corner relative
/// to the tile's origin and its step, per axis, and how far expand() pads.
struct ShellGrid {
    float lo[3] = {0.0f, 0.0f, 0.0f};
    float step[3] = {0.0f, 0.0f, 0.0f};
    /// A bound on the rounding of expand()'s sums for this level (from the
    /// magnitude of its coordinates): from() checks each value against
    /// those very sums, and the pad covers a compiler that evaluates them
    /// differently in another place (contracting them into fused
    /// multiply-adds, say).
    float pad = 0.0f;

    static constexpr std::uint16_t k_last = 65535;
    /// A grid whose k_last steps span the non-empty shells of `shells`.
    static ShellGrid spanning(const Shell* shells, std::size_t count, const Vec3& origin);
};

/// Where a box's slab fractions lie along its axis: fraction 0 at `base`
/// (the least of the axis over the box), each of the k_last steps `step`
/// further.
struct SlabSpan {
    double base;
    double step;
    static SlabSpan of(const Shell& box) {
        double base = 0.0, top = 0.0;
        for (int a = 0; a < 3; ++a) {
            const bool rising = box.axis[a] >= 0.0;
            base += box.axis[a] * (rising ? box.lo[a] : box.hi[a]);
            top += box.axis[a] * (rising ? box.hi[a] : box.lo[a]);
        }
        return {base, (top - base) * (1.0 / ShellGrid::k_last)};
    }
    double value(std::uint16_t q) const { return base + q * step; }
};

struct LevelShell {
    std::uint16_t lo[3];
    std::uint16_t hi[3];
    std::int16_t axis[3];  ///< Shell::axis in steps of 2^-15 (storable_axis)
    /// The slab as fractions (of k_last) of the box's extent along the axis.
    std::uint16_t slab[2];

    /// `shell.axis` must be storable_axis's (descendant_shell rounds it so).
    /// An empty shell stays empty.
    static LevelShell from(const Shell& shell, const ShellGrid& grid, const Vec3& origin);
    /// What expand() reads of a level's grid and its tile's origin, in
    /// double once for the four children a ray expands at every node it
    /// enters (the same bits: a float converts to double exactly).
    struct Frame {
        Frame(const ShellGrid& grid, const Vec3& tile_origin)
            : origin(tile_origin),
              lo{grid.lo[0], grid.lo[1], grid.lo[2]},
              step{grid.step[0], grid.step[1], grid.step[2]},
              pad(grid.pad),
              unbounded(!(grid.pad <= std::numeric_limits<float>::max())) {}
        Vec3 origin;
        double lo[3];
        double step[3];
        double pad;
        /// A level too wide for the grid (ShellGrid::spanning).
        bool unbounded;
        /// Coordinate `a` of grid point q (q * step is exact in double: 16 by 24 bits).
        double coordinate(int a, std::uint16_t q) const { return origin[a] + (lo[a] + q * step[a]); }
    };

    /// Inline: a ray expands the shells of the four children of every node it enters.
    Shell expand(const Frame& f) const {
        if (lo[0] > hi[0]) return Shell{};  // stored empty
        if (f.unbounded) {
            Shell unbounded;
            unbounded.lo = Vec3(-std::numeric_limits<double>::infinity());
            unbounded.hi = Vec3(std::numeric_limits<double>::infinity());
            return unbounded;
        }
        Shell s = box(f);
        if (s.axis != Vec3(0.0)) {
            const SlabSpan span = SlabSpan::of(s);
            s.slab_min = span.value(slab[0]);
            s.slab_max = span.value(slab[1]);
        }
        s.pad(f.pad);
        return s;
    }
    Shell expand(const ShellGrid& grid, const Vec3& origin) const { return expand(Frame(grid, origin)); }

    /// expand() of two shells at once where SSE2 is (a node's children are
    /// expanded together): each lane does expand()'s operations in its
    /// order, so the shells are the same bits.
    static void expand_pair(const Frame& f, const LevelShell& a, const LevelShell& b, Shell& out_a, Shell& out_b) {
#if defined(__SSE2__)
        if (a.lo[0] > a.hi[0] || b.lo[0] > b.hi[0] || f.unbounded) {
#endif
            out_a = a.expand(f);
            out_b = b.expand(f);
#if defined(__SSE2__)
            return;
        }
        const __m128d pad = _mm_set1_pd(f.pad);
        __m128d lo[3], hi[3], axis[3];
        bool has_axis_a = false, has_axis_b = false;
        for (int k = 0; k < 3; ++k) {
            // box(): origin + (lo + q * step), the grid point q exact in double.
            const __m128d origin = _mm_set1_pd(f.origin[k]), grid_lo = _mm_set1_pd(f.lo[k]);
            const __m128d step = _mm_set1_pd(f.step[k]);
            lo[k] = _mm_add_pd(origin, _mm_add_pd(grid_lo, _mm_mul_pd(pair_of(a.lo[k], b.lo[k]), step)));
            hi[k] = _mm_add_pd(origin, _mm_add_pd(grid_lo, _mm_mul_pd(pair_of(a.hi[k], b.hi[k]), step)));
            axis[k] = _mm_mul_pd(pair_of(a.axis[k], b.axis[k]), _mm_set1_pd(1.0 / 32768.0));
            has_axis_a = has_axis_a || a.axis[k] != 0;
            has_axis_b = has_axis_b || b.axis[k] != 0;
        }
        // SlabSpan::of: the axis over the box's lowest and highest corners.
        __m128d base = _mm_setzero_pd(), top = _mm_setzero_pd();
        for (int k = 0; k < 3; ++k) {
            const __m128d rising = _mm_cmpge_pd(axis[k], _mm_setzero_pd());
            const __m128d low_end = select_lanes(rising, lo[k], hi[k]);
            const __m128d high_end = select_lanes(rising, hi[k], lo[k]);
            base = _mm_add_pd(base, _mm_mul_pd(axis[k], low_end));
            top = _mm_add_pd(top, _mm_mul_pd(axis[k], high_end));
        }
        const __m128d slab_step = _mm_mul_pd(_mm_sub_pd(top, base), _mm_set1_pd(1.0 / ShellGrid::k_last));
        __m128d slab_min = _mm_add_pd(base, _mm_mul_pd(pair_of(a.slab[0], b.slab[0]), slab_step));
        __m128d slab_max = _mm_add_pd(base, _mm_mul_pd(pair_of(a.slab[1], b.slab[1]), slab_step));
        // Without an axis the slab stays at zero, as expand() leaves it.
        const __m128d has_axis = lane_mask(has_axis_a, has_axis_b);
        slab_min = _mm_and_pd(has_axis, slab_min);
        slab_max = _mm_and_pd(has_axis, slab_max);
        // Shell::pad.
        for (int k = 0; k < 3; ++k) {
            store_lanes(_mm_sub_pd(lo[k], pad), out_a.lo[k], out_b.lo[k]);
            store_lanes(_mm_add_pd(hi[k], pad), out_a.hi[k], out_b.hi[k]);
            store_lanes(axis[k], out_a.axis[k], out_b.axis[k]);
        }
        store_lanes(_mm_sub_pd(slab_min, pad), out_a.slab_min, out_b.slab_min);
        store_lanes(_mm_add_pd(slab_max, pad), out_a.slab_max, out_b.slab_max);
#endif
    }

private:
    /// The stored box and axis, unpadded and without the slab: what
    /// expand() starts from and from() measures the slab against.
    Shell box(const Frame& f) const {
        Shell s;
        for (int a = 0; a < 3; ++a) {
            s.lo[a] = f.coordinate(a, lo[a]);
            s.hi[a] = f.coordinate(a, hi[a]);
            s.axis[a] = axis_of_bits(axis[a]);
        }
        return s;
    }
};
static_assert(sizeof(LevelShell) == 22, "eleven 16-bit values, no padding");

}  // namespace subdivtrace::detail
