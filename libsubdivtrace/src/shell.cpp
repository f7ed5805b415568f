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

}  // namespace subdivtrace
