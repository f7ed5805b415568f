#include "stability/stability.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include <glm/geometric.hpp>

#ifdef __GLIBC__
#include <malloc.h>
#endif

#include "ray_triangle.h"
#include "render/rss.h"
#include "stability/stiff_meshes.h"

namespace subdivtrace::tools {

namespace {

constexpr double k_pi = 3.14159265358979323846;

const char* const k_names[] = {
    "sliver 1e6",        "zero-area",       "duplicate triangles", "valence 100",
    "valence 200",       "folds",           "crease (cube)",       "boundary (open)",
    "non-manifold edge", "offset 1e6, 1e-3", "scale 1e-6",          "scale 1e6",
    "grazing rays",      "camera on surface", "max_level forced",
};

/// The icosahedron with one face written twice (same corners, same order).
Mesh duplicate_face_mesh() {
    Mesh m = icosahedron();
    m.triangles.push_back(m.triangles[0]);
    return m;
}

/// The icosahedron with a fin on edge (0, 11): that edge has three faces.
Mesh fin_mesh() {
    Mesh m = icosahedron();
    const auto fin = static_cast<std::uint32_t>(m.positions.size());
    m.positions.push_back(m.positions[0] + m.positions[11]);  // outside, off the edge's middle
    m.triangles.push_back({0, 11, fin});
    return m;
}

/// The icosahedron without the five faces around vertex 0: a pentagonal hole.
Mesh holed_mesh() {
    Mesh m = icosahedron();
    std::vector<Triangle> kept;
    for (const Triangle& t : m.triangles)
        if (t[0] != 0 && t[1] != 0 && t[2] != 0) kept.push_back(t);
    m.triangles = kept;
    return m;
}

}  // namespace

std::vector<std::string> stiff_case_names() {
    return std::vector<std::string>(std::begin(k_names), std::end(k_names));
}

StiffCase make_stiff_case(const std::string& name, int width, int height) {
    StiffCase c;
    c.name = name;
    c.has_inside = true;  // all but the open mesh enclose the origin (or the offset)
    if (name == "sliver 1e6") {
        c.mesh = sliver_mesh();
    } else if (name == "zero-area") {
        c.mesh = zero_area_mesh();
    } else if (name == "duplicate triangles") {
        c.mesh = duplicate_face_mesh();
    } else if (name == "valence 100") {
        c.mesh = high_valence_fan(100);
    } else if (name == "valence 200") {
        c.mesh = high_valence_fan(200);
    } else if (name == "folds") {
        c.mesh = folded();
    } else if (name == "crease (cube)") {
        add_box(c.mesh, Vec3(-1.0), Vec3(1.0));
    } else if (name == "boundary (open)") {
        c.mesh = holed_mesh();
        c.has_inside = false;
    } else if (name == "non-manifold edge") {
        c.mesh = fin_mesh();
    } else if (name == "offset 1e6, 1e-3") {
        c.inside = Vec3(1e6);
        c.mesh = offset_mesh(icosahedron(), c.inside, 1e-3);
    } else if (name == "scale 1e-6") {
        c.mesh = offset_mesh(icosahedron(), Vec3(0.0), 1e-6);
    } else if (name == "scale 1e6") {
        c.mesh = offset_mesh(icosahedron(), Vec3(0.0), 1e6);
    } else if (name == "grazing rays" || name == "camera on surface" ||
               name == "max_level forced") {
        c.mesh = icosahedron();
    } else {
        throw std::invalid_argument("no stiff case named '" + name + "'");
    }
    c.camera = frame_bounds(mesh_bounds(c.mesh), width, height, 40.0);
    if (name == "grazing rays") {
        // Side on, 3 degrees wide, centred on the top of the bounds: half the
        // rays pass above, the rest meet the top within a few degrees of it.
        c.camera.fov_degrees = 3.0;
        c.camera.look_at = Vec3(0.0, 0.0, mesh_bounds(c.mesh).hi.z);
        c.camera.look_from = c.camera.look_at + Vec3(-6.0, 0.0, 0.0);
        c.camera.up = Vec3(0.0, 0.0, 1.0);
    } else if (name == "camera on surface") {
        // The normal scheme interpolates: base vertex 0 is on every level.
        c.camera.look_from = c.mesh.positions[0];
        c.camera.look_at = Vec3(0.0);
        c.camera.fov_degrees = 60.0;
        c.camera_rays_must_hit = true;
    } else if (name == "max_level forced") {
        c.options.tolerance = 1e-9;
        c.options.max_level = k_max_level_cap;
    }
    c.options.view = c.camera.view();
    return c;
}

long double reference_t(const Ray& ray, const Hit& hit) {
    using L = long double;
    auto to_l = [](const Vec3& v) { return std::array<L, 3>{L(v.x), L(v.y), L(v.z)}; };
    const auto a = to_l(hit.triangle[0]), b = to_l(hit.triangle[1]), c = to_l(hit.triangle[2]);
    const auto o = to_l(ray.origin), d = to_l(ray.direction);
    const L e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    const L e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    const L n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                    e1[0] * e2[1] - e1[1] * e2[0]};
    const L num = n[0] * (a[0] - o[0]) + n[1] * (a[1] - o[1]) + n[2] * (a[2] - o[2]);
    const L den = n[0] * d[0] + n[1] * d[1] + n[2] * d[2];
    return num / den;
}

