#pragma once
/// \file uniform.h
/// Uniform subdivision: every triangle split 1-to-4, `levels` times. The
/// reference the adaptive hierarchy must equal, and the baseline it is timed
/// against.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "subdivtrace/mesh.h"
#include "subdivtrace/scheme.h"

namespace subdivtrace {

/// A uniformly subdivided mesh. Triangle t of level k has children
/// 4t .. 4t+3 at level k+1, with corners (for parent corners A, B, C and edge
/// points mAB, mBC, mCA): (A, mAB, mCA), (mAB, B, mBC), (mCA, mBC, C),
/// and the middle one (mAB, mBC, mCA), or (mCA, mAB, mBC) when the parent is
/// an inverted ("down") triangle of its base triangle's grid, so that corner order matches
/// the hierarchy's grid (hierarchy.h). Triangle t comes from base triangle
/// t / 4^levels.
struct SubdividedMesh {
    int levels = 0;
    std::vector<Vec3> positions;
    std::vector<Triangle> triangles;
    /// The scheme's normal at each corner of the final level
    /// (corner_normal()): the angle-weighted Gouraud normal of the vertex over
    /// its sector (the triangles around it between creases), or for the
    /// normal scheme at a base vertex the mesh's given normal
    /// (docs/schemes.md, "Given normals"). Kept once per vertex (its first
    /// corner's, in slot order), plus the corners whose normal differs: those
    /// across a crease, or with given normals of their own.
    std::vector<Vec3> vertex_normals;
    struct SplitCorner {
        std::uint32_t slot;  ///< 3t + c, ascending
        Vec3 normal;
    };
    std::vector<SplitCorner> split_corners;

    /// The normal at corner c of triangle t.
    Vec3 corner_normal(std::size_t t, int c) const;
    /// Every corner's normal, 3 per triangle (what a Mesh holds).
    std::vector<Vec3> corner_normals() const;
    /// Heap bytes of the normals (vertex_normals and split_corners).
    std::size_t normal_bytes() const {
        return vertex_normals.capacity() * sizeof(Vec3) + split_corners.capacity() * sizeof(SplitCorner);
    }
    /// Per triangle, bit e set if its edge e (corner e to e + 1) is a crease
    /// (a half of a base crease edge); empty if the mesh has none.
    std::vector<std::uint8_t> crease_masks;
    /// Per-corner UVs, interpolated from the base triangle's corner UVs
    /// (empty if the mesh had none).
    std::vector<Vec2> corner_uvs;
    /// Base triangle of each triangle.
    std::vector<std::uint32_t> base_face;
};

/// Subdivides `mesh` uniformly. levels >= 0; throws std::invalid_argument if
/// levels exceeds k_max_uniform_levels or the result would not fit in 32-bit indices.
SubdividedMesh subdivide_uniform(const Mesh& mesh, SchemeKind scheme, int levels);

constexpr int k_max_uniform_levels = 10;

/// Moves every vertex to its limit point (Loop: loop_limit_point of its
/// final-level ring; interpolating schemes: unchanged, their vertices lie on
/// the limit surface). Normals are left as they are. This is what the
/// adaptive tracer draws at a leaf of the same level.
void push_to_limit(SubdividedMesh& sub, SchemeKind scheme);

/// Converts back to a plain Mesh (with the scheme's corner normals).
Mesh to_mesh(const SubdividedMesh& sub);
/// The same, taking the positions, triangles and UVs instead of copying
/// them, and freeing the per-vertex normals once the corners have theirs:
/// at a deep level the copies had been half of a conversion's peak memory.
Mesh to_mesh(SubdividedMesh&& sub);

}  // namespace subdivtrace
