#pragma once
// The standalone renderer's image loop: headlight Lambert shading of the
// smooth normal and one optional shadow ray to a point light, over any
// intersector (the adaptive surface, the uniform baseline, Embree).

#include <cstdint>
#include <functional>
#include <vector>

#include "render/camera.h"
#include "render/false_colour.h"
#include "subdivtrace/tracer.h"

namespace subdivtrace::tools {

struct RenderOptions {
    int threads = 0;             ///< 0 = all hardware threads
    bool shadows = true;         ///< one shadow ray per hit towards the light
    bool has_light = false;      ///< false: default_light()
    Vec3 light{0.0};
    bool progress = false;       ///< progress on stderr for renders over a second
    /// False colours instead of shading (headlight only, no shadow rays).
    ColorBy color_by = ColorBy::shading;
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
    /// Pixels per leaf level (always) and per base face (ColorBy::face only).
    PixelTally tally;
};

/// Anything that can intersect a ray: the adaptive surface or a uniform mesh.
using IntersectFn = std::function<bool(const Ray&, Hit&)>;

/// Renders with `threads` threads; the image does not depend on the thread count.
Image render(const IntersectFn& intersect, const Camera& camera, const RenderOptions& options,
             const Bounds3& scene_bounds, RenderStats& stats);

}  // namespace subdivtrace::tools
