#pragma once
/// \file mesh.h
/// The validated triangle mesh every other part of the library starts from.

#include <array>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace subdivtrace {

using Vec3 = glm::dvec3;
using Vec2 = glm::dvec2;
using Triangle = std::array<std::uint32_t, 3>;

/// Bad input: the message always reads "<source>: <reason>" (source is a file
/// name, or a label such as "mesh2" for arrays handed over by POV-Ray).
class MeshError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// An indexed triangle mesh in double precision.
///
/// Invariants after validation (see validate_mesh): at least one triangle, every
/// index in range, no triangle repeats a vertex index, every coordinate finite.
/// Attributes are per corner (3 per triangle), like POV-Ray's mesh2 with
/// normal_indices / uv_indices, so seams and creases survive.
struct Mesh {
    std::vector<Vec3> positions;
    std::vector<Triangle> triangles;
    /// Empty, or 3 entries per triangle (corner 0, 1, 2 of triangle t at 3t..3t+2).
    std::vector<Vec3> corner_normals;
    /// Empty, or 3 entries per triangle.
    std::vector<Vec2> corner_uvs;

    bool has_normals() const { return !corner_normals.empty(); }
    bool has_uvs() const { return !corner_uvs.empty(); }
};

/// Raw arrays as a parser (POV-Ray's mesh2) hands them over. Normals and UVs are
/// optional; each has its own index list (empty = same indices as the faces).
struct MeshArrays {
    std::vector<Vec3> positions;
    std::vector<Vec3> normals;
    std::vector<Vec2> uvs;
    std::vector<std::array<std::int64_t, 3>> face_indices;
    std::vector<std::array<std::int64_t, 3>> normal_indices;
    std::vector<std::array<std::int64_t, 3>> uv_indices;
};

/// How vertices with the same position become one vertex of the topology when
/// a Mesh is built (mesh_from_arrays, and so every reader of mesh_io.h).
/// Exporters write a vertex once per patch, UV island or hard edge; without
/// welding, a subdivision surface tears apart along those seams. Each face
/// corner keeps its own normal and UV, so UV seams and split normals survive.
struct WeldOptions {
    /// Weld at all. false keeps the vertices as given (separate sheets stay
    /// separate, an STL file stays a triangle soup).
    bool enabled = true;
    /// 0 = only bit-identical positions (-0 equals +0) are welded. Greater than
    /// 0: a vertex joins the first earlier vertex within relative_tolerance
    /// times the bounding-box diagonal of the used positions (for exporters
    /// that round). Must be finite and >= 0.
    double relative_tolerance = 0.0;
};

/// What building the Mesh did to the input (welding, dropped and turned
/// triangles), for reports (`subdivtrace info`) and callers with per-face data.
struct WeldReport {
    /// Input vertices that were merged into an earlier one (input count minus
    /// the count of the built Mesh).
    std::size_t welded_vertices = 0;
    /// Triangles dropped because welding made two of their corners one vertex.
    std::size_t collapsed_triangles = 0;
    /// The input face each triangle of the built Mesh came from, in order
    /// (faces that repeat a vertex or collapse when welded are not there): a
    /// caller keeping per-face data of its own (mesh2's texture indices)
    /// follows the library's triangles with it.
    std::vector<std::uint32_t> kept_faces;
    /// Triangles of the built Mesh (ascending) whose corners 1 and 2 were
    /// swapped, with their normals and UVs, so that every two triangles along
    /// an edge run it in opposite directions: mesh2 and most file formats do
    /// not care about winding, the surface's normals do. Each connected part
    /// keeps the winding most of its triangles have.
    std::vector<std::uint32_t> reversed_triangles;
};

/// Builds a Mesh from raw arrays, welds coincident vertices (`weld`) and
/// validates it. Throws MeshError naming `source` on out-of-range indices,
/// non-finite values, size mismatches, a bad tolerance or an empty face list.
/// Triangles that repeat a vertex index, in the input or after welding, are
/// dropped with a warning that counts them (they have no area and no edges to
/// subdivide). Welded vertices take the position of their first occurrence
/// and are numbered in order of first appearance; unused input vertices are
/// kept (welded like the others). Triangles keep their order, and their
/// corner normals and UVs are the input's, exactly, except that triangles
/// wound against their neighbours are turned (WeldReport::reversed_triangles,
/// with a warning). `report` (optional) receives the counts.
Mesh mesh_from_arrays(const MeshArrays& arrays, const std::string& source,
                      std::vector<std::string>* warnings = nullptr,
                      const WeldOptions& weld = {}, WeldReport* report = nullptr);

/// Checks the invariants listed on Mesh; throws MeshError naming `source`.
void validate_mesh(const Mesh& mesh, const std::string& source);

/// Axis-aligned bounds of the positions that triangles use.
struct Bounds3 {
    Vec3 lo{0.0};
    Vec3 hi{0.0};
};
Bounds3 mesh_bounds(const Mesh& mesh);

}  // namespace subdivtrace
