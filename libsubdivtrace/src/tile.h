#pragma once
// Tiles (DESIGN.md section 5, "Cost"): when a node first refines, its
// descendants k levels down are built at once from a patch (patch.h) with
// array kernels, and cached as one entry. A node's record is then found in
// its tile by index arithmetic.

#include <array>
#include <atomic>
#include <cstddef>
#include <cstring>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "base_topology.h"
#include "node_shell.h"
#include "octahedral_normal.h"
#include "patch.h"
#include "spin_lock.h"
#include "subdivtrace/hierarchy.h"
#include "subdivtrace/shell.h"

namespace subdivtrace::detail {

/// Levels a tile spans below its root (64 triangles at its deepest level).
/// Deeper tiles amortise their border better; levels are built on demand,
/// so no ray pays for levels below what it needs (docs/tracer.md measures 2-4).
constexpr int k_tile_depth = 3;

class RootRecords;
class Tile;
struct ShadingMemo;

/// What a tile build needs to know of the hierarchy.
struct TileContext {
    const BaseTopology& topo;
    SchemeRules scheme;
    ShellKind shell_kind;
    int max_level;
    /// Running count of node records built (for statistics).
    std::atomic<std::uint64_t>* records_built;
    /// Nanoseconds spent building tiles' levels and the bands they start
    /// from, summed over threads (for statistics; not time waiting for another thread).
    std::atomic<std::uint64_t>* build_ns;
    /// The base level's records once they are built: a base triangle's tile
    /// takes its level-0 normals from them instead of recomputing them.
    const RootRecords* roots = nullptr;
    /// Told when a tile grows or shrinks (a level built on first use, the
    /// patch its child tiles start from, kept or given up), with its
    /// bytes_held() after, so the cache charges what tiles hold rather than
    /// what they might.
    std::function<void(const Tile& tile, const NodeId& root, std::size_t bytes)> resized;
    /// Where tile root `root` (level >= 1) builds its later levels from,
    /// as it keeps no band between levels: its first level with its border,
    /// cut from the level below its parent's deepest where this thread still
    /// has it (band_of_roots), or else the parent's band around the root at
    /// the root's level (Tile::band_of_child). Neither finished.
    std::function<Patch(const NodeId& root)> child_start;
    /// Base triangle `face`'s level 1 with its border, not finished, cut
    /// from a level of its chunk where one is kept: the same triangles and
    /// bits as chunk_level of the face alone, where its tile's later levels
    /// start otherwise (Tile::band_at). Unset or empty: that.
    std::function<std::optional<Patch>(std::uint32_t face)> base_start;
};

/// The level below a parent tile's deepest one (Tile::below_deepest: its
/// triangles' children and their border, with incident lists), as a thread
/// keeps it for the parent's child tiles (hierarchy.cpp). Their later
/// levels start from bands cut from it (band_of_roots); their first levels
/// are its own triangles, so it is finished once (once a few tile groups
/// have started from it, hierarchy.cpp's BelowParents::worth_finishing;
/// the first ones cut their own band), and each child tile then computes
/// only the next level's points around its triangles that no sibling computed before, and
/// shares the siblings' normals (every value is summed in canonical order,
/// so the bits are those of the child's band finished alone). Building
/// each child tile from its own band finished 31 bands of about 50
/// triangles per parent in the blob5k close-up, where the parent's level
/// has about 400, and computed each border vertex's normals once per band.
class LevelBelow {
public:
    /// `below`: a level below a parent tile or a chunk's level 1 (with
    /// incident lists, for band_of_roots), or a band cut from either.
    explicit LevelBelow(Patch below);
    ~LevelBelow();
    LevelBelow(const LevelBelow&) = delete;
    LevelBelow& operator=(const LevelBelow&) = delete;
    /// The level, unfinished until a tile group starts from it.
    const Patch& patch() const { return level_; }
    /// Heap bytes held (it grows as child tiles are built from it).
    std::size_t owned_bytes() const;
    /// Whether a tile group has finished it (and it holds what that derived).
    bool finished() const { return finished_; }
    /// Frees what finishing derived (the next tile group finishes it
    /// again, with the same bits): finished, it holds about 4x its bytes.
    void unfinish();

private:
    friend class TileGroup;
    /// Finishes the level if it is not yet, and computes the next level's
    /// points around the triangles `tris` (ascending) not computed yet.
    void prepare(const TileContext& ctx, const std::vector<std::uint32_t>& tris);
    Patch level_;
    bool finished_ = false;
    Patch next_;
    Flags next_done_;  ///< per point of next_: computed
    std::unique_ptr<ShadingMemo> memo_;
};

/// The first level of a group of tiles: a LevelBelow, finished (or the
/// group's own band cut from one), and the next level's points their records
/// read. Each tile takes its records from it, with the same bits it would
/// compute alone (every value is summed in canonical order): a lone tile is
/// a group of one.
class TileGroup {
public:
    /// Tiles rooted at `roots`: base triangles of the chunk whose
    /// chunk_level() `below` holds, or nodes of the deepest level of the tile
    /// whose below_deepest() it holds (one face and level). `below` must
    /// outlive the group.
    TileGroup(const TileContext& ctx, LevelBelow& below, const std::vector<NodeId>& roots);
    TileGroup(const TileGroup&) = delete;
    TileGroup& operator=(const TileGroup&) = delete;

private:
    friend class Tile;
    /// The triangles of the level in tile `root` (ascending).
    std::vector<std::uint32_t> triangles_of(const NodeId& root) const;
    /// The LevelBelow's level, the next level's points and the shading memo.
    Patch* level_ = nullptr;
    const Patch* next_ = nullptr;
    ShadingMemo* memo_ = nullptr;
};

/// Level 1 of the `count` base faces at `faces` (ascending) with their
/// border, with incident lists, not finished: where their tiles start, as
/// child tiles start from the level below their parent (a LevelBelow). A
/// chunk of neighbouring faces (face_chunks.h) shares one: its level-0
/// patch and that patch's split are computed once for up to 16 tiles, and
/// each tile is built when a ray asks for it, not with its chunk.
Patch chunk_level(const TileContext& ctx, const std::uint32_t* faces, std::size_t count);

/// Tiles below another may be built in groups: the 4^k_group_levels tile
/// roots under one node k_group_levels above them (all in one tile's deepest
/// level). 0, a group of one: in the blob5k close-up (one thread) groups of
/// 4 saved 6% of the instructions for 1.34x the tiles built, but in POV-Ray's
/// twenty bunnies at tolerance 1 the extra tiles and their evictions cost
/// more than that (2.00 M nodes built against 1.87 M, and no faster);
/// groups of 16 built 1.9x the tiles (docs/benchmarks.md, "Tiles built in groups").
constexpr int k_group_levels = 0;
/// The roots of the group holding tile root `root` (level >= k_tile_depth), `root` among them.
std::vector<NodeId> tile_group_of(const NodeId& root);

/// The children of tile roots `roots` (one face and level) with their
/// border, cut from `below_parent` (Tile::below_deepest of the tile whose
/// deepest level holds them; with incident lists), not finished: where a
/// child tile's later levels start.
Patch band_of_roots(const Patch& below_parent, const std::vector<NodeId>& roots);

/// What a tile keeps of one grid point of a level: a node record's corner
/// values (NodeRecord), together, as a ray reads them together, and nothing
/// a ray does not read (the level's Gouraud normals, which only the build
/// reads, are not kept: 52 bytes a point, 80 with them). The normals only a
/// ray's shading reads are kept in 6 bytes each (104 bytes as float vectors).
struct TilePoint {
    /// NodeRecord::position (double: the decisions and both sides of an
    /// edge read the same bits), kept as bytes: a double member would align
    /// the point to 8 and pad it from 52 bytes to 56.
    Vec3 position() const {
        Vec3 p;
        std::memcpy(&p, position_bytes_, sizeof p);
        return p;
    }
    void set_position(const Vec3& p) { std::memcpy(position_bytes_, &p, sizeof p); }

