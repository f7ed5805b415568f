#include "render/render_loop.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <mutex>
#include <thread>

#include <glm/geometric.hpp>

#include "subdivtrace/spawn.h"

namespace subdivtrace::tools {

namespace {

const Vec3 k_background(0.08, 0.09, 0.11);
const Vec3 k_albedo(0.85, 0.78, 0.65);

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

/// The false colour of a hit (ColorBy::level or face), lit by the headlight only.
Vec3 false_colour(ColorBy mode, const Ray& ray, const Hit& hit) {
    const double headlight = std::abs(glm::dot(hit.normal, glm::normalize(ray.direction)));
    const Vec3 base = mode == ColorBy::level   ? level_colour(hit.level)
                      : mode == ColorBy::error ? level_colour(error_bin(hit.surface_error_px))
                                               : face_colour(hit.base_face);
    return base * (0.3 + 0.7 * headlight);
}

void count_pixel(ColorBy mode, const Hit& hit, PixelTally& tally) {
    const std::size_t level = static_cast<std::size_t>(std::max(hit.level, 0));
    if (tally.level_pixels.size() <= level) tally.level_pixels.resize(level + 1, 0);
    ++tally.level_pixels[level];
    if (mode == ColorBy::face) ++tally.face_pixels[hit.base_face];
    if (mode == ColorBy::error) {
        const std::size_t bin = static_cast<std::size_t>(error_bin(hit.surface_error_px));
        if (tally.error_pixels.size() <= bin) tally.error_pixels.resize(bin + 1, 0);
        ++tally.error_pixels[bin];
    }
}

}  // namespace

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
    // Wakes the progress report when the last row is done, so the render's
    // time is not rounded up to its next report.
    std::mutex done_mutex;
    std::condition_variable all_done;
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
                    count_pixel(options.color_by, hit, local.tally);
                    colour = options.color_by == ColorBy::shading
                                 ? shade(intersect, ray, hit, light, options.shadows, local)
                                 : false_colour(options.color_by, ray, hit);
                }
                float* px = &image.rgb[(std::size_t(y) * camera.width + x) * 3];
                px[0] = static_cast<float>(colour.x);
                px[1] = static_cast<float>(colour.y);
                px[2] = static_cast<float>(colour.z);
            }
            if (++rows_done == camera.height) {
                const std::lock_guard<std::mutex> lock(done_mutex);
                all_done.notify_all();
            }
        }
    };
    std::vector<std::thread> pool;
    for (int t = 1; t < threads; ++t) pool.emplace_back(worker, t);
    if (options.progress) {
        // The calling thread reports progress while the others work, then joins in.
        pool.emplace_back(worker, 0);
        int last = -1;
        while (rows_done.load() < camera.height) {
            {
                std::unique_lock<std::mutex> lock(done_mutex);
                all_done.wait_for(lock, std::chrono::milliseconds(250),
                                  [&] { return rows_done.load() >= camera.height; });
            }
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
        stats.tally.add(s.tally);
    }
    return image;
}

}  // namespace subdivtrace::tools
