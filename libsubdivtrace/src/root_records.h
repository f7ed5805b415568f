#pragma once
// The base level's records (one per base triangle), computed once for the
// whole mesh when a surface is built.

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include <glm/vec3.hpp>

#include "patch.h"
#include "subdivtrace/hierarchy.h"
#include "subdivtrace/shell.h"
#include "tile.h"

namespace subdivtrace::detail {

/// The level-0 records, one per base triangle, computed over the whole base
/// mesh once; kept as compact shells plus per-vertex normals and drawn positions.
class RootRecords {
public:
    explicit RootRecords(const TileContext& ctx);
    /// Base triangle `face`'s record; without `normals`, its shading and
    /// edge-midpoint normals are left zero (Hierarchy::Part::geometry);
    /// without `with_shell`, its shell is left empty (Part::corners).
    NodeRecord record(std::uint32_t face, bool normals = true, bool with_shell = true) const;
    /// Its shell alone (record(face).shell).
    Shell shell(std::uint32_t face) const { return shells_[face].expand(mesh_->positions[mesh_->triangles[face][0]]); }
    /// Gives the level-0 patch `p` (finished) the normals of its vertices
    /// with whole rings: the same bits ensure_normal would compute (both sum
    /// the ring in canonical order), once per mesh instead of once per tile.
    void lend_normals(Patch& p) const;
    std::size_t owned_bytes() const;

private:
    /// The normal at corner c of base triangle `face`, of its record.
    Vec3 corner_normal(std::uint32_t face, int c) const;
    const Mesh* mesh_;
    std::vector<Vec3> normal_;  ///< per base vertex
    std::vector<Vec3> draw_;    ///< Loop only
    std::vector<glm::vec3> shading_;  ///< per base vertex
    std::vector<float> displacement_;  ///< per base vertex
    std::vector<glm::vec3> edge_normal_;      ///< per base triangle's edge (3f + e)
    bool linear_shading_ = false;  ///< given normals (normal scheme), or max_level 0
    std::vector<CompactShell> shells_;
    /// Corners (slot 3f + c, ascending) whose normals are not their vertex's,
    /// on the far side of a crease.
    struct SplitCorner {
        std::uint32_t slot;
        Vec3 normal;
        glm::vec3 shading;
    };
    std::vector<SplitCorner> split_corners_;
    /// The split corners of base triangle `face` (its slots), ascending.
    std::pair<const SplitCorner*, const SplitCorner*> splits_of(std::uint32_t face) const;

    /// What one chunk of base triangles leaves to be merged in slot order.
    struct ChunkCorners {
        std::vector<SplitCorner> split;     ///< compared within the chunk: they differ
        std::vector<SplitCorner> deferred;  ///< vertex's first corner in an earlier chunk
        bool linear_shading = false;
    };
    /// Records of base triangles [first, last): shells and edge normals, the
    /// values of vertices whose lowest face is among them.
    void build_chunk(const TileContext& ctx, std::size_t first, std::size_t last,
                     BasePatchScratch& scratch, ChunkCorners& out);
};

}  // namespace subdivtrace::detail
