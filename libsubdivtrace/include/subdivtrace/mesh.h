#pragma once
/// \file mesh.h
/// The validated triangle mesh every other part of the library starts from.

#include <array>
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

/// Builds a Mesh from raw arrays and validates it. Throws MeshError naming
/// `source` on out-of-range indices, non-finite values, size mismatches or an
/// empty face list. Triangles that repeat a vertex index are dropped with a
/// warning (they have no area and no edges to subdivide).
Mesh mesh_from_arrays(const MeshArrays& arrays, const std::string& source,
                      std::vector<std::string>* warnings = nullptr);

/// Checks the invariants listed on Mesh; throws MeshError naming `source`.
void validate_mesh(const Mesh& mesh, const std::string& source);

/// Axis-aligned bounds of the positions that triangles use.
struct Bounds3 {
    Vec3 lo{0.0};
    Vec3 hi{0.0};
};
Bounds3 mesh_bounds(const Mesh& mesh);

}  // namespace subdivtrace
