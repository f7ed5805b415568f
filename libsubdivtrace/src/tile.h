#pragma once
// Tiles (DESIGN.md section 5, "Cost"): when a node first refines, its
// descendants k levels down are built at once from a patch (patch.h) with
// array kernels, and cached as one entry. A node's record is then found in
// its tile by index arithmetic.

#include <array>
#include <atomic>
#include <cstddef>
#include <mutex>
#include <memory>
#include <vector>

#include "base_topology.h"
#include "node_shell.h"
#include "patch.h"
#include "subdivtrace/hierarchy.h"
#include "subdivtrace/shell.h"

namespace subdivtrace::detail {

/// Levels a tile spans below its root (64 triangles at its deepest level).
/// Deeper tiles amortise their border better; levels are built on demand,
/// so no ray pays for levels below what it needs (docs/tracer.md measures 2-4).
constexpr int k_tile_depth = 3;

class RootRecords;
struct ShadingMemo;

/// What a tile build needs to know of the hierarchy.
struct TileContext {
    const BaseTopology& topo;
    SchemeKind scheme;
    ShellKind shell_kind;
    int max_level;
    /// Running count of node records built (for statistics).
    std::atomic<std::uint64_t>* records_built;
    /// Nanoseconds spent building tiles' levels and frontiers, summed over
    /// threads (for statistics; not time waiting for another thread).
    std::atomic<std::uint64_t>* build_ns;
    /// The base level's records once they are built: a base triangle's tile
    /// takes its level-0 normals from them instead of recomputing them.
    const RootRecords* roots = nullptr;
};

/// The first level below a chunk of base triangles (face_chunks.h), computed
/// once for all their tiles: the chunk's level-1 triangles with their border,
/// finished, and the level-2 points their records read. Each tile of the
/// chunk takes its records and its frontier from it, with the same bits it
/// would compute alone (every value is summed in canonical order).
class RootChunk {
public:
    /// `faces`: `count` base triangles, ascending.
    RootChunk(const TileContext& ctx, const std::uint32_t* faces, std::size_t count);
    ~RootChunk();
    RootChunk(const RootChunk&) = delete;
    RootChunk& operator=(const RootChunk&) = delete;
    /// Call once every tile of the chunk is built and before another thread
    /// can see them: their frontiers share the level-1 patch from now on,
    /// without rings and edges.
    void share();

private:
    friend class Tile;
    std::shared_ptr<Patch> level1_;
    std::size_t faces_ = 0;
    Patch next_;
    std::unique_ptr<ShadingMemo> memo_;
};

/// One level of a tile: vertex values on the root's sub-grid of resolution
/// n = 2^j ((n+1)(n+2)/2 points) and a shell per triangle (n^2).
struct TileLevel {
    std::vector<Vec3> position;
    std::vector<Vec3> normal;
    std::vector<Vec3> draw;  ///< Loop only (interpolating schemes draw at position)
    std::vector<glm::vec3> shading;     ///< NodeRecord::shading_normal (a ray only reads it)
    std::vector<float> displacement;    ///< NodeRecord::displacement, rounded up
    /// NodeRecord::edge_normal once per grid edge: by the edge's direction
    /// (along x, along y, the diagonal), at its first grid point.
    std::array<std::vector<glm::vec3>, 3> edge_normal;
    std::vector<CompactShell> shells;
};

/// The records of a node's descendants, levels root.level+1 .. root.level+depth.
/// Levels are built on first use (the first at construction): a ray that
/// stops one level below the root pays for that level only (and the next
/// level's points around it, not that level's topology).
class Tile {
public:
    /// A tile below a tile: `parent_patch` is the last patch of the tile
    /// whose deepest level holds `root` (level >= 1), one level below it.
    /// `ctx` must outlive the tile.
    Tile(const TileContext& ctx, const NodeId& root, const Patch& parent_patch);
    /// A base triangle's tile (`root` a level-0 node of one of `chunk`'s faces).
    Tile(const TileContext& ctx, const NodeId& root, RootChunk& chunk);


    /// The record of descendant `id` (root.level < id.level <= root.level + depth),
    /// building its level first if needed. Thread-safe.
    NodeRecord record(const NodeId& id) const {
        const int j = id.level - root_.level;
        if (ready_.load(std::memory_order_acquire) < j) ensure_level(j);
        return assemble(levels_[j - 1], id);
    }

    /// The records of the four children of `parent` (whose children are in
    /// this tile), in child_of order.
    void children(const NodeId& parent, std::array<NodeRecord, 4>& out) const;

    /// The level below its deepest one (its triangles' children plus their
    /// border, not finished), where child tiles start; builds every level
    /// first. Empty at max_level.
    const Patch& last_patch() const;

    /// What the cache charges for the tile: its size with every level built,
    /// the patch it keeps counted as twice the first level's (the patch
    /// grows with the levels; most tiles never build past their first).
    std::size_t bytes_when_complete() const;

private:
    bool in_tile(const NodeId& id) const;
    std::size_t index_in_level(const NodeId& id) const;
    std::size_t vertex_index(const NodeId& id, std::uint32_t gi, std::uint32_t gj) const;
    using GridPoint = std::array<std::uint32_t, 2>;
    /// Where TileLevel::edge_normal keeps the edge from corner e to e + 1 of
    /// `id`, or the edge between grid points p and q of id's level.
    std::pair<int, std::size_t> edge_slot(const NodeId& id, int e) const;
    std::pair<int, std::size_t> edge_slot(const NodeId& id, const GridPoint& p,
                                          const GridPoint& q) const;
    NodeRecord assemble(const TileLevel& level, const NodeId& id) const;
    void build_level(int j);
    /// Level j's records (levels_[j - 1]) from its patch `q` (finished, the
    /// tile's triangles flagged in `in_this_tile`) and the next level's
    /// points around them.
    void fill_level(int j, Patch& q, const Patch& next, ShadingMemo& memo,
                    const std::vector<bool>& in_this_tile);
    void ensure_level(int j) const;
    /// Splits the frontier (the last built level) into the next level's
    /// tile triangles and their border.
    void advance_frontier();

    const TileContext* ctx_;
    NodeId root_;
    int depth_ = 0;
    std::vector<TileLevel> levels_;
    Vec3 origin_{0.0};  ///< shells are stored relative to it
    /// The deepest level built (without rings and edges), or once
    /// last_patch() was asked for, the level below the tile.
    Patch frontier_;
    /// A base triangle's tile starts with its chunk's level-1 patch as its
    /// frontier, shared with the chunk's other tiles (most never go deeper),
    /// and cuts its own from it when it does.
    std::shared_ptr<const Patch> shared_frontier_;
    std::size_t shared_by_ = 1;  ///< tiles sharing it
    mutable std::mutex mutex_;
    mutable std::atomic<int> ready_{0};
    mutable std::atomic<bool> last_ready_{false};
};

/// Root of the tile that holds node `id` (level >= 1).
NodeId tile_root_of(const NodeId& id);
/// Root of the tile whose deepest level holds `root` (a tile root of level >= 1).
NodeId parent_tile_root(const NodeId& root);

}  // namespace subdivtrace::detail