    float displacement = 0.0f;  ///< NodeRecord::displacement, rounded up
    OctahedralNormal shading;   ///< NodeRecord::shading_normal
    /// NodeRecord::edge_normal once per grid edge: by the edge's direction
    /// (along x, along y, the diagonal), at its first grid point.
    OctahedralNormal edge_normal[3];

private:
    unsigned char position_bytes_[sizeof(Vec3)] = {};
};

/// One level of a tile: values on the root's sub-grid of resolution n = 2^j
/// ((n+1)(n+2)/2 points), a shell per triangle (n^2) and, for Loop, where
/// each point is drawn. Points in one array, not an array per value: a
/// tile's levels are small, and nine blocks per level were a quarter of a
/// render's allocations. And the three arrays in one block, allocated when
/// the level is built: nine tiles in ten build one level (6 points, 4
/// shells), and three vectors per level in a vector of levels were a third
/// of such a tile's bytes.
class TileLevel {
public:
    /// Allocates level j's values, default-initialised (with Loop's drawn
    /// points if `with_draw`). Once: a built level is read without a lock.
    void allocate(int j, bool with_draw);
    bool built() const { return block_ != nullptr; }

    std::size_t point_count() const { return point_count(header().j); }
    std::size_t shell_count() const { return shell_count(header().j); }
    TilePoint* points() { return reinterpret_cast<TilePoint*>(block_.get() + k_header_bytes); }
    const TilePoint* points() const { return reinterpret_cast<const TilePoint*>(block_.get() + k_header_bytes); }
    /// Null where the scheme draws at the position (interpolating schemes).
    Vec3* draw() { return with_draw() ? reinterpret_cast<Vec3*>(block_.get() + draw_offset(header().j)) : nullptr; }
    const Vec3* draw() const {
        return with_draw() ? reinterpret_cast<const Vec3*>(block_.get() + draw_offset(header().j)) : nullptr;
    }
    /// The grid the level's shells are stored on, then the shells.
    ShellGrid& shell_grid() { return *reinterpret_cast<ShellGrid*>(block_.get() + grid_offset()); }
    const ShellGrid& shell_grid() const {
        return *reinterpret_cast<const ShellGrid*>(block_.get() + grid_offset());
    }
    LevelShell* shells() { return reinterpret_cast<LevelShell*>(block_.get() + grid_offset() + sizeof(ShellGrid)); }
    const LevelShell* shells() const {
        return reinterpret_cast<const LevelShell*>(block_.get() + grid_offset() + sizeof(ShellGrid));
    }
    /// Shell k of the level, relative to the tile's origin.
    Shell shell(std::size_t k, const Vec3& origin) const { return shells()[k].expand(shell_grid(), origin); }
    /// The block's bytes as the heap allocates them (0 before allocate()).
    std::size_t bytes_held() const;

private:
    /// What the block says of itself, in front of its arrays (in the
    /// block, not the level: a tile has room for three levels and builds
    /// one, nine times in ten).
    struct Header {
        std::uint8_t j;
        bool with_draw;
    };
    static constexpr std::size_t k_header_bytes = 8;  ///< the points' alignment
    const Header& header() const { return *reinterpret_cast<const Header*>(block_.get()); }
    bool with_draw() const { return header().with_draw; }
    std::size_t grid_offset() const { return grid_offset(header().j, with_draw()); }

