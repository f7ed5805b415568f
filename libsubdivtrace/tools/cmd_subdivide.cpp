// `subdivtrace subdivide MESH -o OUT [--scheme S] [--levels K]`: uniform subdivision.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "cli_args.h"
#include "commands.h"
#include "subdivtrace/mesh_io.h"
#include "subdivtrace/uniform.h"

namespace subdivtrace::cli {

namespace {

const char* k_subdivide_help =
    "usage: subdivtrace subdivide MESH -o OUT [--scheme S] [--levels K] [--limit]\n"
    "                            [--weld EPS | --no-weld]\n"
    "\n"
    "Subdivides every triangle of MESH 1-to-4, K times (default 1, at most 10),\n"
    "and writes OUT (.obj .off .ply .stl, by extension).\n"
    "\n"
    "  -o, --output OUT   output mesh file\n"
    "  --scheme S         normal (default, the paper's), loop or butterfly\n"
    "  --levels K         subdivision levels, 0..10 (1)\n"
    "  --limit            move vertices to the limit surface (Loop; what the tracer draws)\n";

/// From this many output triangles on, the steps are announced as they start.
constexpr double k_announce_triangles = 1.0e6;

}  // namespace

int run_subdivide(const Args& args) {
    const MeshArgs a = parse_mesh_args(args, k_arg_output | k_arg_scheme | k_arg_levels | k_arg_limit, 1, false);
    if (a.help) {
        std::fputs(k_subdivide_help, stdout);
        std::fputs(k_weld_help, stdout);
        return 0;
    }
    if (a.output.empty()) throw UsageError{"no output file given (-o OUT)"};
    std::vector<std::string> warnings;
    const Mesh mesh = read_mesh(a.mesh, &warnings, a.weld);
    print_warnings(warnings);

    // A deep level takes seconds to compute and as long again to write:
    // say what is under way (the summary line comes at the end).
    const double expected = static_cast<double>(mesh.triangles.size()) * std::pow(4.0, a.levels);
    const bool announce = expected >= k_announce_triangles;
    if (announce)
        std::fprintf(stderr, "%s: subdividing to level %d (%.0f triangles)...\n", a.mesh.c_str(), a.levels,
                     expected);
    const auto start = std::chrono::steady_clock::now();
    const SubdividedMesh result = subdivide_or_explain(mesh, a.mesh, a.scheme, a.levels, a.limit);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (announce) std::fprintf(stderr, "%s: writing...\n", a.output.c_str());
    write_mesh(a.output, result);
    std::fprintf(stderr, "%s: %zu triangles -> %zu triangles (%s, %d level%s) in %.3f s -> %s\n",
                 a.mesh.c_str(), mesh.triangles.size(), result.triangles.size(),
                 scheme_name(a.scheme), a.levels, a.levels == 1 ? "" : "s", seconds,
                 a.output.c_str());
    return 0;
}

}  // namespace subdivtrace::cli
