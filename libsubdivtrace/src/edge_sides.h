#pragma once
// A mesh's edges as the sides of its triangles, grouped by edge: the one
// edge table that a base level's topology (LevelTopology), creases
// (crease_masks) and the mesh report (analyze_mesh) read, each of which
// used to sort or hash the edges its own way.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "huge_pages.h"
#include "subdivtrace/mesh.h"

namespace subdivtrace::detail {

/// Side `corner` of triangle `face`: its edge from corner `corner` to corner
/// corner + 1, named by its endpoints' indices, lower first.
struct EdgeSide {
    std::uint32_t lo, hi;
    std::uint32_t face;
    std::uint8_t corner;
};

/// Every side of `triangles` in the order (lo, hi, face, corner): the sides
/// of one edge are consecutive, and an edge's first side is that of its
/// lowest face. A counting sort by the lower vertex, then a sort of each
/// vertex's few sides: linear in the mesh, where one sort of all 3n sides
/// took a tenth of a million-triangle surface's construction. Vertex
/// indices must be below `vertex_count`.
HugeArray<EdgeSide> sorted_edge_sides(const std::vector<Triangle>& triangles,
                                      std::size_t vertex_count);

/// Calls visit(first, last) for each edge of `sides` (sorted_edge_sides),
/// [first, last) being its sides, in order.
template <class Visit>
void for_each_edge(const HugeArray<EdgeSide>& sides, Visit visit) {
    for (std::size_t i = 0; i < sides.size();) {
        std::size_t j = i + 1;
        while (j < sides.size() && sides[j].lo == sides[i].lo && sides[j].hi == sides[i].hi) ++j;
        visit(sides.data() + i, sides.data() + j);
        i = j;
    }
}

}  // namespace subdivtrace::detail
