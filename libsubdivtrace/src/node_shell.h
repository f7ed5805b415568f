#pragma once
// A node's bounding shell (DESIGN.md section 4): the rules that grow it to
// hold every descendant down to max_level, and the compact single-precision
// form tiles store it in.

#include <array>
#include <cmath>
#include <cstdint>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "level_shell.h"
#include "patch.h"
#include "subdivtrace/hierarchy.h"
#include "subdivtrace/shell.h"

namespace subdivtrace::detail {

/// A shell stored in single precision relative to an origin near it, rounded
/// outwards: what a ray reads of a base triangle's bounds at 40 bytes instead
/// of 88 (a tile's levels keep theirs in LevelShell, 22 bytes).
struct CompactShell {
    float lo[3];
    float hi[3];
    std::int16_t axis[3];  ///< axis_bits
    float slab_min;
    float slab_max;

    /// `shell.axis` must be storable_axis's (descendant_shell rounds it so),
    /// so the slab keeps its meaning.
    static CompactShell from(const Shell& shell, const Vec3& origin);
    /// Inline: every child record a tile hands out expands one.
    Shell expand(const Vec3& origin) const {
        Shell s;
        s.lo = origin + Vec3(lo[0], lo[1], lo[2]);
        s.hi = origin + Vec3(hi[0], hi[1], hi[2]);
        s.axis = Vec3(axis_of_bits(axis[0]), axis_of_bits(axis[1]), axis_of_bits(axis[2]));
        const double offset = glm::dot(s.axis, origin);
        s.slab_min = offset + slab_min;
        s.slab_max = offset + slab_max;
        // The additions above round to nearest: pad by their error bound (the
        // sums of absolute values bound every coordinate and the slab offset).
        const Vec3 ao = glm::abs(origin) + glm::max(glm::abs(s.lo), glm::abs(s.hi));
        s.pad(gamma_bound(4) * (ao.x + ao.y + ao.z + std::abs(offset)));
        return s;
    }
};

/// The shell of patch triangle t whose record `rec` has its positions, drawn
/// positions and normals filled in: its corners and drawn points, grown by
/// the scheme's reach over its descendants (from `next`, the level below,
/// unless t is at max_level) and padded for the stencils' rounding.
Shell descendant_shell(const Patch& p, const Patch* next, std::uint32_t t, const NodeRecord& rec,
                       const SchemeRules& scheme, ShellKind shell_kind, int max_level);

}  // namespace subdivtrace::detail
