// trace_rays: the smallest use of libsubdivtrace. Reads a mesh, builds the
// adaptive surface for a 640-pixel-wide view, shoots a few rays from the
// camera at the mesh and prints what each one hits.
//   trace_rays MESH [RAYS]
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "subdivtrace/mesh_io.h"
#include "subdivtrace/tracer.h"

using namespace subdivtrace;

int main(int argc, char** argv) {
    if (argc < 2 || argc > 3) {
        std::fprintf(stderr, "usage: trace_rays MESH [RAYS]\n");
        return 2;
    }
    const int ray_count = argc == 3 ? std::atoi(argv[2]) : 5;
    try {
        // Read and validate the mesh (OBJ, OFF, PLY or STL).
        std::vector<std::string> warnings;
        Mesh mesh = read_mesh(argv[1], &warnings);
        for (const std::string& w : warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());

        // Place a camera in front of the mesh: two bounding radii from its centre.
        const Bounds3 box = mesh_bounds(mesh);
        const Vec3 centre = (box.lo + box.hi) * 0.5;
        const double radius = 0.5 * glm::length(box.hi - box.lo);
        const Vec3 camera = centre + Vec3(0.0, 0.0, 2.0 * radius);

        // The surface refines each ray's triangles until they lie close
        // enough to the limit surface for `tolerance` pixels of this view (40
        // degrees over 640 pixels; docs/tracer.md, the error rule).
        SurfaceOptions options;
        options.scheme = SchemeKind::normal;
        options.tolerance = 1.0;
        options.max_level = 8;
        options.view.camera = camera;
        options.view.pixel_angle = 0.698 / 640.0;
        const AdaptiveSurface surface(std::move(mesh), options);

        // Rays from the camera through points spread across the mesh's middle.
        int hits = 0;
        for (int k = 0; k < ray_count; ++k) {
            const double s = ray_count > 1 ? 2.0 * k / (ray_count - 1) - 1.0 : 0.0;
            Ray ray;
            ray.origin = camera;
            ray.direction = glm::normalize(centre + Vec3(0.3 * s * radius, 0.1 * s * radius, 0.0) -
                                           camera);
            Hit hit;
            if (surface.intersect(ray, hit)) {
                ++hits;
                std::printf("ray %d: hit t=%.6g point=(%.6g, %.6g, %.6g) normal=(%.4f, %.4f, %.4f) "
                            "level=%d base_face=%u\n",
                            k, hit.t, hit.point.x, hit.point.y, hit.point.z, hit.normal.x,
                            hit.normal.y, hit.normal.z, hit.level, hit.base_face);
            } else {
                std::printf("ray %d: miss\n", k);
            }
        }
        const SurfaceStats stats = surface.stats();
        std::printf("%d of %d rays hit; %llu nodes built, deepest level %d\n", hits, ray_count,
                    static_cast<unsigned long long>(stats.nodes_built), stats.trace.deepest_level);
        return hits > 0 ? 0 : 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "trace_rays: %s\n", e.what());
        return 1;
    }
}
