#pragma once
// What the mesh writers (write_mesh.cpp, mesh2_text.cpp) read of a mesh: a
// Mesh, or a SubdividedMesh read in place.

#include <string>
#include <vector>

#include "subdivtrace/mesh.h"
#include "subdivtrace/uniform.h"

namespace subdivtrace::io {

/// What the writers read of a mesh: a Mesh, or a SubdividedMesh read in
/// place. Its normals are one per vertex plus the corners that differ, and
/// expanding them to one per corner first (to_mesh) had been two thirds of
/// `subdivtrace subdivide`'s peak at deep levels (1.5 GB of 2.2 GB at level
/// 6 of a 5k-triangle mesh).
struct MeshOut {
    const std::vector<Vec3>& positions;
    const std::vector<Triangle>& triangles;
    const std::vector<Vec2>& corner_uvs;
    const Mesh* mesh = nullptr;
    const SubdividedMesh* sub = nullptr;

    static MeshOut of(const Mesh& m) { return {m.positions, m.triangles, m.corner_uvs, &m, nullptr}; }
    static MeshOut of(const SubdividedMesh& s) { return {s.positions, s.triangles, s.corner_uvs, nullptr, &s}; }
    bool has_normals() const { return mesh ? mesh->has_normals() : !sub->vertex_normals.empty(); }
    bool has_uvs() const { return !corner_uvs.empty(); }
    /// The normal at corner slot 3t + c.
    Vec3 normal(std::size_t slot) const {
        return mesh ? mesh->corner_normals[slot] : sub->corner_normal(slot / 3, static_cast<int>(slot % 3));
    }
};

/// Fails naming `path` if `sub` has no triangle or a value that is not
/// finite. Its triangles come from the subdivision and are valid; its
/// values are checked as a Mesh's are (validate_mesh): a coordinate near
/// the largest double can overflow as it is subdivided.
void validate_subdivided(const SubdividedMesh& sub, const std::string& path);

}  // namespace subdivtrace::io
