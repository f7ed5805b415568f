#pragma once
// The standalone renderer's pinhole camera (the CLI, the tests and the Embree
// peer in compare/ all use it, so their images line up pixel for pixel).

#include "subdivtrace/mesh.h"
#include "subdivtrace/tracer.h"

namespace subdivtrace::tools {

/// A pinhole camera; pixel (x, y) has y pointing down.
struct Camera {
    Vec3 look_from{0.0, 0.0, 5.0};
    Vec3 look_at{0.0};
    Vec3 up{0.0, 1.0, 0.0};
    double fov_degrees = 40.0;  ///< horizontal field of view
    int width = 640;
    int height = 480;

    /// The angle of one pixel (the footprint rule's pixel_angle).
    double pixel_angle() const;
    /// The camera ray through pixel centre (x + 0.5, y + 0.5), y down; unit
    /// direction, origin_distance 0.
    Ray ray(int x, int y) const;
    /// The footprint view of this camera (perspective).
    View view() const;
};

/// The camera's orthonormal frame.
struct CameraFrame {
    Vec3 forward, right, up;
    double half_width;  ///< tan(fov/2)
};
CameraFrame frame_of(const Camera& camera);

/// A camera that frames the whole box from the front-right-above, at `fov`.
Camera frame_bounds(const Bounds3& bounds, int width, int height, double fov_degrees);

/// The default point light: above and to the right of the camera, at the
/// distance of the scene's diagonal.
Vec3 default_light(const Camera& camera, const Bounds3& scene_bounds);

}  // namespace subdivtrace::tools
