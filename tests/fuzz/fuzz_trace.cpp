// libFuzzer harness of the tracer: random small meshes (closed star-shaped
// ones around a known inside point, or arbitrary triangles), without normals,
// with smooth ones, faceted ones (every edge a crease) or random ones per
// corner (creases anywhere, zero normals included), traced with random rays
// in every scheme. Invariants (DESIGN.md sections 5, 6 and 9):
//   - every hit is finite, within (t_min, t_max), with a unit normal;
//   - every hit point lies within the surface's bounds() (grown by its error bound);
//   - all hits are sorted and as finite as the nearest one;
//   - a closed mesh: every ray from a point inside hits, and inside() says so.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <fuzzer/FuzzedDataProvider.h>
#include <glm/geometric.hpp>

#include "subdivtrace/mesh.h"
#include "subdivtrace/tracer.h"

using namespace subdivtrace;

namespace {

[[noreturn]] void broken(const std::string& what) {
    std::fprintf(stderr, "invariant broken: %s\n", what.c_str());
    std::abort();
}

bool finite(const Vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

/// Octahedron (closed, counter-clockwise from outside), radius 1.
MeshArrays octahedron() {
    MeshArrays a;
    a.positions = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    a.face_indices = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                      {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
    return a;
}

/// Icosahedron (closed, counter-clockwise from outside), radius 1.
MeshArrays icosahedron() {
    const double t = (1.0 + std::sqrt(5.0)) / 2.0;
    MeshArrays a;
    a.positions = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                   {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    for (Vec3& p : a.positions) p = glm::normalize(p);
    a.face_indices = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                      {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                      {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                      {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
    return a;
}

Vec3 unit_direction(FuzzedDataProvider& in) {
    for (int tries = 0; tries < 4; ++tries) {
        const Vec3 d(in.ConsumeFloatingPointInRange(-1.0, 1.0),
                     in.ConsumeFloatingPointInRange(-1.0, 1.0),
                     in.ConsumeFloatingPointInRange(-1.0, 1.0));
        if (glm::length(d) > 1e-3) return d / glm::length(d);
    }
    return Vec3(0.36, -0.48, 0.8);
}

void check_hit(const Ray& ray, const Hit& h, const Bounds3& b, const char* where) {
    if (!(std::isfinite(h.t) && h.t > ray.t_min && h.t < ray.t_max))
        broken(std::string(where) + ": t out of range or not finite");
    if (!finite(h.point) || !finite(h.normal) || !std::isfinite(h.error_bound))
        broken(std::string(where) + ": non-finite point, normal or error bound");
    if (std::abs(glm::length(h.normal) - 1.0) > 1e-6)
        broken(std::string(where) + ": normal not unit length");
    // Within the bounds, up to the hit's own error bound and rounding.
    const double slack = h.error_bound + 1e-9 * glm::length(b.hi - b.lo);
    for (int k = 0; k < 3; ++k)
        if (h.point[k] < b.lo[k] - slack || h.point[k] > b.hi[k] + slack)
            broken(std::string(where) + ": hit outside bounds()");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    FuzzedDataProvider in(data, size);
    const bool closed = in.ConsumeBool();
    const double scale = std::pow(10.0, in.ConsumeIntegralInRange(-6, 6));
    const Vec3 offset = Vec3(in.ConsumeFloatingPointInRange(-2.0, 2.0),
                             in.ConsumeFloatingPointInRange(-2.0, 2.0),
                             in.ConsumeFloatingPointInRange(-2.0, 2.0)) *
                        scale;

    // The mesh.
    MeshArrays a;
    if (closed) {
        // Star-shaped around `offset`: radii within [0.8, 1.25] keep the
        // surface of every scheme far from the centre.
        a = in.ConsumeBool() ? icosahedron() : octahedron();
        for (Vec3& p : a.positions)
            p = offset + p * in.ConsumeFloatingPointInRange(0.8, 1.25) * scale;
    } else {
        const int nv = in.ConsumeIntegralInRange(3, 10);
        for (int i = 0; i < nv; ++i)
            a.positions.push_back(offset + Vec3(in.ConsumeFloatingPointInRange(-1.0, 1.0),
                                                in.ConsumeFloatingPointInRange(-1.0, 1.0),
                                                in.ConsumeFloatingPointInRange(-1.0, 1.0)) *
                                               scale);
        const int nf = in.ConsumeIntegralInRange(1, 14);
        for (int f = 0; f < nf; ++f)
            a.face_indices.push_back({in.ConsumeIntegralInRange<std::int64_t>(0, nv - 1),
                                      in.ConsumeIntegralInRange<std::int64_t>(0, nv - 1),
                                      in.ConsumeIntegralInRange<std::int64_t>(0, nv - 1)});
    }
    Mesh mesh;
    try {
        mesh = mesh_from_arrays(a, "fuzz");
    } catch (const MeshError&) {
        return 0;  // e.g. every triangle repeats a vertex
    }

    // The surface.
    SurfaceOptions o;
    o.scheme = static_cast<SchemeKind>(in.ConsumeIntegralInRange(0, 2));
    o.max_level = in.ConsumeIntegralInRange(0, 4);
    o.tolerance = in.ConsumeFloatingPointInRange(0.25, 8.0);
    o.cache_mb = 4;
    o.view.pixel_angle = in.ConsumeFloatingPointInRange(1e-3, 0.1);
    o.view.camera = offset + unit_direction(in) * (3.0 * scale);

    // Normals per corner: given normals are the normal scheme's level 0, and
    // split ones mark creases for every scheme (docs/schemes.md).
    const int normals = in.ConsumeIntegralInRange(0, 3);
    for (std::size_t t = 0; normals > 0 && t < mesh.triangles.size(); ++t) {
        const Triangle& tri = mesh.triangles[t];
        const Vec3 face = glm::cross(mesh.positions[tri[1]] - mesh.positions[tri[0]],
                                     mesh.positions[tri[2]] - mesh.positions[tri[0]]);
        for (std::uint32_t v : tri) {
            if (normals == 1) mesh.corner_normals.push_back(mesh.positions[v] - offset);
            else if (normals == 2) mesh.corner_normals.push_back(face);
            else mesh.corner_normals.push_back(in.ConsumeBool() ? Vec3(0.0) : unit_direction(in));
        }
    }
    const AdaptiveSurface surface(mesh, o);
    const Bounds3 b = surface.bounds();
    if (!finite(b.lo) || !finite(b.hi)) broken("bounds() not finite");

    // Rays from inside a closed mesh must all hit.
    if (closed) {
        if (!surface.is_closed()) broken("closed mesh reported open");
        View view = o.view;
        view.camera = offset;
        if (!surface.inside(offset, &view)) broken("inside() false at the centre");
        const int n = in.ConsumeIntegralInRange(1, 8);
        for (int k = 0; k < n; ++k) {
            Ray ray;
            ray.origin = offset;
            ray.direction = unit_direction(in) * scale;
            ray.origin_distance = 0.0;
            ray.view = &view;
            Hit h;
            if (!surface.intersect(ray, h)) broken("a ray from inside a closed mesh missed");
            check_hit(ray, h, b, "inside ray");
        }
    }

    // Rays from anywhere: hits must be sane.
    while (in.remaining_bytes() > 0) {
        Ray ray;
        ray.origin = offset + Vec3(in.ConsumeFloatingPointInRange(-3.0, 3.0),
                                   in.ConsumeFloatingPointInRange(-3.0, 3.0),
                                   in.ConsumeFloatingPointInRange(-3.0, 3.0)) *
                                  scale;
        ray.direction = unit_direction(in);
        Hit h;
        if (surface.intersect(ray, h)) check_hit(ray, h, b, "nearest hit");
        std::vector<Hit> all;
        surface.intersect_all(ray, all);
        for (std::size_t k = 0; k < all.size(); ++k) {
            check_hit(ray, all[k], b, "all hits");
            if (k > 0 && all[k].t < all[k - 1].t) broken("all hits not sorted");
        }
    }
    return 0;
}
