#include "subdivtrace/shell.h"

#include <algorithm>

#include <glm/geometric.hpp>

namespace subdivtrace {

bool Shell::contains(const Vec3& p, double slack) const {
    if (p.x < lo.x - slack || p.y < lo.y - slack || p.z < lo.z - slack) return false;
    if (p.x > hi.x + slack || p.y > hi.y + slack || p.z > hi.z + slack) return false;
    if (axis != Vec3(0.0)) {
        const double d = glm::dot(axis, p);
        if (d < slab_min - slack || d > slab_max + slack) return false;
    }
    return true;
}

RayBoxQuery make_ray_box_query(const Vec3& origin, const Vec3& dir, double t_min, double t_max) {
    RayBoxQuery q;
    q.origin = origin;
    q.dir = dir;
    q.inv_dir = Vec3(1.0 / dir.x, 1.0 / dir.y, 1.0 / dir.z);
    q.t_min = t_min;
    q.t_max = t_max;
    return q;
}

bool ray_hits_shell(const RayBoxQuery& q, const Shell& shell, ShellKind kind, double& t_entry) {
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