    // The block's layout: header, points, drawn points (Loop), shell grid, shells.
    static std::size_t point_count(int j) { return ((std::size_t{1} << j) + 1) * ((std::size_t{1} << j) + 2) / 2; }
    static std::size_t shell_count(int j) { return std::size_t{1} << (2 * j); }
    /// After the points, rounded up to the drawn points' alignment.
    static std::size_t draw_offset(int j) {
        return (k_header_bytes + point_count(j) * sizeof(TilePoint) + alignof(Vec3) - 1) / alignof(Vec3) * alignof(Vec3);
    }
    static std::size_t grid_offset(int j, bool with_draw) {
        return draw_offset(j) + (with_draw ? point_count(j) * sizeof(Vec3) : 0);
    }
    static std::size_t block_bytes(int j, bool with_draw) {
        return grid_offset(j, with_draw) + sizeof(ShellGrid) + shell_count(j) * sizeof(LevelShell);
    }

    std::unique_ptr<std::byte[]> block_;
};

/// The records of a node's descendants, levels root.level+1 .. root.level+depth.
/// Levels are built on first use (the first at construction): a ray that
/// stops one level below the root pays for that level only (and the next
/// level's points around it, not that level's topology).
class Tile {
public:
    /// The tile rooted at `root`, one of `group`'s. `ctx` must outlive the tile.
    Tile(const TileContext& ctx, const NodeId& root, TileGroup& group);

