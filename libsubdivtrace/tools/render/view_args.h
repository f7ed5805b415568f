#pragma once
// Command-line options every renderer shares (the CLI's `render`, compare/'s
// Embree peer): image size, camera, light, shadows, threads, outputs. One
// parser and one camera model, so their images line up pixel for pixel.

#include <cstddef>
#include <string>
#include <vector>

#include "render/camera.h"
#include "render/render_loop.h"
#include "subdivtrace/scheme.h"

namespace subdivtrace::tools {

/// A bad command line; the program prints it with its help and exits 2.
struct UsageError {
    std::string message;
};

/// Parses a finite number; throws UsageError naming `option`.
double parse_number(const std::string& option, const std::string& text);
/// Parses an integer in lo..hi; throws UsageError naming `option`.
int parse_int(const std::string& option, const std::string& text, int lo, int hi);
/// Parses "X,Y,Z"; throws UsageError naming `option`.
Vec3 parse_vec3(const std::string& option, const std::string& text);

/// The value after option args[k], advancing k; throws UsageError if none.
const std::string& option_value(const std::vector<std::string>& args, std::size_t& k);
/// The value of --scheme; throws UsageError unless normal, loop or butterfly.
SchemeKind parse_scheme_option(const std::string& text);
/// A positional argument is the mesh (only one); "-..." is an unknown option.
/// Throws UsageError for either mistake.
void take_mesh_argument(const std::string& arg, std::string& mesh);

struct ViewArgs {
    std::string output;      ///< -o
    std::string stats_json;  ///< --stats-json
    int width = 640, height = 480;
    bool has_from = false, has_at = false;
    Vec3 look_from{0.0}, look_at{0.0};
    double fov = 40.0;
    int threads = 0;
    bool has_light = false;
    Vec3 light{0.0};
    bool shadows = true;
    bool quiet = false;
};

/// The help lines of the options parse_view_option takes.
extern const char* const k_view_options_help;

/// If args[k] is a view option (-o, --width, --height, --look-from, --look-at,
/// --fov, --threads, --light, --no-shadows, --stats-json, --quiet), stores it,
/// advances k past its value and returns true; false for any other argument.
bool parse_view_option(const std::vector<std::string>& args, std::size_t& k, ViewArgs& view);

/// The camera: frames `bounds` unless --look-from / --look-at say otherwise.
Camera make_camera(const ViewArgs& view, const Bounds3& bounds);

/// Threads, light, shadows and progress (unless --quiet) for render().
RenderOptions render_options(const ViewArgs& view);

/// The JSON fields every renderer reports, each line ending in ",\n":
/// build/trace/total seconds, peak RSS, the RSS before the mesh was read and
/// the peak above it, ray counts, rays/s and `scene_bytes`.
std::string run_stats_json_fields(double build_seconds, const RenderStats& stats,
                                  std::size_t scene_bytes, std::size_t baseline_rss);

/// Writes `text` to `path`; throws std::runtime_error "<path>: could not write".
void write_text_file(const std::string& path, const std::string& text);

}  // namespace subdivtrace::tools
