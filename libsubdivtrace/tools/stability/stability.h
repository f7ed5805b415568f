#pragma once
// The stability table (`subdivtrace stability`, docs/testing.md): each stiff
// case of DESIGN.md section 9 built in code, traced with a fixed set of rays,
// measured for levels, work, time, memory, NaNs, leaks and how far each hit
// lies from an exact intersection of the same drawn triangle.

#include <cstdint>
#include <string>
#include <vector>

#include "render/camera.h"
#include "subdivtrace/mesh.h"
#include "subdivtrace/tracer.h"

namespace subdivtrace::tools {

/// One stiff input with the camera that shows it.
struct StiffCase {
    std::string name;
    Mesh mesh;
    SurfaceOptions options;  ///< options.view is the camera's
    Camera camera;
    /// A point the surface encloses: every ray from it must hit (leak test).
    bool has_inside = false;
    Vec3 inside{0.0};
    /// The camera sits on the surface looking in: every camera ray must hit.
    bool camera_rays_must_hit = false;
};

/// The cases' names, in table order.
std::vector<std::string> stiff_case_names();

/// Builds the named case (std::invalid_argument for an unknown name) with a
/// width x height camera.
StiffCase make_stiff_case(const std::string& name, int width, int height);

/// Exact (to long double) reference for a hit: the ray parameter where the
/// ray meets the plane of the hit's drawn triangle, computed in long double
/// from the same double inputs.
long double reference_t(const Ray& ray, const Hit& hit);

/// Rounding bound on a hit's t from the watertight test in double precision
/// (pbrt-v4's Triangle::Intersect bound on t, for the same shear).
double t_rounding_bound(const Ray& ray, const Hit& hit);

struct StabilityRow {
    std::string name;
    int max_level = 0;               ///< deepest leaf level hit
    std::uint64_t nodes_built = 0;
    double visits_per_ray = 0.0;     ///< hierarchy nodes visited per ray
    double seconds = 0.0;            ///< surface construction plus every ray
    double peak_mb = 0.0;            ///< peak RSS above the RSS before the case
    std::uint64_t rays = 0;
    std::uint64_t hits = 0;
    std::uint64_t non_finite = 0;    ///< hits with a non-finite t, point or normal
    long long leaks = -1;            ///< must-hit rays that missed; -1 = no such rays
    double max_deviation = 0.0;      ///< largest |t - reference t| * |direction|
    double max_deviation_ratio = 0.0;///< largest |t - reference t| / rounding bound
};

/// Traces the case's camera image and, if it encloses a point, `inside_rays`
/// rays from that point (directions on a Fibonacci sphere).
StabilityRow run_stiff_case(const StiffCase& c, int inside_rays);

}  // namespace subdivtrace::tools