    /// The record of descendant `id` (root.level < id.level <= root.level + depth),
    /// building its level first if needed; without `normals` (Hierarchy::Part::
    /// geometry), its shading and edge-midpoint normals stay zero; without
    /// `shell` (Hierarchy::Part::corners), its shell stays empty. Thread-safe.
    NodeRecord record(const NodeId& id, bool normals = true, bool shell = true) const {
        const int j = id.level - root_.level;
        if (ready_.load(std::memory_order_acquire) < j) ensure_level(j);
        return assemble(levels_[j - 1], id, normals, shell);
    }

    /// The shells alone of those four children (what a ray tests before it
    /// asks for the record of one it enters), building their level first.
    void child_shells(const NodeId& parent, std::array<Shell, 4>& out) const {
        const int j = parent.level + 1 - root_.level;
        if (ready_.load(std::memory_order_acquire) < j) ensure_level(j);
        const TileLevel& level = levels_[j - 1];
        const LevelShell::Frame frame(level.shell_grid(), origin());
        const LevelShell* shells = level.shells();
        for (int c = 0; c < 4; c += 2)
            LevelShell::expand_pair(frame, shells[index_in_level(child_of(parent, c))],
                                    shells[index_in_level(child_of(parent, c + 1))], out[c], out[c + 1]);
    }

    /// The level below its deepest one (its triangles' children and their
    /// band, not finished but with incident lists), where child tiles start
    /// (TileGroup). Computed anew on each call, from the deepest level's band
    /// derived again (band_at): the one below is about 3x the tile's other
    /// bytes (the caller keeps it while it builds children, hierarchy.cpp).
    /// Builds every level first; only for a tile whose deepest level is
    /// above max_level.
    Patch below_deepest() const;

    /// The triangle `child_root` of its deepest level with its border (not
    /// finished): where the child tile rooted there derives its own levels
    /// again. Builds every level first; only for a tile whose deepest level
    /// is above max_level.
    Patch band_of_child(const NodeId& child_root) const;

