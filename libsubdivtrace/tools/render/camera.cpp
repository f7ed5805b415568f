#include "render/camera.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace subdivtrace::tools {

namespace {
constexpr double k_pi = 3.14159265358979323846;
}

CameraFrame frame_of(const Camera& c) {
    CameraFrame f;
    f.forward = glm::normalize(c.look_at - c.look_from);
    f.right = glm::cross(f.forward, c.up);
    if (glm::length(f.right) < 1e-12) f.right = glm::cross(f.forward, Vec3(1.0, 0.0, 0.0));
    f.right = glm::normalize(f.right);
    f.up = glm::cross(f.right, f.forward);
    f.half_width = std::tan(0.5 * c.fov_degrees * k_pi / 180.0);
    return f;
}

double Camera::pixel_angle() const {
    return 2.0 * std::tan(0.5 * fov_degrees * k_pi / 180.0) / std::max(width, 1);
}

Ray Camera::ray(int x, int y) const {
    const CameraFrame f = frame_of(*this);
    const double aspect = static_cast<double>(height) / std::max(width, 1);
    const double sx = ((x + 0.5) / width * 2.0 - 1.0) * f.half_width;
    const double sy = (1.0 - (y + 0.5) / height * 2.0) * f.half_width * aspect;
    Ray r;
    r.origin = look_from;
    r.direction = glm::normalize(f.forward + f.right * sx + f.up * sy);
    r.origin_distance = 0.0;
    return r;
}

View Camera::view() const {
    View v;
    v.camera = look_from;
    v.pixel_angle = pixel_angle();
    return v;
}

Camera frame_bounds(const Bounds3& b, int width, int height, double fov_degrees) {
    Camera c;
    c.width = width;
    c.height = height;
    c.fov_degrees = fov_degrees;
    const Vec3 centre = (b.lo + b.hi) * 0.5;
    // Any positive size frames (a mesh of scale 1e-11 too); a single point
    // gets a radius relative to where it is.
    const double size = 0.5 * glm::length(b.hi - b.lo);
    const double radius = size > 0.0 ? size : std::max(1e-9 * glm::length(centre), 1e-300);
    // Fit the bounding sphere in the narrower field of view, with a margin.
    const double half = 0.5 * fov_degrees * k_pi / 180.0;
    const double vertical = std::atan(std::tan(half) * height / std::max(width, 1));
    const double distance = 1.15 * radius / std::sin(std::min(half, vertical));
    c.look_at = centre;
    c.look_from = centre + glm::normalize(Vec3(0.45, 0.35, 1.0)) * distance;
    return c;
}

Vec3 default_light(const Camera& c, const Bounds3& b) {
    const CameraFrame f = frame_of(c);
    const double size = glm::length(b.hi - b.lo);
    return c.look_from + (f.up * 0.8 + f.right * 0.6) * std::max(size, 1e-12);
}

}  // namespace subdivtrace::tools
