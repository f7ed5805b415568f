// `subdivtrace info MESH`: what the schemes will see in a mesh file.
#include <cstdio>

#include "cli_args.h"
#include "commands.h"
#include "subdivtrace/mesh_io.h"
#include "subdivtrace/mesh_report.h"

namespace subdivtrace::cli {

namespace {

const char* k_info_help =
    "usage: subdivtrace info MESH [--weld EPS | --no-weld]\n"
    "\n"
    "Reads MESH (.obj .off .ply .stl) and prints vertex, face and edge counts,\n"
    "how many vertices were welded, boundary and non-manifold edges, degenerate\n"
    "and duplicate triangles, unreferenced vertices, the valence histogram and\n"
    "the bounding box.\n"
    "\n";

}  // namespace

int run_info(const Args& args) {
    const MeshArgs a = parse_mesh_args(args, 0, 0, false);
    if (a.help) {
        std::fputs(k_info_help, stdout);
        std::fputs(k_weld_help, stdout);
        return 0;
    }
    std::vector<std::string> warnings;
    WeldReport weld;
    const Mesh mesh = read_mesh(a.mesh, &warnings, a.weld, &weld);
    print_warnings(warnings);
    const MeshReport r = analyze_mesh(mesh);

    std::printf("file:                  %s\n", a.mesh.c_str());
    std::printf("vertices:              %zu\n", r.vertices);
    if (a.weld.enabled)
        std::printf("welded vertices:       %zu\n", weld.welded_vertices);
    else
        std::printf("welded vertices:       none (--no-weld)\n");
    std::printf("triangles:             %zu\n", r.faces);
    std::printf("turned triangles:      %zu\n", weld.reversed_triangles.size());
    std::printf("edges:                 %zu\n", r.edges);
    std::printf("components:            %zu\n", r.components);
    std::printf("closed:                %s\n", r.closed ? "yes" : "no");
    std::printf("boundary edges:        %zu\n", r.boundary_edges);
    std::printf("non-manifold edges:    %zu\n", r.nonmanifold_edges);
    std::printf("singular vertices:     %zu\n", r.singular_vertices);
    std::printf("unreferenced vertices: %zu\n", r.unreferenced_vertices);
    std::printf("degenerate triangles:  %zu\n", r.degenerate_faces);
    std::printf("duplicate triangles:   %zu\n", r.duplicate_faces);
    std::printf("normals:               %s\n", r.has_normals ? "per corner" : "none");
    std::printf("crease edges:          %zu\n", r.crease_edges);
    std::printf("uvs:                   %s\n", r.has_uvs ? "per corner" : "none");
    std::printf("valence:               %d..%d\n", r.min_valence, r.max_valence);
    std::printf("valence histogram:    ");
    for (std::size_t k = 0; k < r.valence_histogram.size(); ++k)
        if (r.valence_histogram[k] > 0) std::printf(" %zu:%zu", k, r.valence_histogram[k]);
    std::printf("\n");
    std::printf("bounds:                (%.9g, %.9g, %.9g) .. (%.9g, %.9g, %.9g)\n", r.bounds.lo.x,
                r.bounds.lo.y, r.bounds.lo.z, r.bounds.hi.x, r.bounds.hi.y, r.bounds.hi.z);
    return 0;
}

}  // namespace subdivtrace::cli
