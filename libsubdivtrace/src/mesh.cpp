// Mesh construction from raw arrays, validation and bounds (mesh.h).
#include "subdivtrace/mesh.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "finite_values.h"
#include "huge_pages.h"
#include "orient.h"
#include "weld.h"

namespace subdivtrace {

namespace {

[[noreturn]] void fail(const std::string& source, const std::string& reason) {
    throw MeshError(source + ": " + reason);
}

std::string format_number(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    return buf;
}

std::string format_vec(const Vec3& v) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "(%g, %g, %g)", v.x, v.y, v.z);
    return buf;
}
std::string format_vec(const Vec2& v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "(%g, %g)", v.x, v.y);
    return buf;
}

/// Every value of `values` must be finite; `what` names them in the message.
template <class V>
void check_all_finite(const std::vector<V>& values, const char* what, const std::string& source) {
    for (std::size_t i = 0; i < values.size(); ++i)
        if (!detail::is_finite(values[i]))
            fail(source, std::string(what) + " " + std::to_string(i) + " is not finite " +
                             format_vec(values[i]));
}

/// Checks one index triple of `list` (named `what`) against [0, count).
void check_range(const std::array<std::int64_t, 3>& idx, std::size_t count, const char* what,
                 std::size_t face, const std::string& source) {
    for (std::int64_t i : idx)
        if (i < 0 || static_cast<std::uint64_t>(i) >= count)
            fail(source,
                 std::string(what) + " of face " + std::to_string(face) + ": index " +
                     std::to_string(i) + " out of range (" + std::to_string(count) +
                     (count == 0 ? " entries)"
                                 : " entries, valid 0.." + std::to_string(count - 1) + ")"));
}

/// Turns triangles (corners 1 and 2 swap) so that neighbours agree on the
/// winding (orient.h); returns the turned ones, ascending (their corner
/// normals and uvs, not built yet, must follow).
std::vector<std::uint32_t> orient_consistently(Mesh& mesh, const std::string& source,
                                               std::vector<std::string>* warnings) {
    const Orientation o = consistent_orientation(mesh.triangles, mesh.positions.size());
    std::vector<std::uint32_t> reversed;
    reversed.reserve(o.flipped_count);
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        if (!o.flipped[t]) continue;
        reversed.push_back(static_cast<std::uint32_t>(t));
        std::swap(mesh.triangles[t][1], mesh.triangles[t][2]);
    }
    if (warnings && o.flipped_count > 0)
        warnings->push_back(source + ": turned " + std::to_string(o.flipped_count) + " of " +
                            std::to_string(mesh.triangles.size()) +
                            " triangles to the winding of their neighbours (first: triangle " +
                            std::to_string(reversed.front()) +
                            "); the surface's normals need one consistent side");
    if (warnings && o.conflicting_edges > 0)
        warnings->push_back(source + ": " + std::to_string(o.conflicting_edges) +
                            " edge(s) join triangles whose windings cannot agree (a "
                            "non-orientable surface, like a Moebius strip): normals flip there");
    return reversed;
}

}  // namespace

void detail::check_finite(const std::vector<Vec3>& values, const char* what, const std::string& source) {
    check_all_finite(values, what, source);
}

void detail::check_finite(const std::vector<Vec2>& values, const char* what, const std::string& source) {
    check_all_finite(values, what, source);
}

