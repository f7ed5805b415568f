#pragma once
/// \file tracer.h
/// The public face of the per-ray adaptive tracer: an AdaptiveSurface built
/// once from a Mesh, then intersected by any number of threads at once.

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "subdivtrace/mesh.h"
#include "subdivtrace/scheme.h"
#include "subdivtrace/shell.h"
#include "subdivtrace/tile_cache.h"

namespace subdivtrace {

/// Hard cap on max_level: 4^16 triangles per base triangle is already far past
/// double precision's use for any mesh we can load.
constexpr int k_max_level_cap = 16;

/// How the image samples the scene: the footprint rule of DESIGN.md section 5.
struct View {
    /// Angle of one pixel in radians (perspective: fov / image width).
    double pixel_angle = 1e-3;
    /// Camera position in the surface's object space.
    Vec3 camera{0.0};
    /// Orthographic cameras have a constant footprint instead.
    bool orthographic = false;
    double pixel_size = 0.0;  ///< world units per pixel, orthographic only
};

/// How neighbouring triangles that stop at different levels are kept closed.
enum class CrackRule {
    /// DESIGN section 6: each edge decides; midpoints of frozen edges snap to
    /// an endpoint, so both sides draw the same segment. The default.
    snap_frozen_edges,
    /// The paper's literal rule (each triangle decides alone): leaves
    /// T-junctions and cracks. Kept only to show that the fix matters.
    per_triangle,
};

/// Which nodes a ray refines (docs/tracer.md section 3 explains both and when
/// each wins).
enum class RefineRule {
    /// An edge refines while the surface near it may lie farther than
    /// tolerance / 80 pixels of the ray's footprint from the chord drawn
    /// there, or while the surface turns along an edge wider than two pixels
    /// by more than tolerance / 40 radians. The default: a smooth surface
    /// stops at triangles many pixels wide, and at tolerance 1 renders as
    /// close to the limit as the size rule at 1 (docs/benchmarks.md).
    error,
    /// The paper's rule: an edge refines while it is longer than `tolerance`
    /// pixels of the ray's footprint, whatever the surface's shape.
    size,
};

/// "error" or "size".
const char* refine_rule_name(RefineRule rule);
/// Parses "error" or "size"; false for anything else.
bool parse_refine_rule(const std::string& text, RefineRule& rule);

struct SurfaceOptions {
    SchemeKind scheme = SchemeKind::normal;
    RefineRule refine = RefineRule::error;
    /// The quality knob, in pixels of the ray's footprint: the longest edge
    /// drawn (size rule), or 80x the largest distance allowed between the
    /// surface and what is drawn (error rule). Larger is faster and coarser.
    double tolerance = 1.0;
    /// Deepest level any ray may refine to (0 = the base mesh).
    int max_level = 8;
    /// Byte budget of the surface's own tile cache, shared by all threads;
    /// used only when `cache` (below) is null. A ceiling: the cache starts
    /// at 8 MB and grows only while tiles it dropped are asked for again
    /// (TileCache; a close-up of one object settles at about 8-9 MB).
    std::size_t cache_mb = 32;
    View view;
    CrackRule crack_rule = CrackRule::snap_frozen_edges;
    /// Bounding volume the rays are culled against (docs/tracer.md measures both).
    ShellKind shell_kind = ShellKind::aabb_slab;

