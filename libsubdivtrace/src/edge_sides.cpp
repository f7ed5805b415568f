// A mesh's triangle sides grouped by edge (edge_sides.h).
#include "edge_sides.h"

#include <algorithm>
#include <tuple>

namespace subdivtrace::detail {

HugeArray<EdgeSide> sorted_edge_sides(const std::vector<Triangle>& triangles,
                                      std::size_t vertex_count) {
    // Bucket starts by lower vertex (count, prefix-sum), then fill: faces
    // ascend within each bucket as they are visited in order.
    HugeArray<std::uint32_t> start(vertex_count + 1, 0);
    for (const Triangle& t : triangles)
        for (int e = 0; e < 3; ++e) ++start[std::min(t[e], t[(e + 1) % 3]) + 1];
    for (std::size_t v = 0; v < vertex_count; ++v) start[v + 1] += start[v];
    HugeArray<EdgeSide> sides(3 * triangles.size());
    {
        HugeArray<std::uint32_t> fill(start.begin(), start.end() - 1);
        for (std::uint32_t f = 0; f < triangles.size(); ++f)
            for (std::uint8_t e = 0; e < 3; ++e) {
                const std::uint32_t u = triangles[f][e], w = triangles[f][(e + 1) % 3];
                sides[fill[std::min(u, w)]++] = {std::min(u, w), std::max(u, w), f, e};
            }
    }
    // Each bucket holds about its vertex's valence.
    for (std::size_t v = 0; v < vertex_count; ++v)
        std::sort(sides.begin() + start[v], sides.begin() + start[v + 1], [](const EdgeSide& x, const EdgeSide& y) {
            return std::tie(x.hi, x.face, x.corner) < std::tie(y.hi, y.face, y.corner);
        });
    return sides;
}

}  // namespace subdivtrace::detail