Mesh mesh_from_arrays(const MeshArrays& arrays, const std::string& source,
                      std::vector<std::string>* warnings, const WeldOptions& weld,
                      WeldReport* report) {
    // Sizes first: they decide how the index lists are read.
    if (arrays.face_indices.empty()) fail(source, "no faces");
    if (arrays.positions.empty()) fail(source, "no vertices");
    if (arrays.positions.size() > std::numeric_limits<std::uint32_t>::max())
        fail(source, "too many vertices (" + std::to_string(arrays.positions.size()) +
                         ", at most 2^32 - 1)");
    const std::size_t n_faces = arrays.face_indices.size();
    if (!arrays.normal_indices.empty() && arrays.normals.empty())
        fail(source, "normal_indices given without normal_vectors");
    if (!arrays.uv_indices.empty() && arrays.uvs.empty())
        fail(source, "uv_indices given without uv_vectors");
    if (!arrays.normal_indices.empty() && arrays.normal_indices.size() != n_faces)
        fail(source, "normal_indices has " + std::to_string(arrays.normal_indices.size()) +
                         " entries but face_indices has " + std::to_string(n_faces));
    if (!arrays.uv_indices.empty() && arrays.uv_indices.size() != n_faces)
        fail(source, "uv_indices has " + std::to_string(arrays.uv_indices.size()) +
                         " entries but face_indices has " + std::to_string(n_faces));
    if (!(std::isfinite(weld.relative_tolerance) && weld.relative_tolerance >= 0.0))
        fail(source, "weld tolerance must be finite and >= 0 (it is " +
                         format_number(weld.relative_tolerance) + ")");

    detail::check_finite(arrays.positions, "vertex", source);
    detail::check_finite(arrays.normals, "normal", source);
    detail::check_finite(arrays.uvs, "uv", source);

    const bool has_normals = !arrays.normals.empty();
    const bool has_uvs = !arrays.uvs.empty();
    for (std::size_t f = 0; f < n_faces; ++f) {
        check_range(arrays.face_indices[f], arrays.positions.size(), "vertex index", f, source);
        if (has_normals)
            check_range(
                arrays.normal_indices.empty() ? arrays.face_indices[f] : arrays.normal_indices[f],
                arrays.normals.size(), "normal index", f, source);
        if (has_uvs)
            check_range(arrays.uv_indices.empty() ? arrays.face_indices[f] : arrays.uv_indices[f],
                        arrays.uvs.size(), "uv index", f, source);
    }

    // Weld: the topology is built on the connectivity the positions imply.
    Mesh mesh;
    std::vector<std::uint32_t> remap;
    if (weld.enabled) {
        double tolerance = 0.0;
        if (weld.relative_tolerance > 0.0) {
            Bounds3 b;
            b.lo = b.hi = arrays.positions[static_cast<std::size_t>(arrays.face_indices[0][0])];
            for (const auto& face : arrays.face_indices)
                for (std::int64_t i : face) {
                    b.lo = glm::min(b.lo, arrays.positions[static_cast<std::size_t>(i)]);
                    b.hi = glm::max(b.hi, arrays.positions[static_cast<std::size_t>(i)]);
                }
            tolerance = weld.relative_tolerance * glm::length(b.hi - b.lo);
        }
        WeldMap map = weld_positions(arrays.positions, tolerance);
        mesh.positions = std::move(map.positions);
        remap = std::move(map.remap);
    } else {
        mesh.positions = arrays.positions;
    }
    auto vertex = [&](std::int64_t i) {
        return remap.empty() ? static_cast<std::uint32_t>(i) : remap[static_cast<std::size_t>(i)];
    };

    // Copy, dropping triangles that repeat a vertex (as given, or once welded):
    // they have no area and no three edges, so no scheme can split them.
    std::vector<std::uint32_t> local_kept;
    std::vector<std::uint32_t>& kept = report ? report->kept_faces : local_kept;
    kept.clear();
    detail::reserve_huge(kept, n_faces);
    detail::reserve_huge(mesh.triangles, n_faces);
    std::size_t dropped = 0, first_dropped = 0, collapsed = 0, first_collapsed = 0;
    for (std::size_t f = 0; f < n_faces; ++f) {
        const auto& v = arrays.face_indices[f];
        if (v[0] == v[1] || v[1] == v[2] || v[2] == v[0]) {
            if (dropped++ == 0) first_dropped = f;
            continue;
        }
        const Triangle t{vertex(v[0]), vertex(v[1]), vertex(v[2])};
        if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) {
            if (collapsed++ == 0) first_collapsed = f;
            continue;
        }
        mesh.triangles.push_back(t);
        kept.push_back(static_cast<std::uint32_t>(f));
    }
    // Winding before the corners' normals and uvs exist: its work arrays
    // then do not add to the construction's peak.
    const std::vector<std::uint32_t> reversed =
        mesh.triangles.empty() ? std::vector<std::uint32_t>{}
                               : orient_consistently(mesh, source, warnings);
    if (has_normals) detail::reserve_huge(mesh.corner_normals, 3 * kept.size());
    if (has_uvs) detail::reserve_huge(mesh.corner_uvs, 3 * kept.size());
    auto next_reversed = reversed.begin();
    for (std::size_t t = 0; t < kept.size(); ++t) {
        const std::size_t f = kept[t];
        const bool turned = next_reversed != reversed.end() && *next_reversed == t;
        if (turned) ++next_reversed;
        for (const int c : {0, turned ? 2 : 1, turned ? 1 : 2}) {
            if (has_normals) {
                const auto& ni = arrays.normal_indices.empty() ? arrays.face_indices[f] : arrays.normal_indices[f];
                mesh.corner_normals.push_back(arrays.normals[static_cast<std::size_t>(ni[c])]);
            }
            if (has_uvs) {
                const auto& ui = arrays.uv_indices.empty() ? arrays.face_indices[f] : arrays.uv_indices[f];
                mesh.corner_uvs.push_back(arrays.uvs[static_cast<std::size_t>(ui[c])]);
            }
        }
    }
    if (mesh.triangles.empty()) {
        if (collapsed > 0)
            fail(source, "no faces left: " + std::to_string(collapsed) + " of " +
                             std::to_string(n_faces) +
                             " triangles collapsed when welding coincident vertices" +
                             (dropped > 0 ? ", the others repeat a vertex index" : ""));
        fail(source,
             "no faces left: all " + std::to_string(n_faces) + " triangles repeat a vertex index");
    }
    if (dropped > 0 && warnings)
        warnings->push_back(source + ": dropped " + std::to_string(dropped) +
                            " triangle(s) that repeat a vertex index (first: face " +
                            std::to_string(first_dropped) + ")");
    if (collapsed > 0 && warnings)
        warnings->push_back(source + ": dropped " + std::to_string(collapsed) +
                            " triangle(s) that collapsed when welding coincident vertices " +
                            "(first: face " + std::to_string(first_collapsed) + ")");
    if (report) {
        report->welded_vertices = arrays.positions.size() - mesh.positions.size();
        report->collapsed_triangles = collapsed;
        report->reversed_triangles = reversed;
    }
    return mesh;
}