double t_rounding_bound(const Ray& ray, const Hit& hit) {
    // pbrt-v4 (Pharr, Jakob, Humphreys 2023, section 6.8.7): the bound on the
    // error of t = (e0 z0 + e1 z1 + e2 z2) / det from the translated, sheared
    // corners and the edge functions, for the shear the tracer used.
    const detail::WatertightRay r = detail::make_watertight_ray(ray.origin, ray.direction);
    double max_x = 0.0, max_y = 0.0, max_z = 0.0;
    double px[3], py[3];
    for (int k = 0; k < 3; ++k) {
        const Vec3 p = hit.triangle[k] - ray.origin;
        px[k] = p[r.kx] - r.sx * p[r.kz];
        py[k] = p[r.ky] - r.sy * p[r.kz];
        max_x = std::max(max_x, std::abs(px[k]));
        max_y = std::max(max_y, std::abs(py[k]));
        max_z = std::max(max_z, std::abs(r.sz * p[r.kz]));
    }
    const double e0 = px[1] * py[2] - py[1] * px[2];
    const double e1 = px[2] * py[0] - py[2] * px[0];
    const double e2 = px[0] * py[1] - py[0] * px[1];
    const double det = e0 + e1 + e2;
    const double delta_z = gamma_bound(3) * max_z;
    const double delta_x = gamma_bound(5) * (max_x + max_z);
    const double delta_y = gamma_bound(5) * (max_y + max_z);
    const double delta_e = 2.0 * (gamma_bound(2) * max_x * max_y + delta_y * max_x + delta_x * max_y);
    const double max_e = std::max({std::abs(e0), std::abs(e1), std::abs(e2)});
    return 3.0 * (gamma_bound(3) * max_e * max_z + delta_e * max_z + delta_z * max_e) /
           std::abs(det);
}

StabilityRow run_stiff_case(const StiffCase& c, int inside_rays) {
    StabilityRow row;
    row.name = c.name;
#ifdef __GLIBC__
    // Hand the previous cases' freed memory back first, so the RSS this case
    // starts from is what is live.
    malloc_trim(0);
#endif
    const bool peak_reset = reset_peak_rss();
    const std::size_t rss_before = current_rss_bytes();
    const auto start = std::chrono::steady_clock::now();
    const AdaptiveSurface surface(c.mesh, c.options);

    std::uint64_t must_hit = 0, missed = 0;
    auto trace = [&](const Ray& ray, bool must) {
        ++row.rays;
        Hit hit;
        const bool found = surface.intersect(ray, hit);
        must_hit += must;
        if (!found) {
            missed += must;
            return;
        }
        ++row.hits;
        row.max_level = std::max(row.max_level, hit.level);
        const bool finite = std::isfinite(hit.t) && std::isfinite(hit.point.x) &&
                            std::isfinite(hit.point.y) && std::isfinite(hit.point.z) &&
                            std::isfinite(hit.normal.x) && std::isfinite(hit.normal.y) &&
                            std::isfinite(hit.normal.z);
        if (!finite) {
            ++row.non_finite;
            return;
        }
        const long double t_ref = reference_t(ray, hit);
        const double deviation = static_cast<double>(std::abs(hit.t - t_ref));
        row.max_deviation = std::max(row.max_deviation, deviation * glm::length(ray.direction));
        row.max_deviation_ratio =
            std::max(row.max_deviation_ratio, deviation / t_rounding_bound(ray, hit));
    };

    for (int y = 0; y < c.camera.height; ++y)
        for (int x = 0; x < c.camera.width; ++x) trace(c.camera.ray(x, y), c.camera_rays_must_hit);
    if (c.has_inside) {
        // Fibonacci sphere: evenly spread, fixed directions.
        const double golden = k_pi * (3.0 - std::sqrt(5.0));
        for (int k = 0; k < inside_rays; ++k) {
            const double z = 1.0 - (2.0 * k + 1.0) / inside_rays;
            const double r = std::sqrt(1.0 - z * z);
            Ray ray;
            ray.origin = c.inside;
            ray.direction = Vec3(r * std::cos(golden * k), r * std::sin(golden * k), z);
            trace(ray, true);
        }
    }
    row.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const std::size_t peak = peak_reset ? peak_rss_bytes() : 0;
    row.peak_mb = peak > rss_before ? static_cast<double>(peak - rss_before) / (1 << 20) : 0.0;
    const SurfaceStats stats = surface.stats();
    row.nodes_built = stats.nodes_built;
    row.visits_per_ray = static_cast<double>(stats.trace.nodes_visited) / std::max<std::uint64_t>(row.rays, 1);
    if (must_hit > 0) row.leaks = static_cast<long long>(missed);
    return row;
}

}  // namespace subdivtrace::tools
