#pragma once
/// \file hierarchy.h
/// The lazy subdivision hierarchy (paper eqs. 4, 7-8): any triangle of any
/// uniform level, built on demand and cached under a byte budget, shared by
/// threads. Nodes are built in tiles: when a node first refines, its
/// descendants four levels down are computed at once from a small patch of
/// the mesh with array kernels (docs/tracer.md).
///
/// Adaptive == uniform by construction of the addressing: a node is a triangle
/// of the uniform level-L mesh, named by its base triangle and grid position,
/// and its vertices are evaluated with the same stencils as subdivide_uniform.

#include <array>
#include <cstdint>
#include <memory>

#include "subdivtrace/mesh.h"
#include "subdivtrace/node_id.h"
#include "subdivtrace/scheme.h"
#include "subdivtrace/shell.h"
#include "subdivtrace/tile_cache.h"

namespace subdivtrace {

/// What the tracer needs of a node.
struct NodeRecord {
    std::array<Vec3, 3> position;       ///< level-L positions (decisions, shells)
    std::array<Vec3, 3> draw_position;  ///< where the corner is drawn (Loop: limit point)
    /// What a leaf shades with, closer to the limit surface's normal than the
    /// level's own Gouraud normal: Loop's limit normal (tangent masks) where
    /// the corner's ring is a closed fan, else the Gouraud normal of the
    /// corner's triangles one level down; the level-L Gouraud normal itself
    /// at max_level, and the given normals at level 0. (A record holds only
    /// what a ray reads: the level-L normals at other levels stay in the
    /// build.)
    std::array<Vec3, 3> shading_normal{};
    /// The normal at the midpoint of edge e (corner e to e + 1) one level
    /// down, from the edge point's ring as shading_normal is from a corner's
    /// (zero where that ring has no area). A leaf whose corners are its own
    /// shades with the quadratic through these six normals, which follows the
    /// surface's normal inside it about 5x closer than the linear blend
    /// (docs/tracer.md). Across a crease or boundary, from this side's
    /// triangles only.
    std::array<glm::vec3, 3> edge_normal{};
    /// Shade with the corners' linear blend: the user's normals (as mesh2
    /// does), and at max_level (the uniform level-max_level mesh as it is).
    bool linear_shading = false;
    /// Per corner: the largest offset of a level-(L+1) edge point from its
    /// edge's midpoint along the surface normal, over every edge at the
    /// corner, as the limit surface's sagitta (Loop's control points are off
    /// by half of it); the whole offset at boundaries and creases; 0 at
    /// max_level. The same bits in every record that holds the corner, so
    /// both sides of an edge decide alike from it (the error rule,
    /// docs/tracer.md).
    std::array<float, 3> displacement{};
    Shell shell;                        ///< bounds every descendant to max_level
};

struct HierarchyCounters {
    std::uint64_t nodes_built = 0;  ///< node records computed (tiles x their nodes)
    /// Tiles built: the cache's misses (each tile is built when a ray asks
    /// for it, docs/tracer.md).
    std::uint64_t tiles_built = 0;
    /// Seconds spent building tiles, summed over threads: a tile's own work
    /// (its construction, the levels it builds on first use, the bands they
    /// and child tiles start from), not waiting for another thread.
    double tile_build_seconds = 0.0;
    /// Tile lookups in the cache that found the tile (or waited for another
    /// thread building it). This hierarchy's own, whoever shares the cache;
    /// so are the counters below.
    std::uint64_t node_hits = 0;
    std::uint64_t node_misses = 0;  ///< tile cache misses
    std::uint64_t evictions = 0;    ///< its tiles dropped from the cache to keep the cache's budget
    std::size_t bytes = 0;          ///< what its tiles in the cache are charged now
    std::size_t peak_bytes = 0;     ///< the most its tiles were charged at once
    std::size_t topology_bytes = 0; ///< the base topology's arrays
    std::size_t root_bytes = 0;     ///< the level-0 records
    /// The threads' fronts: their tables and the tiles they hold (each tile
    /// counted once per front; most are in the cache too, so this overlaps it).
    std::size_t front_bytes = 0;
    std::size_t fronts = 0;         ///< threads holding a front of this hierarchy
    /// The levels below parent tiles the threads keep for child tiles to
    /// start from (tile.h, LevelBelow), a few finished.
    std::size_t below_bytes = 0;
};

class HierarchyImpl;

class Hierarchy {
public:
    /// `mesh` must outlive the hierarchy and be validated. A tile cache of
    /// its own with a budget of `cache_bytes`.
    Hierarchy(const Mesh& mesh, SchemeKind scheme, int max_level, std::size_t cache_bytes,
              ShellKind shell_kind = ShellKind::aabb_slab);
    /// The same, sharing `cache` with other hierarchies (null: a cache of its
    /// own with TileCache's default budget). Its tiles leave the cache when
    /// the hierarchy is destroyed.
    Hierarchy(const Mesh& mesh, SchemeKind scheme, int max_level, std::shared_ptr<TileCache> cache,
              ShellKind shell_kind = ShellKind::aabb_slab);
    ~Hierarchy();

    SchemeKind scheme() const;
    int max_level() const;
    std::size_t face_count() const;
    bool closed() const;
    /// The tile cache it uses (shared or its own).
    const std::shared_ptr<TileCache>& cache() const;

    static NodeId root(std::uint32_t face) { return root_node(face); }

    /// What node() fills in: the whole record, or all but its normals
    /// (shading_normal and edge_normal left zero), which is what a ray's
    /// descent reads; the tracer reads the normals of the leaf it hits alone.
    /// A tile keeps them compressed (octahedral), and decoding six per record
    /// was about half of assembling one. `corners` is geometry without the
    /// shell (left empty), for a caller that has the shell already
    /// (child_shells): decoding it again was a fifth of a record's cost.
    enum class Part { all, geometry, corners };

    /// The node's record, from the cache or built now. Thread-safe; the result
    /// does not depend on the cache's contents (evicted entries are rebuilt
    /// bit-identically).
    NodeRecord node(const NodeId& id, Part part = Part::all) const;

    /// The records of the four children of `id` (level < max_level), in
    /// child_of order (node() of each). Thread-safe.
    void children(const NodeId& id, std::array<NodeRecord, 4>& out) const;
    /// The shell of base triangle `face` alone (node(root(face)).shell):
    /// what a ray tests before it reads the rest of the record.
    Shell root_shell(std::uint32_t face) const;
    /// The shells of the four children of `id` alone (what a ray tests
    /// before it enters one), in child_of order.
    void child_shells(const NodeId& id, std::array<Shell, 4>& out) const;

    HierarchyCounters counters() const;

private:
    std::unique_ptr<HierarchyImpl> impl_;
};

}  // namespace subdivtrace
