// `subdivtrace stability`: the stability table of docs/testing.md, one row per
// stiff case of DESIGN.md section 9.
#include <cstdio>
#include <string>

#include "commands.h"
#include "stability/stability.h"

namespace subdivtrace::cli {

namespace {

const char* k_stability_help =
    "usage: subdivtrace stability [--quick] [--width W] [--height H] [--inside-rays N]\n"
    "                             [--case NAME]...\n"
    "\n"
    "Builds each stiff case of DESIGN.md section 9 in code (slivers, zero-area and\n"
    "duplicate triangles, valence 100 and 200, folds, a crease, an open boundary,\n"
    "a non-manifold edge, a 1e6 offset with 1e-3 detail, scales 1e-6 and 1e6,\n"
    "grazing rays, the camera on the surface, max_level forced), traces a W x H\n"
    "image (default 160 x 120) and N rays from a point inside (default 2000), and\n"
    "prints per case: deepest leaf level hit, nodes built, time, peak RSS above\n"
    "the RSS before the case, non-finite hits, leaks (rays that must hit and\n"
    "missed; - where no ray must), and the largest deviation of a hit's distance\n"
    "from the long-double intersection with the same drawn triangle, in world\n"
    "units and as a fraction of the double-precision rounding bound.\n"
    "--quick: a 40 x 30 image and 200 rays from inside.\n"
    "Exit status 1 if any hit is non-finite, any ray leaks or any deviation\n"
    "exceeds its rounding bound.\n";

int int_value(const Args& args, std::size_t& i) {
    if (i + 1 >= args.size()) throw UsageError{args[i] + " needs a value"};
    ++i;
    return tools::parse_int(args[i - 1], args[i], 1, 4096);
}

}  // namespace

int run_stability(const Args& args) {
    int width = 160, height = 120, inside_rays = 2000;
    std::vector<std::string> names;
    for (std::size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        if (a == "--help" || a == "-h") {
            std::fputs(k_stability_help, stdout);
            return 0;
        } else if (a == "--quick") {
            width = 40;
            height = 30;
            inside_rays = 200;
        } else if (a == "--width") {
            width = int_value(args, i);
        } else if (a == "--height") {
            height = int_value(args, i);
        } else if (a == "--inside-rays") {
            inside_rays = int_value(args, i);
        } else if (a == "--case") {
            if (i + 1 >= args.size()) throw UsageError{"--case needs a name"};
            names.push_back(args[++i]);
        } else {
            throw UsageError{"unknown option '" + a + "'"};
        }
    }
    const std::vector<std::string> all = tools::stiff_case_names();
    for (const std::string& n : names) {
        bool known = false;
        for (const std::string& k : all) known = known || k == n;
        if (!known) throw UsageError{"no stiff case named '" + n + "'"};
    }
    if (names.empty()) names = all;

    std::printf("%d x %d camera rays per case, %d rays from inside closed ones\n\n", width,
                height, inside_rays);
    std::printf("%-20s %5s %10s %9s %8s %8s %5s %5s %10s %9s\n", "case", "level", "nodes",
                "visits/ray", "time s",
                "peak MB", "NaN", "leaks", "max dev", "dev/bound");
    bool broken = false;
    for (const std::string& n : names) {
        const tools::StiffCase c = tools::make_stiff_case(n, width, height);
        const tools::StabilityRow r = tools::run_stiff_case(c, inside_rays);
        const std::string leaks = r.leaks < 0 ? "-" : std::to_string(r.leaks);
        std::printf("%-20s %5d %10llu %9.0f %8.3f %8.1f %5llu %5s %10.2e %9.3f\n", r.name.c_str(),
                    r.max_level, static_cast<unsigned long long>(r.nodes_built), r.visits_per_ray,
                    r.seconds,
                    r.peak_mb, static_cast<unsigned long long>(r.non_finite), leaks.c_str(),
                    r.max_deviation, r.max_deviation_ratio);
        std::fflush(stdout);
        broken = broken || r.non_finite > 0 || r.leaks > 0 || r.max_deviation_ratio > 1.0;
    }
    if (broken) std::fprintf(stderr, "subdivtrace stability: an invariant failed (see the table)\n");
    return broken ? 1 : 0;
}

}  // namespace subdivtrace::cli
