#include "tile.h"

#include <algorithm>
#include <chrono>
#include <memory>
#include <mutex>
#include <new>
#include <type_traits>
#include <stdexcept>

#include "patch.h"
#include "patch_records.h"
#include "root_records.h"

namespace subdivtrace::detail {

namespace {

/// Where TileLevel::edge_normal keeps the edge between grid points p and q:
/// its direction (along x, along y, the diagonal; the same in the root's
/// local frame, as a "down" root's point reflection keeps each direction) and
/// whether p is its first point (the smaller j, or on a row the smaller i).
struct GridEdge {
    int direction;
    bool p_first;
};
GridEdge grid_edge(const std::array<std::uint32_t, 2>& p, const std::array<std::uint32_t, 2>& q) {
    return {p[1] == q[1] ? 0 : p[0] == q[0] ? 1 : 2, p[1] != q[1] ? p[1] < q[1] : p[0] < q[0]};
}

/// Adds the time from its construction to its destruction to a counter.
class BuildTimer {
public:
    explicit BuildTimer(std::atomic<std::uint64_t>* total)
        : total_(total), start_(std::chrono::steady_clock::now()) {}
    ~BuildTimer() {
        const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(
            std::chrono::steady_clock::now() - start_);
        total_->fetch_add(static_cast<std::uint64_t>(ns.count()), std::memory_order_relaxed);
    }
    BuildTimer(const BuildTimer&) = delete;
    BuildTimer& operator=(const BuildTimer&) = delete;

private:
    std::atomic<std::uint64_t>* total_;
    std::chrono::steady_clock::time_point start_;
};

/// Corner k of a record from grid point v of a tile level (all but the
/// edge normals, which are kept per grid edge; the shading normal only with
/// `normals`).
void set_corner(const TileLevel& level, std::size_t v, int k, bool normals, NodeRecord& rec) {
    const TilePoint& point = level.points()[v];
    rec.position[k] = point.position();
    if (normals) rec.shading_normal[k] = point.shading.vector();
    rec.displacement[k] = point.displacement;
    const Vec3* draw = level.draw();
    rec.draw_position[k] = draw ? draw[v] : rec.position[k];
}

/// Finishes level `q` and computes the next level's points its records read
/// around the triangles `in_region` accepts (into `next`); returns the flags.
/// A group's first level and a tile's later levels start the same way.
template <class InRegion>
Flags finish_for_records(const TileContext& ctx, Patch& q, InRegion in_region, Patch& next) {
    q.finish(ctx.topo, ctx.scheme);
    Flags region(q.tris.size());
    for (std::size_t t = 0; t < region.size(); ++t) region[t] = in_region(q.tris[t].id);
    // At max_level too: the corners' displacement tells a leaf there that
    // the rule would have refined it.
    const Flags needed = q.points_around(region);
    q.next_positions(ctx.topo, ctx.scheme, &needed, next);
    return region;
}

}  // namespace

// Inline: Tile::children() asks for six per call (1.5% of the close-up's
// instructions as a call).
inline std::size_t Tile::vertex_index(const NodeId& id, std::uint32_t gi, std::uint32_t gj) const {
    const std::size_t n = std::size_t{1} << (id.level - root_.level);
    const std::size_t x = root_.down ? (root_.i + 1) * n - gi : gi - root_.i * n;
    const std::size_t y = root_.down ? (root_.j + 1) * n - gj : gj - root_.j * n;
    // Points row by row: row y holds n + 1 - y of them.
    return y * (n + 1) - y * (y - 1) / 2 + x;
}

NodeId parent_tile_root(const NodeId& root) { return ancestor_at(root, root.level - k_tile_depth); }

std::vector<NodeId> tile_group_of(const NodeId& root) {
    std::vector<NodeId> group{ancestor_at(root, root.level - k_group_levels)};
    for (int d = 0; d < k_group_levels; ++d) {
        std::vector<NodeId> next;
        for (const NodeId& id : group)
            for (int c = 0; c < 4; ++c) next.push_back(child_of(id, c));
        group = std::move(next);
    }
    return group;
}

namespace {

/// The triangles of `p` below the roots (one level), ascending. Its
/// triangles are in the hierarchy's order (patch.h), so each root's
/// descendants are a contiguous run, found by binary search (a scan of the
/// whole patch per group was 1.5% of a close-up's instructions).
std::vector<std::uint32_t> triangles_below(const Patch& p, const std::vector<NodeId>& roots) {
    struct Span {
        std::uint32_t face;
        std::uint64_t first, last;
        bool operator<(const Span& o) const { return face != o.face ? face < o.face : first < o.first; }
    };
    std::vector<Span> spans;
    spans.reserve(roots.size());
    for (const NodeId& r : roots) {
        const auto [first, last] = depth_first_span(r);
        spans.push_back({r.face, first, last});
    }
    std::sort(spans.begin(), spans.end());
    const std::vector<PatchTriangle>& tris = p.tris;
    std::vector<std::uint32_t> region;
    for (const Span& span : spans) {
        const auto before = [&](const PatchTriangle& t, std::uint64_t key) {
            return t.id.face != span.face ? t.id.face < span.face : depth_first_key(t.id) < key;
        };
        const auto from = std::lower_bound(tris.begin(), tris.end(), span.first, before);
        const auto to = std::lower_bound(from, tris.end(), span.last, before);
        for (auto it = from; it != to; ++it) region.push_back(static_cast<std::uint32_t>(it - tris.begin()));
    }
    return region;
}

}  // namespace

Patch chunk_level(const TileContext& ctx, const std::uint32_t* faces, std::size_t count) {
    const BuildTimer timer(ctx.build_ns);
    const auto in_chunk = [&](const NodeId& id) { return std::binary_search(faces, faces + count, id.face); };
    Patch base = base_patch(ctx.topo, faces, count);
    base.finish(ctx.topo, ctx.scheme);
    if (ctx.roots) ctx.roots->lend_normals(base);
    Flags kept;
    Patch level = base.subdivide_band(ctx.topo, ctx.scheme, in_chunk, kept);
    base.give_back_derived();  // its arrays serve the next patch this thread finishes
    level.keep_only(kept);
    level.build_incidence();  // band_of_roots cuts through them
    return level;
}

std::vector<std::uint32_t> TileGroup::triangles_of(const NodeId& root) const {
    return triangles_below(*level_, {root});
}

Patch band_of_roots(const Patch& below_parent, const std::vector<NodeId>& roots) {
    // The roots' children and their border, cut from the level below the
    // parent (its siblings are cut from the same patch, whose incident lists
    // below_deepest() built once, so each cut costs its own size).
    if (!below_parent.has_incidence())
        throw std::logic_error("subdivtrace tile: a child tile's start has no incident lists (Tile::below_deepest builds them)");
    return Patch::copy_of(below_parent, below_parent.band_around(triangles_below(below_parent, roots)));
}

LevelBelow::LevelBelow(Patch below) : level_(std::move(below)) {}

LevelBelow::~LevelBelow() = default;

void LevelBelow::prepare(const TileContext& ctx, const std::vector<std::uint32_t>& tris) {
    if (!finished_) {
        level_.finish(ctx.topo, ctx.scheme);
        next_.level = level_.level + 1;
        next_.verts.assign(level_.verts.size() + level_.edges.size(), PatchVertex{});
        level_.start_positions(ctx.scheme, next_);
        next_done_.assign(next_.verts.size(), 0);
        memo_ = std::make_unique<ShadingMemo>(level_);
        finished_ = true;
    }
    // At max_level too: the corners' displacement tells a leaf there that
    // the rule would have refined it.
    level_.add_points_around(ctx.topo, ctx.scheme, tris, next_, next_done_);
}

void LevelBelow::unfinish() {
    if (!finished_) return;
    level_.give_back_derived();
    level_.build_incidence();  // band_of_roots cuts through them
    next_ = Patch();
    Flags().swap(next_done_);
    memo_.reset();
    finished_ = false;
}

std::size_t LevelBelow::owned_bytes() const {
    std::size_t bytes = level_.owned_bytes() + next_.owned_bytes() + next_done_.capacity();
    if (memo_)
        bytes += sizeof(ShadingMemo) + (memo_->corner.capacity() + memo_->edge.capacity()) * sizeof(Vec3) +
                 memo_->corner_done.capacity() + memo_->edge_done.capacity();
    return bytes;
}

TileGroup::TileGroup(const TileContext& ctx, LevelBelow& below, const std::vector<NodeId>& roots) {
    const BuildTimer timer(ctx.build_ns);
    below.prepare(ctx, triangles_below(below.level_, roots));
    level_ = &below.level_;
    next_ = &below.next_;
    memo_ = below.memo_.get();
}

Tile::Tile(const TileContext& ctx, const NodeId& root, TileGroup& group)
    : ctx_(&ctx), root_(root), depth_(static_cast<std::uint8_t>(std::min(k_tile_depth, ctx.max_level - root.level))) {
    const BuildTimer timer(ctx.build_ns);
    Patch& q = *group.level_;
    const std::vector<std::uint32_t> tile_tris = group.triangles_of(root);
    fill_level(1, q, *group.next_, *group.memo_, tile_tris);
    ready_.store(1, std::memory_order_release);
}

bool Tile::in_tile(const NodeId& id) const {
    return id.face == root_.face && id.level > root_.level && ancestor_at(id, root_.level) == root_;
}

Patch Tile::split_band(Patch& q) const {
    // Its positions are recomputed here from scratch, as only a tile that
    // goes deeper pays for that level's topology.
    q.finish(ctx_->topo, ctx_->scheme);
    if (q.level == 0 && ctx_->roots) ctx_->roots->lend_normals(q);
    Flags kept;
    Patch next = q.subdivide_band(ctx_->topo, ctx_->scheme, [&](const NodeId& id) { return in_tile(id); }, kept);
    q.give_back_derived();  // its arrays serve the next patch this thread finishes
    next.keep_only(kept);
    return next;
}

Patch Tile::band_at(int j) const {
    // The same triangles and bits as the group's first level and the splits
    // after it (patch.h: every value comes from canonically ordered inputs,
    // and a border two rings wide suffices).
    Patch q;
    if (root_.level == 0) {
        std::optional<Patch> cut;
        if (ctx_->base_start) cut = ctx_->base_start(root_.face);
        q = cut ? std::move(*cut) : chunk_level(*ctx_, &root_.face, 1);
    } else {
        if (!ctx_->child_start)
            throw std::logic_error("subdivtrace tile: a child tile's later levels need their start (TileContext::child_start)");
        q = ctx_->child_start(root_);
    }
    const BuildTimer timer(ctx_->build_ns);
    while (q.level < root_.level + j) q = split_band(q);
    return q;
}

void Tile::build_level(int j, Patch& q) {
    // q is level root.level + j - 1 with its border: split it first. Then
    // it is level root.level + j, cut to the tile's triangles and their
    // border; the records of that level read the next level's points around
    // them, computed here and dropped after.
    q = split_band(q);
    // The next level's points and the shading memo live until the level is
    // filled: this thread's scratch, so their blocks are reused.
    thread_local Patch next;
    const Flags in_this_tile =
        finish_for_records(*ctx_, q, [&](const NodeId& id) { return in_tile(id); }, next);
    std::vector<std::uint32_t> tile_tris;
    tile_tris.reserve(std::size_t{1} << (2 * j));  // the tile's whole level
    for (std::uint32_t t = 0; t < in_this_tile.size(); ++t)
        if (in_this_tile[t]) tile_tris.push_back(t);
    thread_local ShadingMemo memo;
    memo.reset(q);
    fill_level(j, q, next, memo, tile_tris);
}

void Tile::fill_level(int j, Patch& q, const Patch& next, ShadingMemo& memo,
                      const std::vector<std::uint32_t>& tile_tris) {
    TileLevel& out = levels_[j - 1];
    out.allocate(j, ctx_->scheme.draws_limit_points());
    TilePoint* points = out.points();
    Vec3* draw = out.draw();
    thread_local std::vector<Shell> shells;  // in double precision until compacted below
    shells.assign(out.shell_count(), Shell{});
    for (std::uint32_t t : tile_tris) {
        const PatchTriangle& tri = q.tris[t];
        for (std::uint32_t v : tri.v) q.ensure_normal(ctx_->topo, ctx_->scheme, v);
        const NodeRecord rec = make_record(*ctx_, q, &next, t, memo);
        shells[index_in_level(tri.id)] = rec.shell;
        const auto grid = node_corner_grid(tri.id);
        for (int c = 0; c < 3; ++c) {
            const std::size_t v = vertex_index(tri.id, grid[c][0], grid[c][1]);
            TilePoint& point = points[v];
            point.set_position(rec.position[c]);
            point.shading = OctahedralNormal::from(rec.shading_normal[c]);
            point.displacement = rec.displacement[c];
            if (draw) draw[v] = rec.draw_position[c];
            const auto [direction, at] = edge_slot(tri.id, c);
            points[at].edge_normal[direction] = OctahedralNormal::from(Vec3(rec.edge_normal[c]));
        }
    }
    const Vec3 origin = this->origin();
    ShellGrid& grid = out.shell_grid();
    grid = ShellGrid::spanning(shells.data(), shells.size(), origin);
    LevelShell* stored = out.shells();
    for (std::size_t k = 0; k < shells.size(); ++k) stored[k] = LevelShell::from(shells[k], grid, origin);
    ctx_->records_built->fetch_add(shells.size(), std::memory_order_relaxed);
}

std::pair<int, std::size_t> Tile::edge_slot(const NodeId& id, int e) const {
    const auto grid = node_corner_grid(id);
    return edge_slot(id, grid[e], grid[(e + 1) % 3]);
}

std::pair<int, std::size_t> Tile::edge_slot(const NodeId& id, const GridPoint& p,
                                            const GridPoint& q) const {
    const GridEdge e = grid_edge(p, q);
    const GridPoint& first = e.p_first ? p : q;
    return {e.direction, vertex_index(id, first[0], first[1])};
}


NodeRecord Tile::assemble(const TileLevel& level, const NodeId& id, bool normals, bool shell) const {
    NodeRecord rec;
    const auto grid = node_corner_grid(id);
    for (int c = 0; c < 3; ++c) {
        const std::size_t v = vertex_index(id, grid[c][0], grid[c][1]);
        set_corner(level, v, c, normals, rec);
        if (!normals) continue;
        const auto [direction, slot] = edge_slot(id, grid[c], grid[(c + 1) % 3]);
        rec.edge_normal[c] = glm::vec3(level.points()[slot].edge_normal[direction].vector());
    }
    if (shell) rec.shell = level.shell(index_in_level(id), origin());
    return rec;
}

void Tile::ensure_level(int j) const {
    std::lock_guard<SpinLock> lock(lock_);
    const int built = ready_.load(std::memory_order_relaxed);
    if (built >= j) return;  // another thread built it
    // The band of the level built last, derived again (band_at times
    // itself, as the parent's builds time their own): a tile keeps records
    // only (tile.h).
    auto* self = const_cast<Tile*>(this);
    Patch q = band_at(built);
    {
        const BuildTimer timer(ctx_->build_ns);
        for (int k = built + 1; k <= j; ++k) {
            self->build_level(k, q);
            ready_.store(static_cast<std::uint8_t>(k), std::memory_order_release);
        }
        q.give_back_derived();  // its arrays serve the next patch this thread finishes
    }
    if (ctx_->resized) ctx_->resized(*this, root_, bytes_held());
}

void Tile::ensure_deepest_for_children() const {
    ensure_level(depth_);
    if (root_.level + depth_ >= ctx_->max_level)
        throw std::logic_error("subdivtrace tile: a level below a tile at max_level asked for");
}

Patch Tile::below_deepest() const {
    ensure_deepest_for_children();
    Patch q = band_at(depth_);
    const BuildTimer timer(ctx_->build_ns);
    Patch below = split_band(q);
    below.build_incidence();  // each child tile cuts its band through them
    return below;
}

Patch Tile::band_of_child(const NodeId& child_root) const {
    if (child_root.level != root_.level + depth_ || !in_tile(child_root))
        throw std::logic_error("subdivtrace tile: band_of_child asked for a node that is not a child tile's root");
    ensure_deepest_for_children();
    const Patch q = band_at(depth_);
    const BuildTimer timer(ctx_->build_ns);
    return Patch::copy_of(q, q.band([&](const NodeId& id) { return id == child_root; }));
}

namespace {

/// Heap bytes of a block of `bytes` as glibc's malloc allocates it (plus an
/// 8-byte header, rounded up to 16, at least 32): leaving this out of the
/// small arrays tiles held undercharged them by about 20% (RSS above the
/// budget, docs/povray.md "Memory").
std::size_t heap_bytes(std::size_t bytes) {
    return bytes == 0 ? 0 : std::max<std::size_t>(32, (bytes + 8 + 15) / 16 * 16);
}

}  // namespace

void TileLevel::allocate(int j, bool with_draw) {
    static_assert(std::is_trivially_destructible_v<TilePoint> && std::is_trivially_destructible_v<Vec3> &&
                  std::is_trivially_destructible_v<ShellGrid> && std::is_trivially_destructible_v<LevelShell>,
                  "a level's block is freed without destructors");
    static_assert(sizeof(TilePoint) == 52 && std::is_trivially_copyable_v<Vec3>, "a point packs its 13 words");
    static_assert(k_header_bytes % alignof(TilePoint) == 0 && sizeof(Header) <= k_header_bytes &&
                      alignof(TilePoint) % alignof(ShellGrid) == 0 && sizeof(Vec3) % alignof(ShellGrid) == 0 &&
                      sizeof(ShellGrid) % alignof(LevelShell) == 0,
                  "each array of the block starts aligned (the drawn points by draw_offset's rounding)");
    // The header first: the accessors below read it.
    block_.reset(new std::byte[block_bytes(j, with_draw)]);
    ::new (static_cast<void*>(block_.get())) Header{static_cast<std::uint8_t>(j), with_draw};
    std::uninitialized_value_construct_n(points(), point_count());
    if (with_draw) std::uninitialized_value_construct_n(draw(), point_count());
    ::new (static_cast<void*>(&shell_grid())) ShellGrid();
    std::uninitialized_value_construct_n(shells(), shell_count());
}

std::size_t TileLevel::bytes_held() const {
    return built() ? heap_bytes(block_bytes(header().j, with_draw())) : 0;
}

std::size_t Tile::bytes_held() const {
    std::size_t bytes = sizeof(Tile);
    for (const TileLevel& l : levels_) bytes += l.bytes_held();
    return bytes;
}

}  // namespace subdivtrace::detail
