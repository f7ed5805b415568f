#pragma once
// The record of a patch's triangle (NodeRecord): its corners, normals, the
// shading normals one level down, and the shell bounding its descendants.
// Tiles make them for their levels, RootRecords for the base level.

#include <cstdint>
#include <vector>

#include "patch.h"
#include "subdivtrace/hierarchy.h"
#include "tile.h"

namespace subdivtrace::detail {

/// The shading normals one level down already computed for a patch: a
/// vertex's is the same for every triangle at it (where it has one sector),
/// an edge midpoint's for both triangles on the edge (where they continue
/// one fan), and each costs an angle per triangle around it, so the records
/// of a level share them instead of each computing its own.
struct ShadingMemo {
    std::vector<Vec3> corner;
    std::vector<std::uint8_t> corner_done;
    std::vector<Vec3> edge;
    std::vector<std::uint8_t> edge_done;

    ShadingMemo() = default;
    explicit ShadingMemo(const Patch& p) { reset(p); }
    /// Empty for patch p (keeps its blocks for reuse).
    void reset(const Patch& p) {
        corner.assign(p.verts.size(), Vec3(0.0));
        corner_done.assign(p.verts.size(), 0);
        edge.assign(p.edges.size(), Vec3(0.0));
        edge_done.assign(p.edges.size(), 0);
    }
};

/// Record of triangle t of patch p (level L), with `next` the patch p
/// subdivided once (untrimmed; only read when L < max_level).
NodeRecord make_record(const TileContext& ctx, const Patch& p, const Patch* next, std::uint32_t t,
                       ShadingMemo& memo);

}  // namespace subdivtrace::detail
