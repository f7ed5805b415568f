// `subdivtrace render` and `subdivtrace stats`: the standalone renderer.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <glm/geometric.hpp>

#include "cli_args.h"
#include "commands.h"
#include "image_out.h"
#include "subdivtrace/mesh_io.h"
#include "subdivtrace/render.h"
#include "subdivtrace/tracer.h"
#include "subdivtrace/uniform.h"

namespace subdivtrace::cli {

namespace {

const char* k_render_help =
    "usage: subdivtrace render MESH -o OUT.png [options]\n"
    "       subdivtrace stats MESH [options]        (no image; JSON on stdout)\n"
    "\n"
    "  --width W, --height H      image size (640 x 480)\n"
    "  --look-from X,Y,Z          camera position (default: frames the whole mesh)\n"
    "  --look-at X,Y,Z            point the camera looks at (default: mesh centre)\n"
    "  --fov DEG                  horizontal field of view (40)\n"
    "  --scheme S                 normal | loop | butterfly (normal)\n"
    "  --tolerance T              refine while an edge exceeds T pixels (1)\n"
    "  --max-level L              deepest level any ray may reach (8)\n"
    "  --uniform K                render the uniform level-K mesh instead (baseline)\n"
    "  --threads N                render threads (all cores)\n"
    "  --cache-mb M               node cache budget in MB (512)\n"
    "  --shell K                  bounding shells: slab (box and normal slab) | aabb (slab)\n"
    "  --light X,Y,Z              point light (default: above right of the camera)\n"
    "  --no-shadows               no shadow rays\n"
    "  --stats-json FILE          write timings and work counters as JSON\n"
    "  --quiet                    no progress output\n"
    "  --weld EPS, --no-weld      how coincident vertices are welded (subdivtrace info --help)\n";

struct RenderArgs {
    std::string mesh;
    std::string output;
    std::string stats_json;
    int width = 640, height = 480;
    bool has_from = false, has_at = false;
    Vec3 look_from{0.0}, look_at{0.0};
    double fov = 40.0;
    SchemeKind scheme = SchemeKind::normal;
    double tolerance = 1.0;
    int max_level = 8;
    int uniform = -1;
    int threads = 0;
    std::size_t cache_mb = 512;
    ShellKind shell = ShellKind::aabb_slab;
    bool has_light = false;
    Vec3 light{0.0};
    bool shadows = true;
    bool quiet = false;
    WeldOptions weld;
};

double parse_number(const std::string& option, const std::string& text) {
    std::size_t used = 0;
    double v = 0.0;
    try {
        v = std::stod(text, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used != text.size() || !std::isfinite(v))
        throw UsageError{option + " expects a number, got '" + text + "'"};
    return v;
}

int parse_int(const std::string& option, const std::string& text, int lo, int hi) {
    const double v = parse_number(option, text);
    if (v != std::floor(v) || v < lo || v > hi)
        throw UsageError{option + " expects an integer in " + std::to_string(lo) + ".." +
                         std::to_string(hi) + ", got '" + text + "'"};
    return static_cast<int>(v);
}

Vec3 parse_vec3(const std::string& option, const std::string& text) {
    std::stringstream in(text);
    std::string part;
    double v[3];
    int n = 0;
    while (std::getline(in, part, ',')) {
        if (n == 3) throw UsageError{option + " expects X,Y,Z, got '" + text + "'"};
        v[n++] = parse_number(option, part);
    }
    if (n != 3) throw UsageError{option + " expects X,Y,Z, got '" + text + "'"};
    return Vec3(v[0], v[1], v[2]);
}

RenderArgs parse_render_args(const Args& args, bool needs_output) {
    RenderArgs r;
    for (std::size_t k = 0; k < args.size(); ++k) {
        const std::string& a = args[k];
        auto value = [&]() -> const std::string& {
            if (k + 1 >= args.size()) throw UsageError{a + " needs a value"};
            return args[++k];
        };
        if (parse_weld_arg(args, k, r.weld)) continue;
        if (a == "-o" || a == "--output") r.output = value();
        else if (a == "--width") r.width = parse_int(a, value(), 1, 16384);
        else if (a == "--height") r.height = parse_int(a, value(), 1, 16384);
        else if (a == "--look-from") r.look_from = parse_vec3(a, value()), r.has_from = true;
        else if (a == "--look-at") r.look_at = parse_vec3(a, value()), r.has_at = true;
        else if (a == "--fov") {
            r.fov = parse_number(a, value());
            if (!(r.fov > 0.0 && r.fov < 179.0)) throw UsageError{"--fov must be in (0, 179)"};
        } else if (a == "--scheme") {
            const auto s = parse_scheme(value());
            if (!s) throw UsageError{"--scheme must be normal, loop or butterfly"};
            r.scheme = *s;
        } else if (a == "--tolerance") {
            r.tolerance = parse_number(a, value());
            if (!(r.tolerance > 0.0)) throw UsageError{"--tolerance must be positive"};
        } else if (a == "--max-level") r.max_level = parse_int(a, value(), 0, k_max_level_cap);
        else if (a == "--uniform") r.uniform = parse_int(a, value(), 0, k_max_uniform_levels);
        else if (a == "--threads") r.threads = parse_int(a, value(), 1, 1024);
        else if (a == "--cache-mb") r.cache_mb = static_cast<std::size_t>(parse_int(a, value(), 1, 1 << 20));
        else if (a == "--shell") {
            const std::string& k = value();
            if (k == "slab") r.shell = ShellKind::aabb_slab;
            else if (k == "aabb") r.shell = ShellKind::aabb;
            else throw UsageError{"--shell must be slab or aabb"};
        } else if (a == "--light") r.light = parse_vec3(a, value()), r.has_light = true;
        else if (a == "--no-shadows") r.shadows = false;
        else if (a == "--stats-json") r.stats_json = value();
        else if (a == "--quiet") r.quiet = true;
        else if (!a.empty() && a[0] == '-') throw UsageError{"unknown option " + a};
        else if (r.mesh.empty()) r.mesh = a;
        else throw UsageError{"more than one mesh given ('" + r.mesh + "', '" + a + "')"};
    }
    if (r.mesh.empty()) throw UsageError{"no mesh given"};
    if (needs_output && r.output.empty()) throw UsageError{"no output given (-o OUT.png)"};
    return r;
}

double seconds_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// Everything one render measured, for --stats-json and `stats`.
std::string stats_json(const RenderArgs& a, double build_s, const RenderStats& rs,
                       const SurfaceStats* ss, std::uint64_t uniform_triangles,
                       std::size_t scene_bytes, std::size_t baseline_rss) {
    std::ostringstream j;
    j.precision(10);
    j << "{\n";
    j << "  \"mesh\": \"" << a.mesh << "\",\n";
    j << "  \"mode\": \"" << (a.uniform >= 0 ? "uniform" : "adaptive") << "\",\n";
    j << "  \"scheme\": \"" << scheme_name(a.scheme) << "\",\n";
    j << "  \"width\": " << a.width << ", \"height\": " << a.height << ",\n";
    j << "  \"tolerance\": " << a.tolerance << ", \"max_level\": " << a.max_level
      << ", \"uniform_level\": " << a.uniform << ",\n";
    j << "  \"build_seconds\": " << build_s << ",\n";
    j << "  \"trace_seconds\": " << rs.trace_seconds << ",\n";
    j << "  \"total_seconds\": " << build_s + rs.trace_seconds << ",\n";
    // The process's resident set before the mesh is read (mostly shared
    // libraries: OpenImageIO pulls in ~260), and the peak above it.
    j << "  \"peak_rss_mb\": " << peak_rss_bytes() / 1048576.0 << ",\n";
    j << "  \"baseline_rss_mb\": " << baseline_rss / 1048576.0 << ",\n";
    j << "  \"peak_rss_above_baseline_mb\": "
      << (peak_rss_bytes() > baseline_rss ? peak_rss_bytes() - baseline_rss : 0) / 1048576.0
      << ",\n";
    j << "  \"rays\": " << rs.rays << ", \"shadow_rays\": " << rs.shadow_rays
      << ", \"hit_pixels\": " << rs.hit_pixels << ",\n";
    j << "  \"rays_per_second\": " << (rs.trace_seconds > 0 ? rs.rays / rs.trace_seconds : 0.0)
      << ",\n";
    j << "  \"scene_bytes\": " << scene_bytes << ",\n";
    if (ss) {
        const double rays = std::max<double>(1.0, static_cast<double>(ss->trace.rays));
        j << "  \"nodes_built\": " << ss->nodes_built << ",\n";
        j << "  \"nodes_visited_per_ray\": " << ss->trace.nodes_visited / rays << ",\n";
        j << "  \"leaves_tested_per_ray\": " << ss->trace.leaves_tested / rays << ",\n";
        j << "  \"cache_hits\": " << ss->trace.cache_hits << ", \"cache_misses\": "
          << ss->trace.cache_misses << ", \"cache_evictions\": " << ss->cache_evictions << ",\n";
        j << "  \"cache_peak_mb\": " << ss->cache_peak_bytes / 1048576.0 << ",\n";
        j << "  \"deepest_level\": " << ss->trace.deepest_level << ",\n";
        j << "  \"leaf_level_histogram\": [";
        for (std::size_t k = 0; k < ss->leaf_level_histogram.size(); ++k)
            j << (k ? ", " : "") << ss->leaf_level_histogram[k];
        j << "],\n";
    }
    j << "  \"uniform_triangles_at_deepest_level\": " << uniform_triangles << "\n";
    j << "}\n";
    return j.str();
}

int run_render_or_stats(const Args& args, bool write_png) {
    for (const std::string& a : args) {
        if (a == "--help" || a == "-h") {
            std::fputs(k_render_help, stdout);
            return 0;
        }
    }
    const RenderArgs a = parse_render_args(args, write_png);
    const std::size_t baseline_rss = current_rss_bytes();
    std::vector<std::string> warnings;
    const auto build_start = std::chrono::steady_clock::now();
    Mesh mesh = read_mesh(a.mesh, &warnings, a.weld);
    for (const std::string& w : warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());

    RenderOptions ro;
    ro.threads = a.threads;
    ro.shadows = a.shadows;
    ro.has_light = a.has_light;
    ro.light = a.light;
    ro.progress = !a.quiet;
    RenderStats rs;
    Image image;
    double build_seconds = 0.0;
    std::string json;

    auto make_camera = [&](const Bounds3& bounds) {
        Camera cam = frame_bounds(bounds, a.width, a.height, a.fov);
        if (a.has_at) cam.look_at = a.look_at;
        if (a.has_from) cam.look_from = a.look_from;
        if (glm::length(cam.look_at - cam.look_from) == 0.0)
            throw UsageError{"--look-from and --look-at are the same point"};
        return cam;
    };

    if (a.uniform >= 0) {
        const UniformScene scene(subdivide_or_explain(mesh, a.mesh, a.scheme, a.uniform));
        build_seconds = seconds_since(build_start);
        const Camera cam = make_camera(scene.bounds());
        image = render([&](const Ray& r, Hit& h) { return scene.intersect(r, h); }, cam, ro,
                       scene.bounds(), rs);
        json = stats_json(a, build_seconds, rs, nullptr, scene.triangle_count(), scene.memory_bytes(),
                          baseline_rss);
    } else {
        // The camera is framed on the base mesh's bounds, then handed to the surface.
        const Camera cam = make_camera(mesh_bounds(mesh));
        SurfaceOptions so;
        so.scheme = a.scheme;
        so.tolerance = a.tolerance;
        so.max_level = a.max_level;
        so.cache_mb = a.cache_mb;
        so.shell_kind = a.shell;
        so.view.camera = cam.look_from;
        so.view.pixel_angle = cam.pixel_angle();
        const AdaptiveSurface surface(std::move(mesh), so);
        build_seconds = seconds_since(build_start);
        image = render([&](const Ray& r, Hit& h) { return surface.intersect(r, h); }, cam, ro,
                       surface.bounds(), rs);
        const SurfaceStats ss = surface.stats();
        json = stats_json(a, build_seconds, rs, &ss,
                          surface.uniform_triangle_count(ss.trace.deepest_level),
                          ss.cache_peak_bytes, baseline_rss);
    }
    if (write_png) {
        write_image(a.output, image);
        if (!a.quiet)
            std::fprintf(stderr, "wrote %s (%dx%d, build %.2f s, trace %.2f s)\n",
                         a.output.c_str(), a.width, a.height, build_seconds, rs.trace_seconds);
    } else {
        std::fputs(json.c_str(), stdout);
    }
    if (!a.stats_json.empty()) {
        std::ofstream out(a.stats_json);
        out << json;
        if (!out) throw std::runtime_error(a.stats_json + ": could not write the statistics");
    }
    return 0;
}

}  // namespace

int run_render(const Args& args) { return run_render_or_stats(args, true); }
int run_stats(const Args& args) { return run_render_or_stats(args, false); }

}  // namespace subdivtrace::cli
