#include "subdivtrace/render.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <thread>

#include <glm/geometric.hpp>

#include "bvh.h"
#include "ray_triangle.h"

namespace subdivtrace {

namespace {

constexpr double k_pi = 3.14159265358979323846;
const Vec3 k_background(0.08, 0.09, 0.11);
const Vec3 k_albedo(0.85, 0.78, 0.65);

struct CameraFrame {
    Vec3 forward, right, up;
    double half_width;  ///< tan(fov/2)
};

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

Vec3 default_light(const Camera& c, const Bounds3& b) {
    const CameraFrame f = frame_of(c);
    const double size = glm::length(b.hi - b.lo);
    return c.look_from + (f.up * 0.8 + f.right * 0.6) * std::max(size, 1e-12);
}

/// Headlight Lambert plus a point light with one shadow ray.
Vec3 shade(const IntersectFn& intersect, const Ray& ray, const Hit& hit, const Vec3& light,
           bool shadows, RenderStats& local) {
    const Vec3 view = glm::normalize(ray.direction);
    Vec3 n = hit.normal;
    if (glm::dot(n, view) > 0.0) n = -n;  // shade the side the camera sees
    Vec3 g = hit.geometric_normal;
    if (glm::dot(g, view) > 0.0) g = -g;
    const double headlight = std::abs(glm::dot(n, view));
    const Vec3 to_light = light - hit.point;
    const double light_distance = glm::length(to_light);
    const Vec3 l = to_light / light_distance;
    double direct = std::max(0.0, glm::dot(n, l));
    if (direct > 0.0 && shadows && glm::dot(g, l) > 0.0) {
        const Ray s = spawn_shadow_ray(ray, hit, light);
        Hit blocker;
        ++local.shadow_rays;
        ++local.rays;
        if (intersect(s, blocker)) direct = 0.0;
    } else if (glm::dot(g, l) <= 0.0) {
        direct = 0.0;
    }
    return k_albedo * (0.08 + 0.45 * headlight + 0.55 * direct);
}

}  // namespace

Ray spawn_shadow_ray(const Ray& ray, const Hit& hit, const Vec3& light) {
    Vec3 g = hit.geometric_normal;
    if (glm::dot(g, light - hit.point) < 0.0) g = -g;
    Ray s;
    s.origin = hit.point + g * (hit.error_bound + 1e-12 * glm::length(hit.point));
    s.direction = glm::normalize(light - s.origin);
    s.t_min = 0.0;
    s.t_max = glm::length(light - s.origin);
    s.origin_distance = hit.t * glm::length(ray.direction) + std::max(0.0, ray.origin_distance);
    return s;
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

Image render(const IntersectFn& intersect, const Camera& camera, const RenderOptions& options,
             const Bounds3& scene_bounds, RenderStats& stats) {
    Image image;
    image.width = camera.width;
    image.height = camera.height;
    image.rgb.assign(std::size_t(camera.width) * camera.height * 3, 0.0f);
    const Vec3 light = options.has_light ? options.light : default_light(camera, scene_bounds);
    int threads = options.threads > 0 ? options.threads
                                      : static_cast<int>(std::thread::hardware_concurrency());
    threads = std::max(1, threads);

    std::atomic<int> next_row{0};
    std::atomic<int> rows_done{0};
    std::vector<RenderStats> per_thread(threads);
    const auto start = std::chrono::steady_clock::now();
    auto worker = [&](int t) {
        RenderStats& local = per_thread[t];
        for (int y = next_row++; y < camera.height; y = next_row++) {
            for (int x = 0; x < camera.width; ++x) {
                const Ray ray = camera.ray(x, y);
                Hit hit;
                ++local.rays;
                Vec3 colour = k_background;
                if (intersect(ray, hit)) {
                    ++local.hit_pixels;
                    colour = shade(intersect, ray, hit, light, options.shadows, local);
                }
                float* px = &image.rgb[(std::size_t(y) * camera.width + x) * 3];
                px[0] = static_cast<float>(colour.x);
                px[1] = static_cast<float>(colour.y);
                px[2] = static_cast<float>(colour.z);
            }
            ++rows_done;
        }
    };
    std::vector<std::thread> pool;
    for (int t = 1; t < threads; ++t) pool.emplace_back(worker, t);
    if (options.progress) {
        // The calling thread reports progress while the others work, then joins in.
        pool.emplace_back(worker, 0);
        int last = -1;
        while (rows_done.load() < camera.height) {
            std::this_thread::sleep_for(std::chrono::milliseconds(250));
            const double elapsed =
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            const int percent = 100 * rows_done.load() / camera.height;
            if (elapsed > 1.0 && percent != last) {
                std::fprintf(stderr, "\rrendering: %3d%% (%.1f s)", percent, elapsed);
                last = percent;
            }
        }
        if (last >= 0) std::fprintf(stderr, "\rrendering: 100%%            \n");
    } else {
        worker(0);
    }
    for (std::thread& th : pool) th.join();
    stats.trace_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    for (const RenderStats& s : per_thread) {
        stats.rays += s.rays;
        stats.shadow_rays += s.shadow_rays;
        stats.hit_pixels += s.hit_pixels;
    }
    return image;
}

struct UniformScene::Impl {
    SubdividedMesh mesh;
    detail::Bvh bvh;
    Bounds3 bounds;
};

UniformScene::UniformScene(SubdividedMesh mesh) : impl_(std::make_unique<Impl>()) {
    impl_->mesh = std::move(mesh);
    const SubdividedMesh& m = impl_->mesh;
    std::vector<Vec3> lo(m.triangles.size()), hi(m.triangles.size());
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
        const Triangle& tri = m.triangles[t];
        lo[t] = glm::min(glm::min(m.positions[tri[0]], m.positions[tri[1]]), m.positions[tri[2]]);
        hi[t] = glm::max(glm::max(m.positions[tri[0]], m.positions[tri[1]]), m.positions[tri[2]]);
        impl_->bounds.lo = t == 0 ? lo[t] : glm::min(impl_->bounds.lo, lo[t]);
        impl_->bounds.hi = t == 0 ? hi[t] : glm::max(impl_->bounds.hi, hi[t]);
    }
    impl_->bvh.build(lo, hi, 4);
}

UniformScene::~UniformScene() = default;

bool UniformScene::intersect(const Ray& ray, Hit& hit) const {
    const SubdividedMesh& m = impl_->mesh;
    const RayBoxQuery q = make_ray_box_query(ray.origin, ray.direction, ray.t_min, ray.t_max);
    const detail::WatertightRay wr = detail::make_watertight_ray(ray.origin, ray.direction);
    double t_max = ray.t_max;
    bool found = false;
    impl_->bvh.traverse(q, t_max, [&](std::uint32_t t) {
        const Triangle& tri = m.triangles[t];
        detail::TriangleHit th;
        if (!detail::intersect_watertight(wr, m.positions[tri[0]], m.positions[tri[1]],
                                          m.positions[tri[2]], ray.t_min, t_max, th))
            return;
        t_max = th.t;
        found = true;
        hit.t = th.t;
        hit.point = th.b0 * m.positions[tri[0]] + th.b1 * m.positions[tri[1]] +
                    th.b2 * m.positions[tri[2]];
        hit.geometric_normal = finish_normal(glm::cross(m.positions[tri[1]] - m.positions[tri[0]],
                                                        m.positions[tri[2]] - m.positions[tri[0]]));
        hit.normal = finish_normal(th.b0 * m.vertex_normals[tri[0]] +
                                   th.b1 * m.vertex_normals[tri[1]] +
                                   th.b2 * m.vertex_normals[tri[2]]);
        if (hit.normal == Vec3(0.0)) hit.normal = hit.geometric_normal;
        if (!m.corner_uvs.empty()) {
            hit.uv = th.b0 * m.corner_uvs[3 * t] + th.b1 * m.corner_uvs[3 * t + 1] +
                     th.b2 * m.corner_uvs[3 * t + 2];
        }
        hit.level = m.levels;
        hit.base_face = m.base_face[t];
        const Vec3 ap = glm::abs(hit.point);
        hit.error_bound = gamma_bound(7) * (ap.x + ap.y + ap.z);
    });
    return found;
}

Bounds3 UniformScene::bounds() const { return impl_->bounds; }

std::size_t UniformScene::memory_bytes() const {
    const SubdividedMesh& m = impl_->mesh;
    return m.positions.capacity() * sizeof(Vec3) + m.triangles.capacity() * sizeof(Triangle) +
           m.vertex_normals.capacity() * sizeof(Vec3) + m.corner_uvs.capacity() * sizeof(Vec2) +
           m.base_face.capacity() * sizeof(std::uint32_t) + impl_->bvh.memory_bytes();
}

std::size_t UniformScene::triangle_count() const { return impl_->mesh.triangles.size(); }

namespace {

std::size_t proc_status_bytes(const char* field) {
    std::ifstream status("/proc/self/status");
    std::string line;
    const std::string prefix = std::string(field) + ":";
    while (std::getline(status, line)) {
        if (line.rfind(prefix, 0) == 0) return std::stoull(line.substr(prefix.size())) * 1024;
    }
    return 0;
}

}  // namespace

std::size_t peak_rss_bytes() { return proc_status_bytes("VmHWM"); }
std::size_t current_rss_bytes() { return proc_status_bytes("VmRSS"); }

}  // namespace subdivtrace
