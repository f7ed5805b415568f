#pragma once
// Tiles (DESIGN.md section 5, "Cost"): when a node first refines, its
// descendants k levels down are built at once from a patch (patch.h) with
// array kernels, and cached as one entry. A node's record is then found in
// its tile by index arithmetic.

#include <cstddef>
#include <memory>
#include <vector>

#include "grid.h"
#include "patch.h"
#include "subdivtrace/hierarchy.h"
#include "subdivtrace/shell.h"

namespace subdivtrace::detail {

/// Levels a tile spans below its root (16 triangles at its deepest level).
/// Deeper tiles amortise their border better but build levels no ray needs
/// (docs/tracer.md measures 2, 3 and 4).
constexpr int k_tile_depth = 2;

/// What a tile build needs to know of the hierarchy.
struct TileContext {
    const BaseTopology& topo;
    SchemeKind scheme;
    ShellKind shell_kind;
    int max_level;
};

/// The records of a node's descendants, levels root.level+1 .. root.level+depth.
class Tile {
public:
    /// `parent_patch`: the last patch of the tile whose deepest level holds
    /// `root`, one level below it (nullptr for a base triangle's tile).
    Tile(const TileContext& ctx, const NodeId& root, const Patch* parent_patch);

    const NodeId& root() const { return root_; }
    int depth() const { return depth_; }
    std::size_t node_count() const { return records_.size(); }
    /// Heap bytes the tile owns.
    std::size_t owned_bytes() const;

    /// The level below its deepest one (its triangles' children plus their
    /// border, not finished), where child tiles start; empty at max_level.
    const Patch& last_patch() const { return last_patch_; }

    /// The record of descendant `id` (root.level < id.level <= root.level + depth).
    const NodeRecord& record(const NodeId& id) const { return records_[index_of(id)]; }

private:
    std::size_t index_of(const NodeId& id) const;

    NodeId root_;
    int depth_ = 0;
    std::vector<NodeRecord> records_;
    Patch last_patch_;
};

/// Root of the tile that holds node `id` (level >= 1).
NodeId tile_root_of(const NodeId& id);
/// Root of the tile whose deepest level holds `root` (a tile root of level >= 1).
NodeId parent_tile_root(const NodeId& root);

/// The level-0 records, one per base triangle, computed over the whole base mesh.
std::vector<NodeRecord> build_root_records(const TileContext& ctx);

/// The node's parent (level >= 1) and its ancestor at `level`.
NodeId parent_of(const NodeId& id);
NodeId ancestor_at(NodeId id, int level);

}  // namespace subdivtrace::detail