void validate_mesh(const Mesh& mesh, const std::string& source) {
    if (mesh.triangles.empty()) fail(source, "no faces");
    if (mesh.positions.size() > std::numeric_limits<std::uint32_t>::max())
        fail(source, "too many vertices");
    const std::size_t corners = 3 * mesh.triangles.size();
    if (!mesh.corner_normals.empty() && mesh.corner_normals.size() != corners)
        fail(source, "corner_normals has " + std::to_string(mesh.corner_normals.size()) +
                         " entries, expected 3 per triangle (" + std::to_string(corners) + ")");
    if (!mesh.corner_uvs.empty() && mesh.corner_uvs.size() != corners)
        fail(source, "corner_uvs has " + std::to_string(mesh.corner_uvs.size()) +
                         " entries, expected 3 per triangle (" + std::to_string(corners) + ")");
    detail::check_finite(mesh.positions, "vertex", source);
    detail::check_finite(mesh.corner_normals, "corner normal", source);
    detail::check_finite(mesh.corner_uvs, "corner uv", source);
    const std::size_t n = mesh.positions.size();
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        const Triangle& tri = mesh.triangles[t];
        for (std::uint32_t i : tri)
            if (i >= n)
                fail(source, "triangle " + std::to_string(t) + ": vertex index " +
                                 std::to_string(i) + " out of range (" + std::to_string(n) +
                                 " vertices)");
        if (tri[0] == tri[1] || tri[1] == tri[2] || tri[2] == tri[0])
            fail(source, "triangle " + std::to_string(t) + " repeats a vertex index");
    }
}

Bounds3 mesh_bounds(const Mesh& mesh) {
    Bounds3 b;
    bool first = true;
    for (const Triangle& tri : mesh.triangles)
        for (std::uint32_t i : tri) {
            if (i >= mesh.positions.size()) continue;
            const Vec3& p = mesh.positions[i];
            if (first) {
                b.lo = b.hi = p;
                first = false;
            } else {
                b.lo = glm::min(b.lo, p);
                b.hi = glm::max(b.hi, p);
            }
        }
    return b;
}

}  // namespace subdivtrace
