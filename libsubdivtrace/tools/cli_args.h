#pragma once
// Shared option parsing of the mesh commands (info, subdivide, export-mesh2):
// one positional MESH, -o/--output, --scheme, --levels, --name, --limit, --help,
// and the weld options every command that reads a mesh takes (--weld, --no-weld).

#include <string>

#include "commands.h"
#include "subdivtrace/mesh.h"
#include "subdivtrace/scheme.h"
#include "subdivtrace/uniform.h"

namespace subdivtrace::cli {

/// Which options a command accepts (bit set).
enum ArgFlags : unsigned {
    k_arg_output = 1u,
    k_arg_scheme = 2u,
    k_arg_levels = 4u,
    k_arg_name = 8u,
    k_arg_limit = 16u,  ///< --limit (no value)
};

struct MeshArgs {
    std::string mesh;
    std::string output;
    std::string name;  ///< empty = derive from the mesh file's stem
    SchemeKind scheme = SchemeKind::normal;
    int levels = 0;
    bool limit = false;  ///< push vertices to the limit surface (push_to_limit)
    WeldOptions weld;    ///< --weld EPS / --no-weld
    bool help = false;
};

/// Help text of the weld options, for each command's --help.
extern const char* const k_weld_help;

/// If args[i] is a weld option (`--no-weld`, `--weld EPS`, `--weld=EPS`),
/// applies it to `weld`, advances i past its value and returns true. EPS is
/// relative to the bounding-box diagonal: a number in [0, 0.1] (0 = exact,
/// the default). Throws UsageError on a missing or bad EPS.
bool parse_weld_arg(const Args& args, std::size_t& i, WeldOptions& weld);

/// Parses `args`; options may be given as `--opt VALUE` or `--opt=VALUE`.
/// Throws UsageError on an unknown option, a missing value, a bad scheme, a
/// level outside 0..10, a bad --name, a missing MESH or (if `output_required`)
/// a missing -o. With --help, returns at once with help = true.
MeshArgs parse_mesh_args(const Args& args, unsigned accepted, int default_levels,
                         bool output_required);

/// Prints the reader's warnings to stderr, each prefixed "warning: ".
void print_warnings(const std::vector<std::string>& warnings);

/// Uniform subdivision for a command: failures (too many levels, out of
/// memory) become a MeshError naming the mesh file.
/// With `limit`, the result's vertices are pushed to the limit surface.
SubdividedMesh subdivide_or_explain(const Mesh& mesh, const std::string& path, SchemeKind scheme,
                                    int levels, bool limit = false);

}  // namespace subdivtrace::cli
