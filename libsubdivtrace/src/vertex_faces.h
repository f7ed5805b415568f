#pragma once
// The triangles around each vertex, in compressed rows: the one adjacency
// that base-mesh connectivity (BaseTopology) and the winding pass (orient.h)
// both walk.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "subdivtrace/mesh.h"

namespace subdivtrace::detail {

/// Position of `v` among t's corners (t holds it).
inline int corner_of(const Triangle& t, std::uint32_t v) { return t[0] == v ? 0 : t[1] == v ? 1 : 2; }

/// The faces around one vertex: a view into VertexFaces' flat arrays (valid
/// while they live), in increasing face order.
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

/// One flat list of faces per vertex (an offset per vertex, 3 entries per
/// face, 4 bytes each); the faces on an edge are those of one endpoint that
/// also hold the other, so edges cost no memory of their own.
class VertexFaces {
public:
    VertexFaces(const std::vector<Triangle>& triangles, std::size_t vertex_count);

    /// The faces that have vertex v as a corner, in increasing order.
    FaceRange faces_of(std::uint32_t v) const {
        return FaceRange(faces_.data() + offset_[v], faces_.data() + offset_[v + 1]);
    }

    /// Calls visit(f) for every face of `triangles` (the ones the rows were
    /// built from) on the edge {u, w}, in increasing order.
    template <class Visit>
    void for_each_face_of_edge(const std::vector<Triangle>& triangles, std::uint32_t u,
                               std::uint32_t w, Visit visit) const {
        // Through the endpoint with fewer faces (next to a high-valence
        // vertex, the other one); both lists ascend.
        const bool through_u = faces_of(u).size() <= faces_of(w).size();
        const std::uint32_t x = through_u ? u : w, y = through_u ? w : u;
        for (std::uint32_t f : faces_of(x)) {
            const Triangle& t = triangles[f];
            if (t[0] == y || t[1] == y || t[2] == y) visit(f);
        }
    }

    std::size_t owned_bytes() const {
        return (offset_.capacity() + faces_.capacity()) * sizeof(std::uint32_t);
    }

private:
    std::vector<std::uint32_t> offset_;  ///< vertex count + 1 entries
    std::vector<std::uint32_t> faces_;   ///< 3 per face
};

}  // namespace subdivtrace::detail
