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
#include "render/camera.h"
#include "render/image_out.h"
#include "render/render_loop.h"
#include "render/rss.h"
#include "render/uniform_scene.h"
#include "render/view_args.h"
#include "subdivtrace/mesh_report.h"
#include "subdivtrace/mesh_io.h"
#include "subdivtrace/tracer.h"
#include "subdivtrace/uniform.h"

namespace subdivtrace::cli {

using namespace subdivtrace::tools;

namespace {

const char* k_render_usage =
    "usage: subdivtrace render MESH -o OUT.png [options]\n"
    "       subdivtrace stats MESH [options]        (no image; JSON on stdout)\n"
    "\n";
const char* k_render_options_help =
    "  --scheme S                 normal | loop | butterfly (normal)\n"
    "  --refine R                 error | size (error): refine while the surface may lie\n"
    "                             farther than T pixels from what is drawn, or (size, the\n"
    "                             paper's rule) while an edge is longer than T pixels\n"
    "  --tolerance T              pixels, for the rule above (1)\n"
    "  --max-level L              deepest level any ray may reach (8)\n"
    "  --uniform K                render the uniform level-K mesh instead (baseline)\n"
    "  --cache-mb M               most the tile cache keeps, MB (32); it keeps\n"
    "                             less where the picture needs less\n"
    "  --cache-fixed              keep all of --cache-mb from the start (to measure\n"
    "                             what every node built costs to keep: nothing evicted)\n"
    "  --shell K                  bounding shells: slab (box and normal slab) | aabb (slab)\n"
    "  --color-by level|face|error false colours: the level of the leaf each pixel hit,\n"
    "                             its base triangle, or its certified error bound in\n"
    "                             pixels; a legend goes to stdout\n"
    "  --weld EPS, --no-weld      how coincident vertices are welded (subdivtrace info --help)\n";

struct RenderArgs {
    std::string mesh;
    ViewArgs view;
    SchemeKind scheme = SchemeKind::normal;
    RefineRule refine = SurfaceOptions{}.refine;
    double tolerance = 1.0;
    int max_level = 8;
    int uniform = -1;
    std::size_t cache_mb = SurfaceOptions{}.cache_mb;
    bool cache_fixed = false;
    ShellKind shell = ShellKind::aabb_slab;
    ColorBy color_by = ColorBy::shading;
    WeldOptions weld;
};

RenderArgs parse_render_args(const Args& args, bool needs_output) {
    RenderArgs r;
    for (std::size_t k = 0; k < args.size(); ++k) {
        if (parse_view_option(args, k, r.view)) continue;
        const std::string& a = args[k];
        auto value = [&]() -> const std::string& { return option_value(args, k); };
        if (parse_weld_arg(args, k, r.weld)) continue;
        if (a == "--scheme") r.scheme = parse_scheme_option(value());
        else if (a == "--refine") {
            if (!parse_refine_rule(value(), r.refine)) throw UsageError{"--refine must be error or size"};
        } else if (a == "--tolerance") {
            r.tolerance = parse_number(a, value());
            if (!(r.tolerance > 0.0)) throw UsageError{"--tolerance must be positive"};
        } else if (a == "--max-level") r.max_level = parse_int(a, value(), 0, k_max_level_cap);
        else if (a == "--uniform") r.uniform = parse_int(a, value(), 0, k_max_uniform_levels);
        else if (a == "--cache-fixed") r.cache_fixed = true;
        else if (a == "--cache-mb") r.cache_mb = static_cast<std::size_t>(parse_int(a, value(), 1, 1 << 20));
        else if (a == "--shell") {
            const std::string& kind = value();
            if (kind == "slab") r.shell = ShellKind::aabb_slab;
            else if (kind == "aabb") r.shell = ShellKind::aabb;
            else throw UsageError{"--shell must be slab or aabb"};
        } else if (a == "--color-by") {
            const auto c = parse_color_by(value());
            if (!c) throw UsageError{"--color-by must be level, face or error"};
            r.color_by = *c;
        } else take_mesh_argument(a, r.mesh);
    }
    if (r.mesh.empty()) throw UsageError{"no mesh given"};
    if (needs_output && r.view.output.empty()) throw UsageError{"no output given (-o OUT.png)"};
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
    j << "  \"width\": " << a.view.width << ", \"height\": " << a.view.height << ",\n";
    j << "  \"refine\": \"" << refine_rule_name(a.refine) << "\",\n";
    j << "  \"tolerance\": " << a.tolerance << ", \"max_level\": " << a.max_level
      << ", \"uniform_level\": " << a.uniform << ",\n";
    j << run_stats_json_fields(build_s, rs, scene_bytes, baseline_rss);
    if (ss) {
        const double rays = std::max<double>(1.0, static_cast<double>(ss->trace.rays));
        j << "  \"nodes_built\": " << ss->nodes_built << ",\n";
        // What a node costs to build, and (exact while nothing was evicted,
        // when every node built is in the cache: --cache-fixed) to keep.
        const double nodes = std::max<double>(1.0, static_cast<double>(ss->nodes_built));
        j << "  \"tiles_built\": " << ss->tiles_built << ", \"tile_build_seconds\": "
          << ss->tile_build_seconds << ", \"ns_per_node_built\": "
          << ss->tile_build_seconds * 1e9 / nodes << ",\n";
        j << "  \"cache_peak_bytes_per_node_built\": "
          << static_cast<double>(ss->cache_peak_bytes) / nodes << ",\n";
        j << "  \"nodes_visited_per_ray\": " << ss->trace.nodes_visited / rays << ",\n";
        j << "  \"leaves_tested_per_ray\": " << ss->trace.leaves_tested / rays << ",\n";
        j << "  \"cache_hits\": " << ss->trace.cache_hits << ", \"cache_misses\": "
          << ss->trace.cache_misses << ", \"cache_evictions\": " << ss->cache_evictions << ",\n";
        j << "  \"cache_peak_mb\": " << ss->cache_peak_bytes / 1048576.0 << ",\n";
        // The scene cache's working limit (it grows while dropped tiles are
        // asked for again: the remisses) under its budget.
        j << "  \"cache_limit_mb\": " << ss->shared_cache.limit_bytes / 1048576.0
          << ", \"cache_budget_mb\": " << ss->shared_cache.budget_bytes / 1048576.0
          << ", \"cache_remisses\": " << ss->shared_cache.remisses << ",\n";
        // What the surface holds outside the cache budget, part by part.
        const SurfaceMemory& m = ss->memory;
        const double faces = std::max<double>(1.0, static_cast<double>(ss->base_triangles));
        j << "  \"memory_bytes\": {\"mesh\": " << m.mesh << ", \"topology\": " << m.topology
          << ", \"bvh\": " << m.bvh << ", \"roots\": " << m.roots << ", \"fronts\": " << m.fronts
          << ", \"front_threads\": " << m.front_threads << ", \"levels_below\": " << m.levels_below
          << ", \"cache\": " << ss->cache_bytes
          << ", \"cache_peak\": " << ss->cache_peak_bytes << "},\n";
        j << "  \"base_triangles\": " << ss->base_triangles << ",\n";
        j << "  \"base_bytes_per_triangle\": " << m.base() / faces << ",\n";
        j << "  \"deepest_level\": " << ss->trace.deepest_level << ",\n";
        // The certified bound on each hit's distance to the surface, in pixels.
        const double hits = std::max<double>(1.0, static_cast<double>(ss->trace.hits));
        j << "  \"error_bound_px_max\": " << ss->trace.error_bound_px_max
          << ", \"error_bound_px_mean\": " << ss->trace.error_bound_px_sum / hits
          << ", \"hits_at_max_level\": " << ss->trace.hits_at_max_level << ",\n";
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
            std::fputs(k_render_usage, stdout);
            std::fputs(k_view_options_help, stdout);
            std::fputs(k_render_options_help, stdout);
            return 0;
        }
    }
    const RenderArgs a = parse_render_args(args, write_png);
    if (write_png) check_image_module(a.view.output);
    const std::size_t baseline_rss = current_rss_bytes();
    std::vector<std::string> warnings;
    const auto build_start = std::chrono::steady_clock::now();
    Mesh mesh = read_mesh(a.mesh, &warnings, a.weld);
    // A uniform render's subdivide_or_explain says it itself.
    if (a.uniform < 0) warnings.push_back(given_normals_warning(mesh, a.scheme, a.mesh));
    for (const std::string& w : warnings)
        if (!w.empty()) std::fprintf(stderr, "warning: %s\n", w.c_str());

