// embree_render: the views of `subdivtrace render` through Embree 3, with the
// same camera, light, shading, shadows and --stats-json fields (the tools'
// render loop), so compare/ can put Embree beside uniform and adaptive.
//
//   embree_render MESH -o OUT.png --uniform K [view options]
//       our uniform level-K mesh (scheme --scheme) in Embree's triangle BVH
//   embree_render MESH -o OUT.png --subdiv-pixels P [view options]
//       the base mesh as Embree's Catmull-Clark subdivision geometry, each
//       base edge tessellated into segments of at most P pixels
#include <chrono>
#include <cstdio>
#include <exception>
#include <sstream>
#include <string>
#include <vector>

#include "embree_scene.h"
#include "render/image_out.h"
#include "render/render_loop.h"
#include "render/rss.h"
#include "render/view_args.h"
#include "subdivtrace/mesh_io.h"
#include "subdivtrace/uniform.h"

using namespace subdivtrace;
using namespace subdivtrace::tools;

namespace {

const char* k_usage =
    "usage: embree_render MESH -o OUT.png (--uniform K | --subdiv-pixels P) [options]\n"
    "\n"
    "  --uniform K                our uniform level-K mesh in Embree's triangle BVH\n"
    "  --scheme S                 scheme of --uniform: normal | loop | butterfly (normal)\n"
    "  --subdiv-pixels P          Embree's Catmull-Clark subdivision of the base mesh,\n"
    "                             base edges cut into segments of at most P pixels\n";

struct Args {
    std::string mesh;
    ViewArgs view;
    int uniform = -1;
    double subdiv_pixels = 0.0;
    SchemeKind scheme = SchemeKind::normal;
};

Args parse_args(const std::vector<std::string>& args) {
    Args r;
    for (std::size_t k = 0; k < args.size(); ++k) {
        if (parse_view_option(args, k, r.view)) continue;
        const std::string& a = args[k];
        if (a == "--uniform") r.uniform = parse_int(a, option_value(args, k), 0, k_max_uniform_levels);
        else if (a == "--subdiv-pixels") {
            r.subdiv_pixels = parse_number(a, option_value(args, k));
            if (!(r.subdiv_pixels > 0.0)) throw UsageError{"--subdiv-pixels must be positive"};
        } else if (a == "--scheme") r.scheme = parse_scheme_option(option_value(args, k));
        else take_mesh_argument(a, r.mesh);
    }
    if (r.mesh.empty()) throw UsageError{"no mesh given"};
    if (r.view.output.empty()) throw UsageError{"no output given (-o OUT.png)"};
    if ((r.uniform >= 0) == (r.subdiv_pixels > 0.0))
        throw UsageError{"give exactly one of --uniform K and --subdiv-pixels P"};
    return r;
}

double seconds_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

int run(const Args& a) {
    const std::size_t baseline_rss = current_rss_bytes();
    const auto build_start = std::chrono::steady_clock::now();
    std::vector<std::string> warnings;
    const Mesh mesh = read_mesh(a.mesh, &warnings);
    for (const std::string& w : warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());

    // The camera frames the base mesh, as `subdivtrace render` does for adaptive renders.
    const Camera camera = make_camera(a.view, mesh_bounds(mesh));
    compare::EmbreeScene scene(a.view.threads);
    compare::EdgeLevels levels;
    std::size_t triangles = 0;
    if (a.uniform >= 0) {
        const SubdividedMesh sub = subdivide_uniform(mesh, a.scheme, a.uniform);
        triangles = sub.triangles.size();
        scene.add_uniform(sub);
    } else {
        levels = compare::edge_levels(mesh, camera, a.subdiv_pixels);
        scene.add_subdivision(mesh, levels);
    }
    scene.commit();
    const double build_seconds = seconds_since(build_start);

    RenderStats rs;
    const Image image = render([&](const Ray& r, Hit& h) { return scene.intersect(r, h); }, camera,
                               render_options(a.view), scene.bounds(), rs);
    // The statistics (peak RSS) are taken before the image is written: writing
    // loads the image module and OpenImageIO's libraries, which would count as
    // the scene's memory. `subdivtrace render` measures the same way.
    std::ostringstream j;
    j.precision(10);
    j << "{\n";
    j << "  \"mesh\": \"" << a.mesh << "\",\n";
    j << "  \"mode\": \"" << (a.uniform >= 0 ? "embree_uniform" : "embree_subdiv") << "\",\n";
    j << "  \"scheme\": \"" << (a.uniform >= 0 ? scheme_name(a.scheme) : "catmull-clark")
      << "\",\n";
    j << "  \"width\": " << a.view.width << ", \"height\": " << a.view.height << ",\n";
    j << "  \"uniform_level\": " << a.uniform << ", \"subdiv_pixels\": " << a.subdiv_pixels
      << ",\n";
    j << run_stats_json_fields(build_seconds, rs, scene.bytes(), baseline_rss);
    j << "  \"embree_peak_bytes\": " << scene.peak_bytes() << ",\n";
    j << "  \"mean_edge_level\": " << levels.mean << ", \"max_edge_level\": " << levels.max
      << ",\n";
    j << "  \"uniform_triangles_at_deepest_level\": " << triangles << "\n";
    j << "}\n";
    write_image(a.view.output, image);
    if (!a.view.stats_json.empty()) write_text_file(a.view.stats_json, j.str());
    if (!a.view.quiet)
        std::fprintf(stderr, "wrote %s (%dx%d, build %.2f s, trace %.2f s)\n",
                     a.view.output.c_str(), a.view.width, a.view.height, build_seconds,
                     rs.trace_seconds);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    const std::vector<std::string> args(argv + 1, argv + argc);
    for (const std::string& a : args) {
        if (a == "--help" || a == "-h") {
            std::fputs(k_usage, stdout);
            std::fputs(k_view_options_help, stdout);
            return 0;
        }
    }
    try {
        return run(parse_args(args));
    } catch (const UsageError& e) {
        std::fprintf(stderr, "embree_render: %s\n\n%s%s", e.message.c_str(), k_usage,
                     k_view_options_help);
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "embree_render: %s\n", e.what());
        return 1;
    }
}
