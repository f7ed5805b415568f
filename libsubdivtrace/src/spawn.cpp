#include "subdivtrace/spawn.h"

#include <algorithm>

#include <glm/geometric.hpp>

namespace subdivtrace {

Ray spawn_shadow_ray(const Ray& ray, const Hit& hit, const Vec3& target) {
    Vec3 g = hit.geometric_normal;
    if (glm::dot(g, target - hit.point) < 0.0) g = -g;
    Ray s;
    s.origin = hit.point + g * (hit.error_bound + 1e-12 * glm::length(hit.point));
    s.direction = glm::normalize(target - s.origin);
    s.t_min = 0.0;
    s.t_max = glm::length(target - s.origin);
    s.origin_distance = hit.t * glm::length(ray.direction) + std::max(0.0, ray.origin_distance);
    s.view = ray.view;
    return s;
}

}  // namespace subdivtrace