    RenderOptions ro = render_options(a.view);
    ro.color_by = a.color_by;
    RenderStats rs;
    Image image;
    double build_seconds = 0.0;
    std::string json;

    if (a.uniform >= 0) {
        const UniformScene scene(subdivide_or_explain(mesh, a.mesh, a.scheme, a.uniform));
        build_seconds = seconds_since(build_start);
        const Camera cam = make_camera(a.view, scene.bounds());
        image = render([&](const Ray& r, Hit& h) { return scene.intersect(r, h); }, cam, ro,
                       scene.bounds(), rs);
        json = stats_json(a, build_seconds, rs, nullptr, scene.triangle_count(), scene.memory_bytes(),
                          baseline_rss);
    } else {
        // The camera is framed on the base mesh's bounds, then handed to the surface.
        const Camera cam = make_camera(a.view, mesh_bounds(mesh));
        SurfaceOptions so;
        so.scheme = a.scheme;
        so.refine = a.refine;
        so.tolerance = a.tolerance;
        so.max_level = a.max_level;
        so.cache_mb = a.cache_mb;
        if (a.cache_fixed) so.cache = std::make_shared<TileCache>(a.cache_mb << 20, TileCache::Sizing::whole_budget);
        so.shell_kind = a.shell;
        so.view = cam.view();
        const AdaptiveSurface surface(std::move(mesh), so);
        build_seconds = seconds_since(build_start);
        image = render([&](const Ray& r, Hit& h) { return surface.intersect(r, h); }, cam, ro,
                       surface.bounds(), rs);
        const SurfaceStats ss = surface.stats();
        json = stats_json(a, build_seconds, rs, &ss,
                          surface.uniform_triangle_count(ss.trace.deepest_level),
                          ss.memory.base() + ss.cache_peak_bytes, baseline_rss);
    }
    if (write_png) {
        write_image(a.view.output, image);
        if (a.color_by != ColorBy::shading) std::fputs(legend(a.color_by, rs.tally).c_str(), stdout);
        if (!a.view.quiet)
            std::fprintf(stderr, "wrote %s (%dx%d, build %.2f s, trace %.2f s)\n",
                         a.view.output.c_str(), a.view.width, a.view.height, build_seconds,
                         rs.trace_seconds);
    } else {
        std::fputs(json.c_str(), stdout);
    }
    if (!a.view.stats_json.empty()) write_text_file(a.view.stats_json, json);
    return 0;
}

}  // namespace

int run_render(const Args& args) { return run_render_or_stats(args, true); }
int run_stats(const Args& args) { return run_render_or_stats(args, false); }

}  // namespace subdivtrace::cli
