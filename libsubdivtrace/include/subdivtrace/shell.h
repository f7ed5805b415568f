#pragma once
/// \file shell.h
/// Bounding shells B(t) (the paper's open problem 1, DESIGN.md section 4):
/// a convex volume that holds every descendant of a node up to max_level,
/// and the conservative ray tests against it.

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "subdivtrace/mesh.h"

namespace subdivtrace {

enum class ShellKind {
    /// Axis-aligned box only.
    aabb,
    /// Axis-aligned box intersected with a slab along the node's normal: the
    /// triangle prism with offsets, clipped by the box.
    aabb_slab,
};

/// pbrt's gamma(n) = n eps / (1 - n eps): a bound on the relative rounding
/// error of n floating-point operations.
constexpr double gamma_bound(int n) {
    constexpr double eps = std::numeric_limits<double>::epsilon() * 0.5;
    return (n * eps) / (1.0 - n * eps);
}

struct Shell {
    Vec3 lo{std::numeric_limits<double>::infinity()};
    Vec3 hi{-std::numeric_limits<double>::infinity()};
    /// Slab: points p with slab_min <= dot(axis, p) <= slab_max. axis == 0 means none.
    Vec3 axis{0.0};
    double slab_min = 0.0;
    double slab_max = 0.0;

    bool empty() const { return !(lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z); }
    // Inline: the shells of a tile's nodes grow by every point below them.
    void grow(const Vec3& p) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    /// Grows the box and the slab to hold p.
    void grow_both(const Vec3& p) {
        grow(p);
        if (axis != Vec3(0.0)) {
            const double d = glm::dot(axis, p);
            slab_min = std::min(slab_min, d);
            slab_max = std::max(slab_max, d);
        }
    }
    /// Pads box and slab by `margin` in every direction. Inline: every
    /// child record a tile hands out expands a compact shell and pads it.
    void pad(double margin) {
        lo -= Vec3(margin);
        hi += Vec3(margin);
        slab_min -= margin;
        slab_max += margin;
    }
    bool contains(const Vec3& p, double slack = 0.0) const;
    /// Width of the slab along its axis.
    double thickness() const { return slab_max - slab_min; }
};

/// A ray prepared for many box tests.
struct RayBoxQuery {
    Vec3 origin;
    Vec3 inv_dir;
    Vec3 dir;
    double t_min;
    double t_max;
};

RayBoxQuery make_ray_box_query(const Vec3& origin, const Vec3& dir, double t_min, double t_max);

/// Conservative slab test (Ize 2013: the far distance is scaled by
/// 1 + 2 gamma(3), so rounding never drops a ray that grazes a flat box); NaN
/// never counts as a hit. On a hit, [t_near, t_far] is the part of
/// [q.t_min, q.t_max] inside the box. Inline: the BVH's traversal calls it
/// for every node it meets.
inline bool ray_box_interval(const RayBoxQuery& q, const Vec3& lo, const Vec3& hi, double& t_near,
                             double& t_far) {
    t_near = q.t_min;
    t_far = q.t_max;
    for (int a = 0; a < 3; ++a) {
        double t0 = (lo[a] - q.origin[a]) * q.inv_dir[a];
        double t1 = (hi[a] - q.origin[a]) * q.inv_dir[a];
        if (t0 > t1) std::swap(t0, t1);
        t1 *= 1.0 + 2.0 * gamma_bound(3);
        // Written so that a NaN (0 * inf on a face the ray lies in) leaves the
        // interval unchanged instead of rejecting the ray.
        t_near = t0 > t_near ? t0 : t_near;
        t_far = t1 < t_far ? t1 : t_far;
        if (t_near > t_far) return false;
    }
    return true;
}

/// ray_box_interval's test; on a hit, t_entry is where the ray enters the volume.
inline bool ray_hits_box(const RayBoxQuery& q, const Vec3& lo, const Vec3& hi, double& t_entry) {
    double t_far = 0.0;
    return ray_box_interval(q, lo, hi, t_entry, t_far);
}

/// Box and (if present) slab, with the same conservative rounding. Inline:
/// a ray tests four at every node it enters.
inline bool ray_hits_shell(const RayBoxQuery& q, const Shell& shell, ShellKind kind, double& t_entry) {
    double t_near = 0.0;
    double t_far = 0.0;
    if (!ray_box_interval(q, shell.lo, shell.hi, t_near, t_far)) return false;
    if (kind == ShellKind::aabb_slab && shell.axis != Vec3(0.0)) {
        const double denom = glm::dot(shell.axis, q.dir);
        const double num = glm::dot(shell.axis, q.origin);
        // Rounding of the two dot products, bounded as in pbrt.
        const Vec3 ao = glm::abs(shell.axis * q.origin);
        const double err = gamma_bound(5) * (ao.x + ao.y + ao.z);
        const double s_min = shell.slab_min - err;
        const double s_max = shell.slab_max + err;
        if (denom == 0.0) {
            if (num < s_min || num > s_max) return false;
        } else {
            double t0 = (s_min - num) / denom;
            double t1 = (s_max - num) / denom;
            if (t0 > t1) std::swap(t0, t1);
            t0 *= t0 > 0.0 ? 1.0 - 2.0 * gamma_bound(3) : 1.0 + 2.0 * gamma_bound(3);
            t1 *= t1 > 0.0 ? 1.0 + 2.0 * gamma_bound(3) : 1.0 - 2.0 * gamma_bound(3);
            t_near = t0 > t_near ? t0 : t_near;
            t_far = t1 < t_far ? t1 : t_far;
            if (t_near > t_far) return false;
        }
    }
    t_entry = t_near;
    return true;
}

}  // namespace subdivtrace
