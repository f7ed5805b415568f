// subdivtrace: command-line front end of libsubdivtrace.
#include <cstdio>
#include <cstring>
#include <exception>
#include <string>

#include "commands.h"

namespace {

const char* k_usage =
    "usage: subdivtrace <command> [options]\n"
    "\n"
    "commands:\n"
    "  info MESH                         counts, boundaries, valences, bounds\n"
    "  subdivide MESH -o OUT [--scheme S] [--levels K]\n"
    "                                    uniform subdivision, OUT = .obj .off .ply .stl\n"
    "  export-mesh2 MESH -o OUT.inc [--scheme S] [--levels K] [--name IDENT]\n"
    "                                    POV-Ray mesh2 include\n"
    "  render MESH -o OUT.png [options]  per-ray adaptive render (render --help)\n"
    "  stats MESH [options]              work counters of an adaptive render, as JSON\n"
    "  stability [--quick]               the stiff cases' table: levels, work, memory,\n"
    "                                    NaNs, leaks, deviation (stability --help)\n"
    "\n"
    "schemes: normal (default, the paper's), loop, butterfly\n"
    "exit status: 0 ok, 1 bad input, 2 usage error\n";

}  // namespace

int main(int argc, char** argv) {
    using namespace subdivtrace::cli;
    if (argc < 2 || !std::strcmp(argv[1], "--help") || !std::strcmp(argv[1], "-h")) {
        std::fputs(k_usage, argc < 2 ? stderr : stdout);
        return argc < 2 ? 2 : 0;
    }
    const std::string command = argv[1];
    const Args args(argv + 2, argv + argc);
    try {
        if (command == "info") return run_info(args);
        if (command == "subdivide") return run_subdivide(args);
        if (command == "export-mesh2") return run_export_mesh2(args);
        if (command == "render") return run_render(args);
        if (command == "stats") return run_stats(args);
        if (command == "stability") return run_stability(args);
    } catch (const UsageError& e) {
        std::fprintf(stderr, "subdivtrace %s: %s\n\n%s", command.c_str(), e.message.c_str(),
                     k_usage);
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "subdivtrace %s: %s\n", command.c_str(), e.what());
        return 1;
    }
    std::fprintf(stderr, "subdivtrace: unknown command '%s'\n\n%s", command.c_str(), k_usage);
    return 2;
}