    // --- Scene-wide tile cache (issue 16) ---
    /// The tile cache this surface shares with the other surfaces of a scene
    /// (tile_cache.h): one budget for all of them, evicting across them by
    /// recency. Null: the surface makes a cache of its own of cache_mb.
    std::shared_ptr<TileCache> cache;
};

/// A ray in the surface's object space. direction need not be unit length;
/// distances t are in units of |direction|.
struct Ray {
    Vec3 origin{0.0};
    Vec3 direction{0.0, 0.0, 1.0};
    double t_min = 0.0;
    double t_max = 1e300;
    /// Distance the light travelled from the camera to origin (D in DESIGN
    /// section 5). Negative = use |origin - view.camera|.
    double origin_distance = -1.0;
    /// The view whose pixel footprint this ray follows. Each instance of a
    /// surface (a copy at its own scale, an orthographic camera) passes its
    /// own; nullptr = SurfaceOptions::view. Must outlive the call.
    const View* view = nullptr;
};

struct Hit {
    double t = 0.0;            ///< ray parameter of the hit
    Vec3 point{0.0};
    /// Smooth unit normal: the leaf's corner normals interpolated (the scheme's
    /// normals per sector between creases; the mesh's own at level 0 of the
    /// normal scheme).
    Vec3 normal{0.0};
    Vec3 geometric_normal{0.0};///< unit normal of the leaf triangle drawn
    /// From the base mesh's per-corner UVs; without UVs, the barycentric
    /// weights of the base triangle's corners 1 and 2 at the hit.
    Vec2 uv{0.0};
    /// The leaf triangle as drawn (corners after snapping), wound so that
    /// geometric_normal is its normal: a caller can re-intersect it exactly.
    std::array<Vec3, 3> triangle{};
    int level = 0;             ///< subdivision level of the leaf that was hit
    std::uint32_t base_face = 0;
    /// Upper bound on how far `point` may lie from the exact ray/leaf hit and
    /// from the surface a neighbouring ray may see; offset secondary rays by it.
    double error_bound = 0.0;
    /// Certified bound on the distance from `point` to the subdivision surface
    /// at max_level (scene units): the leaf's shell, which holds every
    /// descendant, grown by the corners it draws, plus rounding.
    double surface_error = 0.0;
    /// surface_error in pixels of the ray's footprint at the hit.
    double surface_error_px = 0.0;
    /// The leaf is at max_level and the refinement rule would have refined it
    /// further: raise max_level if its surface_error_px is too large.
    bool capped_by_max_level = false;

    // --- Where the hit lies on its base triangle (issue 16) ---
    /// Barycentric weights of base_face's corners 1 and 2 at the hit (corner
    /// 0's is 1 - x - y): what `uv` interpolates the mesh's corner uvs with,
    /// so a caller can weigh per-corner data of its own (mesh2's three
    /// textures per face) without handing it to the library.
    Vec2 base_barycentric{0.0};
};

/// Work counters; the surface keeps running totals, a caller may keep its own.
struct TraceCounters {
    std::uint64_t rays = 0;
    std::uint64_t nodes_visited = 0;
    std::uint64_t leaves_tested = 0;
    std::uint64_t cache_hits = 0;
    std::uint64_t cache_misses = 0;
    int deepest_level = 0;
    /// Hits reported (nearest: one per ray that hit; all hits: each crossing).
    std::uint64_t hits = 0;
    /// Sum and largest of the hits' surface_error_px.
    double error_bound_px_sum = 0.0;
    double error_bound_px_max = 0.0;
    /// Hits with Hit::capped_by_max_level: their bound may exceed what the rule
    /// asks only because max_level stopped them.
    std::uint64_t hits_at_max_level = 0;
    void add(const TraceCounters& o);
};

/// Heap bytes the surface holds, by part (capacities of its arrays, plus
/// malloc's bookkeeping where a part allocates per entry).
struct SurfaceMemory {
    std::size_t mesh = 0;      ///< its copy of the mesh (positions, triangles, corner normals, UVs)
    std::size_t topology = 0;  ///< base topology: faces around each vertex (4 B/vertex + 12 B/triangle)
    std::size_t bvh = 0;       ///< top-level BVH over the base triangles' shells
    std::size_t roots = 0;     ///< level-0 records: compact shells, per-vertex normals (Loop: limit points)
    /// Per-thread tile fronts: their tables and the tiles they hold. Most of
    /// those tiles are in the cache too, so fronts + cache over-counts them.
    std::size_t fronts = 0;
    std::size_t front_threads = 0;  ///< threads holding a front
    /// Per thread, the levels below recent parent tiles that child tiles
    /// start from (a few finished, shared by the parent's child tiles).
    std::size_t levels_below = 0;
    /// Everything but the cache, the fronts and the levels below: fixed once the surface is built.
    std::size_t base() const { return mesh + topology + bvh + roots; }
};

struct SurfaceStats {
    TraceCounters trace;
    std::uint64_t nodes_built = 0;
    std::uint64_t tiles_built = 0;  ///< HierarchyCounters::tiles_built
    /// Time constructing this surface's tiles (tiles_built of them), summed
    /// over threads.
    double tile_build_seconds = 0.0;
    /// This surface's tiles dropped from the cache to keep the cache within
    /// its budget (each tile is one entry holding up to 84 node records; see
    /// docs/tracer.md). Per surface, also when the cache is shared.
    std::uint64_t cache_evictions = 0;
    std::size_t cache_bytes = 0;       ///< what this surface's tiles are charged now
    std::size_t cache_peak_bytes = 0;  ///< the most they were charged at once
    SurfaceMemory memory;
    std::size_t base_triangles = 0;  ///< triangles of the base mesh
    std::vector<std::uint64_t> leaf_level_histogram;  ///< index = level

