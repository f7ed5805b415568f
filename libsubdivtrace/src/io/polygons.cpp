// Polygons to a Mesh: fan triangulation, then mesh_from_arrays (readers.h).
#include <algorithm>

#include "huge_pages.h"
#include "io/readers.h"

namespace subdivtrace::io {

Mesh mesh_from_polygons(Polygons& in, const std::string& path,
                        std::vector<std::string>* warnings, const WeldOptions& weld,
                        WeldReport* report) {
    MeshArrays a;
    a.positions = std::move(in.positions);
    a.normals = std::move(in.normals);
    a.uvs = std::move(in.uvs);
    const bool has_n = !a.normals.empty() && in.vn.size() == in.v.size();
    const bool has_t = !a.uvs.empty() && in.vt.size() == in.v.size();
    if (!has_n) a.normals.clear();
    if (!has_t) a.uvs.clear();
    // Allocated once (huge_pages.h): grown by doubling, the index lists of
    // a 100 MB export were copied about twice over.
    std::size_t triangles = 0;
    for (std::uint32_t k : in.sizes) triangles += k >= 3 ? k - 2 : 0;
    detail::reserve_huge(a.face_indices, triangles);
    if (has_n) detail::reserve_huge(a.normal_indices, triangles);
    if (has_t) detail::reserve_huge(a.uv_indices, triangles);
    std::size_t polygons = 0, largest = 0, corner = 0;
    for (std::uint32_t k : in.sizes) {
        if (k > 3) {
            ++polygons;
            largest = std::max<std::size_t>(largest, k);
        }
        for (std::uint32_t i = 1; i + 1 < k; ++i) {
            const std::size_t c0 = corner, c1 = corner + i, c2 = corner + i + 1;
            a.face_indices.push_back({in.v[c0], in.v[c1], in.v[c2]});
            if (has_n) a.normal_indices.push_back({in.vn[c0], in.vn[c1], in.vn[c2]});
            if (has_t) a.uv_indices.push_back({in.vt[c0], in.vt[c1], in.vt[c2]});
        }
        corner += k;
    }
    // The corners are all in the triangles now: their lists go before the
    // mesh is built (as int64s, 24 bytes a corner).
    std::vector<std::int64_t>().swap(in.v);
    std::vector<std::int64_t>().swap(in.vn);
    std::vector<std::int64_t>().swap(in.vt);
    if (polygons > 0 && warnings)
        warnings->push_back(path + ": fan-triangulated " + std::to_string(polygons) +
                            " polygon(s) with up to " + std::to_string(largest) + " corners into " +
                            std::to_string(a.face_indices.size()) + " triangles in all");
    return mesh_from_arrays(a, path, warnings, weld, report);
}

}  // namespace subdivtrace::io
