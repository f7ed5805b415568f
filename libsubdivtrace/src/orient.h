#pragma once
// Consistent winding (mesh.h, mesh_from_arrays): every input's triangles are
// turned so that neighbours run their shared edge in opposite directions.
//
// Why: a vertex normal is the angle-weighted sum of its triangles' normals;
// where half of them are wound the other way the sum cancels (POV-Ray's own
// scenes/objects/mesh2.pov has such a cube, whose apex normals came out 0),
// and the normal scheme moves every new point along those normals. mesh2
// itself ignores winding, so users' files do not keep it.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "subdivtrace/mesh.h"

namespace subdivtrace {

struct Orientation {
    /// flipped[t]: triangle t must swap its corners 1 and 2.
    std::vector<std::uint8_t> flipped;
    std::size_t flipped_count = 0;
    /// Manifold edges whose two triangles still run it the same way: the
    /// component is non-orientable (a Moebius strip), no winding agrees.
    std::size_t conflicting_edges = 0;
};

/// Chooses flips over the edges shared by exactly two triangles (boundary and
/// non-manifold edges join nothing). Each connected component keeps the
/// winding of the majority of its triangles (on a tie, its first triangle's),
/// so a consistently wound mesh is never touched. Linear time.
Orientation consistent_orientation(const std::vector<Triangle>& triangles,
                                   std::size_t vertex_count);

}  // namespace subdivtrace
