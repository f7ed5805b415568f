#pragma once
// The base mesh's connectivity as the hierarchy reads it (faces around a
// vertex and on an edge, creases, curves, given normals), in flat arrays, and
// the canonical names of grid points (node_address.h) computed from it.

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "node_address.h"
#include "subdivtrace/mesh.h"
#include "vertex_faces.h"

namespace subdivtrace::detail {

/// Base-mesh connectivity the grid needs: faces around each vertex and the
/// faces on each (unordered) vertex pair. Stored as one flat list of faces per
/// vertex (compressed rows: an offset per vertex, 3 entries per face); the
/// faces on an edge are those of its lower vertex that also hold the upper
/// one, so edges cost no memory of their own.
class BaseTopology {
public:
    explicit BaseTopology(const Mesh& mesh);

    const Mesh& mesh() const { return mesh_; }
    std::size_t face_count() const { return mesh_.triangles.size(); }

    VertexKey canonical(std::uint32_t face, int level, std::uint32_t i, std::uint32_t j) const;

    /// Every (face, i, j) at `level` that names `key` (several on shared
    /// edges and corners), in a fixed order.
    void representations(const VertexKey& key, int level, std::vector<GridPoint>& out) const;

    /// The faces that have base vertex v as a corner, in increasing order.
    FaceRange faces_of_vertex(std::uint32_t v) const { return faces_.faces_of(v); }

    /// Number of base triangles on the edge between base vertices u and w
    /// (0 if they share none).
    std::size_t edge_face_count(std::uint32_t u, std::uint32_t w) const;
    /// The same for a pair that is an edge of the mesh. Where no edge has
    /// more than two triangles, an edge with one has both ends on a curve, so
    /// the faces are counted only there (every new edge point of an open
    /// mesh asks: counting was 1.7% of a render of a modeller's mesh).
    std::size_t faces_on_edge(std::uint32_t u, std::uint32_t w) const {
        if (at_most_two_ && !(on_curve(u) && on_curve(w))) return 2;
        return edge_face_count(u, w);
    }

    /// True if every base edge has exactly two triangles.
    bool closed() const { return closed_; }

    /// True if edge e (corner e to e + 1) of base triangle `face` is a crease (creases.h).
    bool is_crease(std::uint32_t face, int e) const {
        return !crease_mask_.empty() && (crease_mask_[face] >> e & 1u) != 0;
    }
    bool has_creases() const { return !crease_mask_.empty(); }

    /// The mesh's own normal at base vertex v in base triangle `face`,
    /// normalised (zero if the mesh has none, or v is not a corner of face).
    /// Kept compactly (one per vertex, plus the corners that differ), so the
    /// mesh's corner normals need not outlive construction.
    Vec3 given_normal(std::uint32_t face, std::uint32_t v) const;
    bool has_given_normals() const { return !given_vertex_.empty(); }
    /// True if base vertex v touches a boundary edge (one triangle) or a
    /// crease: only such vertices, and edge points between two of them, can
    /// lie on a curve of the subdivided surface.
    bool on_curve(std::uint32_t v) const { return !on_curve_.empty() && on_curve_[v] != 0; }

    /// Heap bytes the topology holds (its arrays; the mesh is the caller's).
    std::size_t owned_bytes() const {
        return faces_.owned_bytes() + crease_mask_.capacity() +
               on_curve_.capacity() + given_vertex_.capacity() * sizeof(Vec3) +
               given_split_.capacity() * sizeof(GivenCorner);
    }

private:
    /// Calls visit(f) for every face on the edge {u, w}, in increasing order.
    template <class Visit>
    void for_each_face_of_edge(std::uint32_t u, std::uint32_t w, Visit visit) const {
        faces_.for_each_face_of_edge(mesh_.triangles, u, w, visit);
    }

    const Mesh& mesh_;
    VertexFaces faces_;
    bool closed_ = true;
    bool at_most_two_ = false;  ///< no edge has more than two triangles (set once on_curve_ is)
    std::vector<std::uint8_t> crease_mask_;  ///< empty when the mesh has no crease
    std::vector<std::uint8_t> on_curve_;  ///< empty when nothing is on a curve
    std::vector<Vec3> given_vertex_;      ///< a vertex's first corner's normal
    struct GivenCorner {
        std::uint32_t slot;  ///< 3 face + corner, ascending
        Vec3 normal;
    };
    std::vector<GivenCorner> given_split_;  ///< corners whose normal is not their vertex's
};

}  // namespace subdivtrace::detail
