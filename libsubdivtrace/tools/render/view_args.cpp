#include "render/view_args.h"

#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <glm/geometric.hpp>

#include "render/rss.h"

namespace subdivtrace::tools {

const char* const k_view_options_help =
    "  -o OUT.png                 output image\n"
    "  --width W, --height H      image size (640 x 480)\n"
    "  --look-from X,Y,Z          camera position (default: frames the whole mesh)\n"
    "  --look-at X,Y,Z            point the camera looks at (default: mesh centre)\n"
    "  --fov DEG                  horizontal field of view (40)\n"
    "  --threads N                render threads (all cores)\n"
    "  --light X,Y,Z              point light (default: above right of the camera)\n"
    "  --no-shadows               no shadow rays\n"
    "  --stats-json FILE          write timings and work counters as JSON\n"
    "  --quiet                    no progress output\n";

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

const std::string& option_value(const std::vector<std::string>& args, std::size_t& k) {
    if (k + 1 >= args.size()) throw UsageError{args[k] + " needs a value"};
    return args[++k];
}

SchemeKind parse_scheme_option(const std::string& text) {
    const auto s = parse_scheme(text);
    if (!s) throw UsageError{"--scheme must be normal, loop or butterfly"};
    return *s;
}

void take_mesh_argument(const std::string& arg, std::string& mesh) {
    if (!arg.empty() && arg[0] == '-') throw UsageError{"unknown option " + arg};
    if (!mesh.empty()) throw UsageError{"more than one mesh given ('" + mesh + "', '" + arg + "')"};
    mesh = arg;
}

bool parse_view_option(const std::vector<std::string>& args, std::size_t& k, ViewArgs& r) {
    const std::string& a = args[k];
    auto value = [&]() -> const std::string& { return option_value(args, k); };
    if (a == "-o" || a == "--output") r.output = value();
    else if (a == "--width") r.width = parse_int(a, value(), 1, 16384);
    else if (a == "--height") r.height = parse_int(a, value(), 1, 16384);
    else if (a == "--look-from") r.look_from = parse_vec3(a, value()), r.has_from = true;
    else if (a == "--look-at") r.look_at = parse_vec3(a, value()), r.has_at = true;
    else if (a == "--fov") {
        r.fov = parse_number(a, value());
        if (!(r.fov > 0.0 && r.fov < 179.0)) throw UsageError{"--fov must be in (0, 179)"};
    } else if (a == "--threads") r.threads = parse_int(a, value(), 1, 1024);
    else if (a == "--light") r.light = parse_vec3(a, value()), r.has_light = true;
    else if (a == "--no-shadows") r.shadows = false;
    else if (a == "--stats-json") r.stats_json = value();
    else if (a == "--quiet") r.quiet = true;
    else return false;
    return true;
}

Camera make_camera(const ViewArgs& a, const Bounds3& bounds) {
    Camera cam = frame_bounds(bounds, a.width, a.height, a.fov);
    if (a.has_at) cam.look_at = a.look_at;
    if (a.has_from) cam.look_from = a.look_from;
    if (glm::length(cam.look_at - cam.look_from) == 0.0)
        throw UsageError{"--look-from and --look-at are the same point"};
    return cam;
}

RenderOptions render_options(const ViewArgs& a) {
    RenderOptions ro;
    ro.threads = a.threads;
    ro.shadows = a.shadows;
    ro.has_light = a.has_light;
    ro.light = a.light;
    ro.progress = !a.quiet;
    return ro;
}

std::string run_stats_json_fields(double build_s, const RenderStats& rs, std::size_t scene_bytes,
                                  std::size_t baseline_rss) {
    const std::size_t peak = peak_rss_bytes();
    std::ostringstream j;
    j.precision(10);
    j << "  \"build_seconds\": " << build_s << ",\n";
    j << "  \"trace_seconds\": " << rs.trace_seconds << ",\n";
    j << "  \"total_seconds\": " << build_s + rs.trace_seconds << ",\n";
    // The process's resident set before the mesh is read (its shared
    // libraries; the image module with OpenImageIO is loaded only after these
    // figures are taken, to write the image), and the peak above it.
    j << "  \"peak_rss_mb\": " << peak / 1048576.0 << ",\n";
    j << "  \"baseline_rss_mb\": " << baseline_rss / 1048576.0 << ",\n";
    j << "  \"peak_rss_above_baseline_mb\": "
      << (peak > baseline_rss ? peak - baseline_rss : 0) / 1048576.0 << ",\n";
    j << "  \"rays\": " << rs.rays << ", \"shadow_rays\": " << rs.shadow_rays
      << ", \"hit_pixels\": " << rs.hit_pixels << ",\n";
    j << "  \"rays_per_second\": " << (rs.trace_seconds > 0 ? rs.rays / rs.trace_seconds : 0.0)
      << ",\n";
    j << "  \"scene_bytes\": " << scene_bytes << ",\n";
    return j.str();
}

void write_text_file(const std::string& path, const std::string& text) {
    std::ofstream out(path);
    out << text;
    if (!out) throw std::runtime_error(path + ": could not write");
}

}  // namespace subdivtrace::tools
