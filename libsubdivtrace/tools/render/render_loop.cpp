#include "render/render_loop.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <mutex>
#include <thread>
#include <vector>

#include <glm/geometric.hpp>

#include "subdivtrace/spawn.h"

namespace subdivtrace::tools {

namespace {

/// The side of the square blocks of pixels threads take (POV-Ray's default
/// render block size).
constexpr int k_block_pixels = 32;

/// The indices (row-major) of a grid of `across` x `down` blocks in Z-order
/// (Morton order over the smallest power-of-two square that holds them).
std::vector<int> z_order(int across, int down) {
    int side = 1;
    while (side < across || side < down) side *= 2;
    std::vector<int> order;
    order.reserve(static_cast<std::size_t>(across) * down);
    for (int m = 0; m < side * side; ++m) {
        // Even bits of m are x's, odd bits y's.
        int x = 0, y = 0;
        for (int bit = 0; (1 << bit) < side; ++bit) {
            x |= ((m >> (2 * bit)) & 1) << bit;
            y |= ((m >> (2 * bit + 1)) & 1) << bit;
        }
        if (x < across && y < down) order.push_back(y * across + x);
    }
    return order;
}

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

    // Threads take square blocks of pixels, as POV-Ray does (its default
    // block size), in Z-order: a block's rays come back to the same tiles,
    // and to the same parents their child tiles start from, which a row of
    // pixels crossing the whole image would have left; and the blocks that
    // follow one another are neighbours in both directions, so the tiles
    // along a block's edges are soon asked for again (docs/benchmarks.md,
    // "Blocks of pixels"). Pixels do not depend on the order.
    const int blocks_across = (camera.width + k_block_pixels - 1) / k_block_pixels;
    const int blocks_down = (camera.height + k_block_pixels - 1) / k_block_pixels;
    const int block_count = blocks_across * blocks_down;
    const std::vector<int> block_order = z_order(blocks_across, blocks_down);
    std::atomic<int> next_block{0};
    std::atomic<int> blocks_done{0};
    // Wakes the progress report when the last block is done, so the render's
    // time is not rounded up to its next report.
    std::mutex done_mutex;
    std::condition_variable all_done;
    std::vector<RenderStats> per_thread(threads);
    const auto start = std::chrono::steady_clock::now();
    auto worker = [&](int t) {
        RenderStats& local = per_thread[t];
        for (int n = next_block++; n < block_count; n = next_block++) {
            const int b = block_order[n];
            const int x0 = (b % blocks_across) * k_block_pixels, y0 = (b / blocks_across) * k_block_pixels;
            const int x1 = std::min(camera.width, x0 + k_block_pixels);
            const int y1 = std::min(camera.height, y0 + k_block_pixels);
            for (int y = y0; y < y1; ++y) {
                for (int x = x0; x < x1; ++x) {
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
            }
            if (++blocks_done == block_count) {
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
        while (blocks_done.load() < block_count) {
            {
                std::unique_lock<std::mutex> lock(done_mutex);
                all_done.wait_for(lock, std::chrono::milliseconds(250),
                                  [&] { return blocks_done.load() >= block_count; });
            }
            const double elapsed =
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            const int percent = 100 * blocks_done.load() / block_count;
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
