// Faces around each vertex in compressed rows (vertex_faces.h).
#include "vertex_faces.h"

namespace subdivtrace::detail {

VertexFaces::VertexFaces(const std::vector<Triangle>& triangles, std::size_t vertex_count)
    : offset_(vertex_count + 1, 0), faces_(3 * triangles.size()) {
    // Count, prefix-sum, fill: faces land in increasing order per vertex, and
    // the arrays are allocated once at their final size.
    for (const Triangle& t : triangles)
        for (std::uint32_t v : t) ++offset_[v + 1];
    for (std::size_t v = 0; v < vertex_count; ++v) offset_[v + 1] += offset_[v];
    std::vector<std::uint32_t> fill(offset_.begin(), offset_.end() - 1);
    for (std::uint32_t f = 0; f < triangles.size(); ++f)
        for (std::uint32_t v : triangles[f]) faces_[fill[v]++] = f;
}

}  // namespace subdivtrace::detail
