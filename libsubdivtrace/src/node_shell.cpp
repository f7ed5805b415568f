#include "node_shell.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

#include "float_step.h"
#include "loop_patch.h"

namespace subdivtrace::detail {

namespace {

/// Descendants of an interpolating scheme's node stay within this many times
/// the largest edge-point displacement of its neighbourhood from the hull of
/// its corners and its three edge points: those points are the first term of
/// the geometric series, so the rest, with ratio <= 1/2, sums to at most 1x
/// (docs/tracer.md section 2 has the measured ratios, 1/2.7 .. 1/3.7: about
/// 0.6x). tests/unit/test_shells.cpp holds it to containment.
constexpr double k_displacement_factor = 1.0;
/// Relative slack for rounding in the stencils, times the node's extent.
constexpr double k_rounding_slack = 1e-9;
/// Rounding steps allowed per coordinate between a base vertex and any
/// descendant (a few operations per stencil, over up to 16 levels, with
/// margin), times the coordinates' magnitude; the shell containment test at
/// 1e6 from the origin holds it.
constexpr int k_stencil_rounding_steps = 64 * 17;

}  // namespace

CompactShell CompactShell::from(const Shell& s, const Vec3& origin) {
    // Relative to a nearby origin, so float keeps the detail of a mesh far
    // from (0,0,0). One float step further out covers the double rounding of
    // the subtraction.
    CompactShell c;
    for (int a = 0; a < 3; ++a) {
        c.lo[a] = float_below_rounded(s.lo[a] - origin[a]);
        c.hi[a] = float_above_rounded(s.hi[a] - origin[a]);
        c.axis[a] = axis_bits(s.axis[a]);
    }
    const double offset = glm::dot(s.axis, origin);
    c.slab_min = float_below_rounded(s.slab_min - offset);
    c.slab_max = float_above_rounded(s.slab_max - offset);
    return c;
}

Shell descendant_shell(const Patch& p, const Patch* next, std::uint32_t t, const NodeRecord& rec,
                       const SchemeRules& scheme, ShellKind shell_kind, int max_level) {
    const PatchTriangle& tri = p.tris[t];
    // Slab axis: the node's own plane (or its corners' mean normal if it is degenerate).
    Shell shell;
    Vec3 axis = finish_normal(
        glm::cross(rec.position[1] - rec.position[0], rec.position[2] - rec.position[0]));
    if (axis == Vec3(0.0))
        axis = finish_normal(p.corner_normal[3 * t] + p.corner_normal[3 * t + 1] + p.corner_normal[3 * t + 2]);
    // Rounded first: the stored shell keeps this very axis.
    shell.axis = shell_kind == ShellKind::aabb_slab ? storable_axis(axis) : Vec3(0.0);
    if (shell.axis != Vec3(0.0)) shell.slab_min = shell.slab_max = glm::dot(shell.axis, rec.position[0]);
    for (int c = 0; c < 3; ++c) {
        shell.grow_both(rec.position[c]);
        shell.grow_both(rec.draw_position[c]);
    }

    if (tri.id.level < max_level) {
        if (scheme.convex_rules) {
            // Loop draws limit points: below t a ray meets only the limit
            // surface and flat triangles between its points. Where t's
            // corners are regular that surface is one Bezier triangle
            // (loop_patch.h), held by the hull of its net; else it is
            // bounded child by child (the middle child and the children of
            // regular corners by their nets, the others by their corners'
            // rings one level down). t's control points lie off the surface
            // and are never drawn, so they are not bounded. Where t's edges
            // are boundaries or creases, the corners' rings one level down
            // bound it all: Loop's stencils are convex combinations.
            Shell drawn;
            drawn.axis = shell.axis;
            if (drawn.axis != Vec3(0.0)) drawn.slab_min = drawn.slab_max = glm::dot(drawn.axis, rec.draw_position[0]);
            for (int c = 0; c < 3; ++c) drawn.grow_both(rec.draw_position[c]);
            LoopPatchPoints points;
            if (loop_patch_points(p, t, points)) {
                for (const Vec3& b : loop_bezier_net(points)) drawn.grow_both(b);
                shell = drawn;
            } else if (grow_by_children(p, *next, t, drawn)) {
                shell = drawn;
            } else {
                for (int c = 0; c < 3; ++c) grow_by_corner_ring(p, *next, t, c, shell);
            }
        } else {
            // Interpolating: the children's edge points are exact; deeper
            // levels are bounded by the displacement of every edge point in
            // the corners' neighbourhood, times a series factor.
            double max_displacement = 0.0;
            for (std::uint32_t v : tri.v) {
                if (!p.derived[v].has_displacement) stencil_cut("an edge point next to a corner");
                max_displacement = std::max(max_displacement, p.derived[v].displacement);
            }
            for (int e = 0; e < 3; ++e)
                shell.grow_both(next->verts[p.edges[p.tri_edges[3 * t + e]].point].position);
            if (tri.id.level + 1 < max_level) shell.pad(k_displacement_factor * max_displacement);
        }
    }
    // Slack for the stencils' rounding: relative to the node's extent, plus
    // the rounding of coordinates of this magnitude (a pad relative to the
    // distance from the origin would swallow a small mesh far from it: at
    // 1e6 it was wider than a 1e-3 mesh, and no shell culled anything).
    const Vec3 extent = shell.hi - shell.lo;
    const Vec3 magnitude = glm::max(glm::abs(shell.lo), glm::abs(shell.hi));
    shell.pad(k_rounding_slack * std::max({extent.x, extent.y, extent.z}) +
              gamma_bound(k_stencil_rounding_steps) * (magnitude.x + magnitude.y + magnitude.z));
    return shell;
}

}  // namespace subdivtrace::detail