    /// What the tile holds now: the levels built (records only). Grows as
    /// levels are built (TileContext::resized).
    std::size_t bytes_held() const;

private:
    bool in_tile(const NodeId& id) const;
    /// Builds every level; throws std::logic_error for a tile whose deepest
    /// level is max_level (it has no child tiles).
    void ensure_deepest_for_children() const;
    /// Level j of the tile's triangles with their border, not finished
    /// (j <= the deepest level built): from TileContext::child_start (or,
    /// for a base triangle, TileContext::base_start), split down to level
    /// j. Where a later level or a child tile starts: a tile keeps no band
    /// between levels. Kept bands (the "frontier", about 9 kB a tile) were
    /// 70% of the cache's peak in POV-Ray's balcony scene and 19% in the
    /// blob5k close-up (docs/benchmarks.md, "Tiles keep records only").
    Patch band_at(int j) const;
    std::size_t index_in_level(const NodeId& id) const;
    std::size_t vertex_index(const NodeId& id, std::uint32_t gi, std::uint32_t gj) const;
    using GridPoint = std::array<std::uint32_t, 2>;
    /// Where TileLevel::edge_normal keeps the edge from corner e to e + 1 of
    /// `id`, or the edge between grid points p and q of id's level.
    std::pair<int, std::size_t> edge_slot(const NodeId& id, int e) const;
    std::pair<int, std::size_t> edge_slot(const NodeId& id, const GridPoint& p,
                                          const GridPoint& q) const;
    /// Without `normals`, the shading and edge-midpoint normals stay zero;
    /// without `shell`, the shell stays empty.
    NodeRecord assemble(const TileLevel& level, const NodeId& id, bool normals, bool shell) const;
    /// Level j's records from `q`, level j - 1 with its border; leaves
    /// level j's band in `q`, finished.
    void build_level(int j, Patch& q);
    /// Level j's records (levels_[j - 1]) from its patch `q` (finished, the
    /// tile's triangles listed in `tile_tris`) and the next level's
    /// points around them.
    void fill_level(int j, Patch& q, const Patch& next, ShadingMemo& memo,
                    const std::vector<std::uint32_t>& tile_tris);
    void ensure_level(int j) const;
    /// The triangles of `q` (a level of this tile with its border; finished
    /// here) split, cut to the tile's triangles and their border.
    Patch split_band(Patch& q) const;

    /// Shells are stored relative to it: the first grid point of level 1
    /// (built at construction).
    Vec3 origin() const { return levels_[0].points()[0].position(); }

    const TileContext* ctx_;
    NodeId root_;
    /// Levels 1..depth_ at [j - 1], allocated as they are built.
    std::array<TileLevel, k_tile_depth> levels_;
    std::uint8_t depth_ = 0;
    mutable SpinLock lock_;  ///< held while a level is built
    mutable std::atomic<std::uint8_t> ready_{0};  ///< levels built (1..ready_)
};

/// Triangle index of local grid position (x, y) among the n^2 triangles of
/// resolution n: "up" triangles row by row, then "down" ones.
inline std::size_t local_triangle_index(std::uint32_t n, std::uint32_t x, std::uint32_t y, bool down) {
    if (!down) return std::size_t{y} * n - std::size_t{y} * (y - 1) / 2 + x;
    const std::size_t ups = std::size_t{n} * (n + 1) / 2;
    return ups + std::size_t{y} * (n - 1) - std::size_t{y} * (y - 1) / 2 + x;
}

// Inline: a ray's every visit asks for four (as a call it was 1.6% of a
// close-up's instructions).
inline std::size_t Tile::index_in_level(const NodeId& id) const {
    const std::uint32_t n = std::uint32_t{1} << (id.level - root_.level);
    // The root's sub-grid in local coordinates; a "down" root's is point-reflected.
    if (!root_.down) return local_triangle_index(n, id.i - root_.i * n, id.j - root_.j * n, id.down);
    return local_triangle_index(n, (root_.i + 1) * n - id.i - 1, (root_.j + 1) * n - id.j - 1,
                                !id.down);
}

/// Root of the tile that holds node `id` (level >= 1). Inline: every node a
/// ray visits asks for its tile.
inline NodeId tile_root_of(const NodeId& id) {
    return ancestor_at(id, ((id.level - 1) / k_tile_depth) * k_tile_depth);
}
/// Root of the tile whose deepest level holds `root` (a tile root of level >= 1).
NodeId parent_tile_root(const NodeId& root);

}  // namespace subdivtrace::detail
