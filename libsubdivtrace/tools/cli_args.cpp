// Shared option parsing of the mesh commands (cli_args.h).
#include "cli_args.h"

#include <cstdio>

#include "subdivtrace/mesh_io.h"
#include "subdivtrace/mesh_report.h"
#include "subdivtrace/uniform.h"

namespace subdivtrace::cli {

const char* const k_weld_help =
    "  --weld EPS                 also weld vertices closer than EPS times the bounding-box\n"
    "                             diagonal (default 0: only identical positions are welded)\n"
    "  --no-weld                  keep coincident vertices apart (separate sheets)\n";

bool parse_weld_arg(const Args& args, std::size_t& i, WeldOptions& weld) {
    const std::string& arg = args[i];
    if (arg == "--no-weld") {
        weld.enabled = false;
        return true;
    }
    std::string value;
    if (arg == "--weld") {
        if (i + 1 >= args.size()) throw UsageError{"option '--weld' needs a value"};
        value = args[++i];
    } else if (arg.compare(0, 7, "--weld=") == 0) {
        value = arg.substr(7);
    } else {
        return false;
    }
    std::size_t used = 0;
    double eps = -1.0;
    try {
        eps = std::stod(value, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    // Beyond a tenth of the diagonal, welding would fold the mesh onto itself.
    if (value.empty() || used != value.size() || !(eps >= 0.0 && eps <= 0.1))
        throw UsageError{"--weld expects a number in [0, 0.1] (relative to the bounding-box "
                         "diagonal), got '" + value + "'"};
    weld.enabled = true;
    weld.relative_tolerance = eps;
    return true;
}

MeshArgs parse_mesh_args(const Args& args, unsigned accepted, int default_levels,
                         bool output_required) {
    MeshArgs out;
    out.levels = default_levels;
    for (std::size_t i = 0; i < args.size(); ++i) {
        std::string arg = args[i];
        if (arg == "--help" || arg == "-h") {
            out.help = true;
            return out;
        }
        if (arg.size() < 2 || arg[0] != '-') {
            if (!out.mesh.empty())
                throw UsageError{"more than one mesh given ('" + out.mesh + "' and '" + arg + "')"};
            out.mesh = arg;
            continue;
        }
        if (arg == "--limit" && (accepted & k_arg_limit)) {
            out.limit = true;
            continue;
        }
        if (parse_weld_arg(args, i, out.weld)) continue;
        // --opt=value or --opt value
        std::string value;
        bool has_value = false;
        const std::size_t eq = arg.find('=');
        if (arg.compare(0, 2, "--") == 0 && eq != std::string::npos) {
            value = arg.substr(eq + 1);
            arg = arg.substr(0, eq);
            has_value = true;
        }
        unsigned flag = 0;
        if (arg == "-o" || arg == "--output")
            flag = k_arg_output;
        else if (arg == "--scheme")
            flag = k_arg_scheme;
        else if (arg == "--levels")
            flag = k_arg_levels;
        else if (arg == "--name")
            flag = k_arg_name;
        if (flag == 0 || !(accepted & flag)) throw UsageError{"unknown option '" + arg + "'"};
        if (!has_value) {
            if (i + 1 >= args.size()) throw UsageError{"option '" + arg + "' needs a value"};
            value = args[++i];
        }
        if (value.empty()) throw UsageError{"option '" + arg + "' needs a value"};
        switch (flag) {
            case k_arg_output: out.output = value; break;
            case k_arg_scheme: {
                const auto kind = parse_scheme(value);
                if (!kind)
                    throw UsageError{"unknown scheme '" + value +
                                     "' (expected normal, loop or butterfly)"};
                out.scheme = *kind;
                break;
            }
            case k_arg_levels: {
                std::size_t used = 0;
                int levels = -1;
                try {
                    levels = std::stoi(value, &used);
                } catch (const std::exception&) {
                    used = 0;
                }
                if (used != value.size() || levels < 0 || levels > k_max_uniform_levels)
                    throw UsageError{"--levels expects an integer in 0.." +
                                     std::to_string(k_max_uniform_levels) + ", got '" + value +
                                     "'"};
                out.levels = levels;
                break;
            }
            case k_arg_name:
                if (!is_pov_identifier(value))
                    throw UsageError{"--name '" + value +
                                     "' is not a POV-Ray identifier (a letter, then letters, "
                                     "digits or '_', at most 40)"};
                out.name = value;
                break;
        }
    }
    if (out.mesh.empty()) throw UsageError{"no mesh file given"};
    if (output_required && out.output.empty()) throw UsageError{"no output file given (-o OUT)"};
    return out;
}

void print_warnings(const std::vector<std::string>& warnings) {
    for (const std::string& w : warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
}

SubdividedMesh subdivide_or_explain(const Mesh& mesh, const std::string& path, SchemeKind scheme,
                                    int levels, bool limit) {
    const std::string note = given_normals_warning(mesh, scheme, path);
    if (!note.empty() && levels > 0) print_warnings({note});
    try {
        SubdividedMesh sub = subdivide_uniform(mesh, scheme, levels);
        if (limit) push_to_limit(sub, scheme);
        return sub;
    } catch (const std::invalid_argument& e) {
        throw MeshError(path + ": " + e.what());
    } catch (const std::length_error&) {
        throw MeshError(path + ": too large to subdivide " + std::to_string(levels) + " levels");
    } catch (const std::bad_alloc&) {
        throw MeshError(path + ": out of memory subdividing " + std::to_string(levels) +
                        " levels");
    }
}

}  // namespace subdivtrace::cli
