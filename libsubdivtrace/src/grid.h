#pragma once
// Addressing of the uniformly subdivided mesh without building it. At level L
// every base triangle f carries a triangular grid of resolution N = 2^L: point
// (i, j) has barycentric weights (N - i - j, i, j) on f's corners. A grid point
// on a base edge or corner is shared with the neighbouring triangles, so each
// point has one canonical VertexKey, the same whichever triangle names it.

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "subdivtrace/mesh.h"

namespace subdivtrace::detail {

/// Canonical name of a vertex of the uniform hierarchy, level-independent: the
/// level it is stored with is its birth level (coordinates reduced while even).
struct VertexKey {
    enum Kind : std::uint8_t { base_vertex = 0, edge_point = 1, face_point = 2 };
    std::uint8_t kind = base_vertex;
    std::uint8_t level = 0;  ///< birth level
    std::uint32_t a = 0;     ///< base vertex | lower edge vertex | base face
    std::uint32_t b = 0;     ///< -           | upper edge vertex | grid i
    std::uint32_t c = 0;     ///< -           | weight on upper   | grid j

    bool operator==(const VertexKey& o) const {
        return kind == o.kind && level == o.level && a == o.a && b == o.b && c == o.c;
    }
    bool operator!=(const VertexKey& o) const { return !(*this == o); }
};

inline std::uint64_t mix64(std::uint64_t x) {
    x ^= x >> 33;
    x *= 0xff51afd7ed558ccdULL;
    x ^= x >> 33;
    x *= 0xc4ceb9fe1a85ec53ULL;
    x ^= x >> 33;
    return x;
}

struct VertexKeyHash {
    std::size_t operator()(const VertexKey& k) const {
        const std::uint64_t h0 = (std::uint64_t{k.kind} << 56) ^ (std::uint64_t{k.level} << 48) ^ k.a;
        const std::uint64_t h1 = (std::uint64_t{k.b} << 32) ^ k.c;
        return static_cast<std::size_t>(mix64(h0 ^ mix64(h1)));
    }
};

/// A grid point of base triangle `face` at `level`.
struct GridPoint {
    std::uint32_t face = 0;
    std::uint32_t i = 0;
    std::uint32_t j = 0;
};

/// The faces around one base vertex: a view into BaseTopology's flat arrays
/// (valid while the topology lives), in increasing face order.
class FaceRange {
public:
    FaceRange(const std::uint32_t* begin, const std::uint32_t* end) : begin_(begin), end_(end) {}
    const std::uint32_t* begin() const { return begin_; }
    const std::uint32_t* end() const { return end_; }
    std::size_t size() const { return static_cast<std::size_t>(end_ - begin_); }
    bool empty() const { return begin_ == end_; }
    std::uint32_t operator[](std::size_t k) const { return begin_[k]; }

private:
    const std::uint32_t* begin_;
    const std::uint32_t* end_;
};

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
    FaceRange faces_of_vertex(std::uint32_t v) const {
        return FaceRange(vertex_faces_.data() + vertex_offset_[v],
                         vertex_faces_.data() + vertex_offset_[v + 1]);
    }

    /// Number of base triangles on the edge between base vertices u and w.
    std::size_t edge_face_count(std::uint32_t u, std::uint32_t w) const;

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
        return vertex_offset_.capacity() * sizeof(std::uint32_t) +
               vertex_faces_.capacity() * sizeof(std::uint32_t) + crease_mask_.capacity() +
               on_curve_.capacity() + given_vertex_.capacity() * sizeof(Vec3) +
               given_split_.capacity() * sizeof(GivenCorner);
    }

private:
    /// Calls visit(f) for every face on the edge {u, w}, in increasing order.
    template <class Visit>
    void for_each_face_of_edge(std::uint32_t u, std::uint32_t w, Visit visit) const {
        // Through the endpoint with fewer faces; both lists ascend.
        const bool through_u = faces_of_vertex(u).size() <= faces_of_vertex(w).size();
        const std::uint32_t x = through_u ? u : w, y = through_u ? w : u;
        for (std::uint32_t f : faces_of_vertex(x)) {
            const Triangle& t = mesh_.triangles[f];
            if (t[0] == y || t[1] == y || t[2] == y) visit(f);
        }
    }

    const Mesh& mesh_;
    std::vector<std::uint32_t> vertex_offset_;  ///< vertex count + 1 entries
    std::vector<std::uint32_t> vertex_faces_;   ///< 3 per face
    bool closed_ = true;
    std::vector<std::uint8_t> crease_mask_;  ///< empty when the mesh has no crease
    std::vector<std::uint8_t> on_curve_;  ///< empty when nothing is on a curve
    std::vector<Vec3> given_vertex_;      ///< a vertex's first corner's normal
    struct GivenCorner {
        std::uint32_t slot;  ///< 3 face + corner, ascending
        Vec3 normal;
    };
    std::vector<GivenCorner> given_split_;  ///< corners whose normal is not their vertex's
};

/// The grid triangles of resolution n that have grid point (i, j) as a
/// corner, each rotated so that point comes first (counter-clockwise): calls
/// out(i1, j1, i2, j2) with the other two corners. "Up" triangle (x, y) has
/// corners (x,y) (x+1,y) (x,y+1); "down" triangle (x, y) has (x+1,y) (x+1,y+1) (x,y+1).
template <class Out>
void for_each_incident_grid_triangle(std::uint32_t n, std::uint32_t i, std::uint32_t j, Out out) {
    const long N = n, I = i, J = j;
    auto up_ok = [&](long x, long y) { return x >= 0 && y >= 0 && x + y <= N - 1; };
    auto down_ok = [&](long x, long y) { return x >= 0 && y >= 0 && x + y <= N - 2; };
    auto emit = [&](long i1, long j1, long i2, long j2) {
        out(static_cast<std::uint32_t>(i1), static_cast<std::uint32_t>(j1),
            static_cast<std::uint32_t>(i2), static_cast<std::uint32_t>(j2));
    };
    // Counter-clockwise around (i, j), starting towards +i.
    if (up_ok(I, J)) emit(I + 1, J, I, J + 1);              // up(i, j)
    if (down_ok(I - 1, J)) emit(I, J + 1, I - 1, J + 1);    // down(i-1, j)
    if (up_ok(I - 1, J)) emit(I - 1, J + 1, I - 1, J);      // up(i-1, j)
    if (down_ok(I - 1, J - 1)) emit(I - 1, J, I, J - 1);    // down(i-1, j-1)
    if (up_ok(I, J - 1)) emit(I, J - 1, I + 1, J - 1);      // up(i, j-1)
    if (down_ok(I, J - 1)) emit(I + 1, J - 1, I + 1, J);    // down(i, j-1)
}

}  // namespace subdivtrace::detail