    // --- Scene-wide tile cache (issue 16) ---
    /// The whole cache this surface uses, over every surface sharing it
    /// (its budget, bytes, peak and evictions).
    TileCacheStats shared_cache;
};

class SurfaceImpl;

/// The adaptively subdivided surface. Thread-safe: every const method may be
/// called by many threads at once; they share one node cache.
class AdaptiveSurface {
public:
    /// Validates options (throws std::invalid_argument with the reason) and
    /// builds the base topology and top-level BVH.
    AdaptiveSurface(Mesh mesh, const SurfaceOptions& options);
    ~AdaptiveSurface();
    AdaptiveSurface(const AdaptiveSurface&) = delete;
    AdaptiveSurface& operator=(const AdaptiveSurface&) = delete;

    /// Nearest hit with t in (ray.t_min, ray.t_max); false if none.
    bool intersect(const Ray& ray, Hit& hit, TraceCounters* counters = nullptr) const;

    /// Every crossing along the ray in (t_min, t_max), sorted by t, each surface
    /// crossing reported once (for CSG). Crossings are told apart by what the
    /// ray meets (a drawn triangle's inside, edge or corner, and the winding of
    /// the triangles there), never by distance: see docs/tracer.md.
    void intersect_all(const Ray& ray, std::vector<Hit>& hits,
                       TraceCounters* counters = nullptr) const;

    /// Inside test for closed meshes (parity of crossings along a fixed ray
    /// through the surface seen at the view's resolution). For open meshes the
    /// answer is the same parity rule, which is only meaningful near closed parts.
    bool inside(const Vec3& point, const View* view = nullptr) const;

    /// Diagnostics: every leaf triangle a ray from `origin` would draw (no
    /// shell culling), as drawn, including degenerate ones.
    void drawn_triangles(const Vec3& origin, double origin_distance,
                         std::vector<std::array<Vec3, 3>>& out) const;

    /// Conservative bounds of the surface at every level up to max_level.
    Bounds3 bounds() const;
    /// True if every edge of the base mesh has exactly two triangles.
    bool is_closed() const;

    const SurfaceOptions& options() const;
    /// Replaces the default view (rays without their own). Not thread-safe
    /// against concurrent intersect calls; call before rendering starts.
    void set_view(const View& view);
    /// Throws std::invalid_argument if `view` is not usable (non-finite,
    /// non-positive pixel size or angle).
    static void check_view(const View& view);

    SurfaceStats stats() const;
    /// Number of triangles of uniform subdivision at `level`.
    std::uint64_t uniform_triangle_count(int level) const;

private:
    std::unique_ptr<SurfaceImpl> impl_;
};

}  // namespace subdivtrace
