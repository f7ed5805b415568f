#pragma once
/// \file render.h
/// The standalone renderer: a pinhole camera, headlight Lambert shading of
/// the smooth normal and one optional shadow ray to a point light. Renders
/// the adaptive surface, or a uniform level-K mesh through a binned-SAH BVH
/// with the same camera and shading (the baseline).

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "subdivtrace/tracer.h"
#include "subdivtrace/uniform.h"

namespace subdivtrace {

struct Camera {
    Vec3 look_from{0.0, 0.0, 5.0};
    Vec3 look_at{0.0};
    Vec3 up{0.0, 1.0, 0.0};
    double fov_degrees = 40.0;  ///< horizontal field of view
    int width = 640;
    int height = 480;

    /// The angle of one pixel (the footprint rule's pixel_angle).
    double pixel_angle() const;
    /// The camera ray through pixel centre (x + 0.5, y + 0.5), y down.
    Ray ray(int x, int y) const;
};

/// A camera that frames the whole box from the front-right-above, at `fov`.
Camera frame_bounds(const Bounds3& bounds, int width, int height, double fov_degrees);

struct RenderOptions {
    int threads = 0;             ///< 0 = all hardware threads
    bool shadows = true;         ///< one shadow ray per hit towards the light
    bool has_light = false;      ///< false: light placed beside the camera
    Vec3 light{0.0};
    bool progress = false;       ///< progress on stderr for renders over a second
};

struct Image {
    int width = 0;
    int height = 0;
    std::vector<float> rgb;  ///< width * height * 3, linear, row 0 at the top
};

struct RenderStats {
    double trace_seconds = 0.0;
    std::uint64_t rays = 0;         ///< camera + shadow rays
    std::uint64_t shadow_rays = 0;
    std::uint64_t hit_pixels = 0;
};

/// Anything that can intersect a ray: the adaptive surface or a uniform mesh.
using IntersectFn = std::function<bool(const Ray&, Hit&)>;

/// Renders with `threads` threads; the image does not depend on the thread count.
Image render(const IntersectFn& intersect, const Camera& camera, const RenderOptions& options,
             const Bounds3& scene_bounds, RenderStats& stats);

/// A uniform mesh with a BVH, intersected like the adaptive surface.
class UniformScene {
public:
    explicit UniformScene(SubdividedMesh mesh);
    ~UniformScene();
    bool intersect(const Ray& ray, Hit& hit) const;
    Bounds3 bounds() const;
    std::size_t memory_bytes() const;
    std::size_t triangle_count() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

/// The shadow ray from `hit` (found by `ray`) towards a point light: it leaves
/// the surface by the hit's error bound on the light's side (pbrt's spawn-ray
/// offset) and carries the camera path length, so the footprint rule gives it
/// the camera's resolution near its origin (DESIGN section 5).
Ray spawn_shadow_ray(const Ray& ray, const Hit& hit, const Vec3& light);

/// Peak resident set size of this process (VmHWM), in bytes; 0 if unknown.
std::size_t peak_rss_bytes();
/// Current resident set size (VmRSS), in bytes; 0 if unknown.
std::size_t current_rss_bytes();

}  // namespace subdivtrace
