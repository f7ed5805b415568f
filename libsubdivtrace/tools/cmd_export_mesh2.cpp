// `subdivtrace export-mesh2 MESH -o OUT.inc [--scheme S] [--levels K] [--name IDENT]`:
// a POV-Ray mesh2 include, the baseline our primitive is compared with.
#include <chrono>
#include <cstdio>
#include <stdexcept>

#include "cli_args.h"
#include "commands.h"
#include "subdivtrace/mesh_io.h"
#include "subdivtrace/uniform.h"

namespace subdivtrace::cli {

namespace {

const char* k_export_help =
    "usage: subdivtrace export-mesh2 MESH -o OUT.inc [--scheme S] [--levels K] [--name IDENT]\n"
    "                           [--limit] [--weld EPS | --no-weld]\n"
    "\n"
    "Writes `#declare IDENT = mesh2 { ... }` for POV-Ray 3.7, after K levels of\n"
    "uniform subdivision (default 0: the mesh as read, with its own normals/UVs).\n"
    "\n"
    "  -o, --output OUT   output include file\n"
    "  --scheme S         normal (default), loop or butterfly\n"
    "  --levels K         subdivision levels, 0..10 (0)\n"
    "  --name IDENT       identifier (default: the file stem, e.g. Bunny_lowpoly)\n"
    "  --limit            move vertices to the limit surface (Loop; what the tracer draws)\n";

std::string file_stem(const std::string& path) {
    const std::size_t slash = path.find_last_of("/\\");
    std::string name = slash == std::string::npos ? path : path.substr(slash + 1);
    const std::size_t dot = name.find_last_of('.');
    if (dot != std::string::npos && dot > 0) name.resize(dot);
    return name;
}

}  // namespace

int run_export_mesh2(const Args& args) {
    const MeshArgs a =
        parse_mesh_args(args, k_arg_output | k_arg_scheme | k_arg_levels | k_arg_name | k_arg_limit, 0,
                        false);
    if (a.help) {
        std::fputs(k_export_help, stdout);
        std::fputs(k_weld_help, stdout);
        return 0;
    }
    if (a.output.empty()) throw UsageError{"no output file given (-o OUT.inc)"};
    std::vector<std::string> warnings;
    Mesh mesh = read_mesh(a.mesh, &warnings, a.weld);
    print_warnings(warnings);
    const std::size_t base = mesh.triangles.size();

    const auto start = std::chrono::steady_clock::now();
    const std::string ident = a.name.empty() ? pov_identifier(file_stem(a.mesh)) : a.name;
    std::size_t written = base;
    if (a.levels > 0 || a.limit) {
        // Written in place: its normals stay per vertex (write_mesh2's overload).
        const SubdividedMesh sub = subdivide_or_explain(mesh, a.mesh, a.scheme, a.levels, a.limit);
        mesh = Mesh();
        written = sub.triangles.size();
        write_mesh2(a.output, sub, ident);
    } else {
        write_mesh2(a.output, mesh, ident);
    }
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::fprintf(stderr,
                 "%s: %zu triangles -> %zu triangles (%s, %d level%s) in %.3f s -> %s as %s\n",
                 a.mesh.c_str(), base, written, scheme_name(a.scheme), a.levels,
                 a.levels == 1 ? "" : "s", seconds, a.output.c_str(), ident.c_str());
    return 0;
}

}  // namespace subdivtrace::cli
