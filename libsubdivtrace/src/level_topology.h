#pragma once
// Connectivity of one level of a mesh held in plain arrays: edges with their
// opposite vertices, ordered vertex rings, and Gouraud normals.

#include <cstdint>
#include <vector>

#include "subdivtrace/mesh.h"
#include "subdivtrace/scheme.h"

namespace subdivtrace {

class LevelTopology {
public:
    struct Edge {
        std::uint32_t a = 0;  ///< as in the first triangle that has the edge
        std::uint32_t b = 0;
        std::uint32_t c = 0;  ///< third vertex of that triangle (interior only)
        std::uint32_t d = 0;  ///< third vertex of the other triangle (interior only)
        std::uint32_t face_count = 0;
        bool interior = false;  ///< exactly two triangles
    };

    LevelTopology(const std::vector<Vec3>& positions, const std::vector<Triangle>& triangles);

    std::uint32_t edge_count() const { return static_cast<std::uint32_t>(edges_.size()); }
    const Edge& edge(std::uint32_t e) const { return edges_[e]; }
    /// Edge i of triangle t runs from corner i to corner (i + 1) % 3.
    std::uint32_t face_edge(std::size_t t, int i) const { return face_edges_[3 * t + i]; }

    /// The ordered ring of v with positions filled in.
    void fill_ring(std::uint32_t v, const std::vector<Vec3>& positions, VertexRing& ring) const;
    /// Position of w in v's ring (0 if absent).
    std::size_t ring_index(std::uint32_t v, std::uint32_t w) const;
    bool ring_closed(std::uint32_t v) const { return ring_closed_[v] != 0; }
    bool ring_regular(std::uint32_t v) const { return ring_regular_[v] != 0; }
    std::size_t valence(std::uint32_t v) const { return ring_offsets_[v + 1] - ring_offsets_[v]; }

private:
    std::vector<Edge> edges_;
    std::vector<std::uint32_t> face_edges_;
    std::vector<std::size_t> ring_offsets_;
    std::vector<std::uint32_t> ring_nbrs_;
    std::vector<std::uint8_t> ring_closed_;
    std::vector<std::uint8_t> ring_regular_;
};

/// Per-vertex angle-weighted Gouraud normals (unit, or zero where no triangle
/// with area touches the vertex).
std::vector<Vec3> gouraud_normals(const std::vector<Vec3>& positions,
                                  const std::vector<Triangle>& triangles);

}  // namespace subdivtrace
