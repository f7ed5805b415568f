#include "tile.h"

#include <algorithm>
#include <chrono>
#include <exception>
#include <thread>

#include <glm/geometric.hpp>

#include "node_shell.h"
#include "patch.h"

namespace subdivtrace::detail {

namespace {

/// Base triangles whose level-0 records are computed from one patch.
constexpr std::size_t k_root_chunk = 4096;
constexpr std::uint32_t k_no_slot = ~std::uint32_t{0};

/// Runs work(i, scratch) for i in [0, count) on up to one thread per core,
/// each thread with its own scratch; rethrows the first exception.
template <class Work>
void run_in_parallel(std::size_t count, Work work) {
    const std::size_t threads =
        std::min<std::size_t>(count, std::max(1u, std::thread::hardware_concurrency()));
    std::atomic<std::size_t> next{0};
    std::exception_ptr failure;
    std::mutex failure_mutex;
    const auto worker = [&] {
        BasePatchScratch scratch;
        try {
            for (std::size_t i; (i = next.fetch_add(1)) < count;) work(i, scratch);
        } catch (...) {
            const std::lock_guard<std::mutex> lock(failure_mutex);
            if (!failure) failure = std::current_exception();
            next = count;  // the others stop after their current item
        }
    };
    std::vector<std::thread> pool;
    for (std::size_t k = 1; k < threads; ++k) pool.emplace_back(worker);
    worker();
    for (std::thread& t : pool) t.join();
    if (failure) std::rethrow_exception(failure);
}

/// Loop's limit normal from a closed ring of n points in counter-clockwise
/// order (Halstead, Kass and DeRose 1993: the tangent masks cos(2 pi k / n),
/// sin(2 pi k / n), centre weight 0); zero where the tangents are parallel.
template <class RingPoint>
Vec3 loop_tangent_normal(std::size_t n, RingPoint ring_point) {
    constexpr double k_two_pi = 6.283185307179586476925;
    Vec3 t1(0.0), t2(0.0);
    for (std::size_t k = 0; k < n; ++k) {
        const double a = k_two_pi * static_cast<double>(k) / static_cast<double>(n);
        t1 += std::cos(a) * ring_point(k);
        t2 += std::sin(a) * ring_point(k);
    }
    return finish_normal(glm::cross(t1, t2));
}

/// Loop's limit normal at a vertex whose ring is one closed fan; false where
/// no such mask applies (open or irregular rings, creases, curve vertices).
bool loop_limit_normal(const Patch& p, std::uint32_t v, Vec3& normal) {
    const VertexDerived& d = p.derived[v];
    const Patch::Ring& r = p.rings[v];
    if (!d.has_ring || !d.single_sector || d.curve_count != 0 || !r.closed || !r.regular ||
        r.count < 3)
        return false;
    normal = loop_tangent_normal(r.count, [&](std::size_t k) -> const Vec3& {
        return p.verts[p.ring_nbrs[r.offset + k]].position;
    });
    return normal != Vec3(0.0);
}

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

    explicit ShadingMemo(const Patch& p)
        : corner(p.verts.size()), corner_done(p.verts.size(), 0), edge(p.edges.size()),
          edge_done(p.edges.size(), 0) {}
};

/// The normal a leaf shades corner c of triangle t with (NodeRecord::shading_normal):
/// closer to the limit surface's than the level's own Gouraud normal, so a leaf
/// that stops early does not shade as a coarse mesh would.
Vec3 compute_shading_normal(const TileContext& ctx, const Patch& p, const Patch& next,
                            std::uint32_t t, int c) {
    const std::uint32_t v = p.tris[t].v[c];
    const Vec3 own = p.corner_normal[3 * t + c];
    Vec3 limit;
    if (ctx.scheme == SchemeKind::loop && loop_limit_normal(p, v, limit))
        return glm::dot(limit, own) < 0.0 ? -limit : limit;
    // One level down: the corner's triangles there are (v, edge point, edge
    // point) for each of its triangles in the corner's sector.
    const bool one_sector = p.derived[v].single_sector;
    const std::uint16_t sector = p.corner_sector[3 * t + c];
    const Vec3 centre = next.verts[v].position;
    Vec3 sum(0.0);
    for (std::uint32_t k = p.incident_offsets[v]; k < p.incident_offsets[v + 1]; ++k) {
        const std::uint32_t slot = p.incident_slots[k];
        if (!one_sector && p.corner_sector[slot] != sector) continue;
        const std::uint32_t first = slot - slot % 3;
        const PatchEdge& out = p.edges[p.tri_edges[slot]];
        const PatchEdge& in = p.edges[p.tri_edges[first + (slot % 3 + 2) % 3]];
        if (!out.valid || !in.valid) stencil_cut("an edge point next to a corner");
        sum += angle_weighted_normal(centre, next.verts[out.point].position,
                                     next.verts[in.point].position);
    }
    const Vec3 n = finish_normal(sum);
    return n == Vec3(0.0) ? own : n;
}

Vec3 shading_normal(const TileContext& ctx, const Patch& p, const Patch& next, std::uint32_t t,
                    int c, ShadingMemo& memo) {
    const std::uint32_t v = p.tris[t].v[c];
    // With one sector, the result depends on the vertex alone.
    if (!p.derived[v].single_sector) return compute_shading_normal(ctx, p, next, t, c);
    if (!memo.corner_done[v]) {
        memo.corner[v] = compute_shading_normal(ctx, p, next, t, c);
        memo.corner_done[v] = 1;
    }
    return memo.corner[v];
}

/// Whether the edge's two triangles continue one fan across it: neither a
/// curve nor a flipped neighbour (it runs the edge the other way).
bool continues_one_fan(const Patch& p, const PatchEdge& edge) {
    if (edge.curve || edge.slot_count != 2) return false;
    const std::uint32_t s0 = edge.slot[0], s1 = edge.slot[1];
    const auto& t0 = p.tris[s0 / 3].v;
    const auto& t1 = p.tris[s1 / 3].v;
    return t0[s0 % 3] == t1[(s1 % 3 + 1) % 3] && t0[(s0 % 3 + 1) % 3] == t1[s1 % 3];
}

/// The normal at the midpoint of edge e of triangle t one level down
/// (NodeRecord::edge_normal): from the edge point's ring there, the
/// children of the edge's two triangles (one, across a crease or boundary).
/// Loop: its limit normal (the ring is regular, valence 6); otherwise the
/// Gouraud normal of the ring's triangles.
Vec3 compute_edge_midpoint_normal(const TileContext& ctx, const Patch& p, const Patch& next,
                                  std::uint32_t t, int e) {
    const PatchTriangle& tri = p.tris[t];
    const std::uint32_t a = tri.v[e], b = tri.v[(e + 1) % 3];
    const PatchEdge& edge = p.edges[p.tri_edges[3 * t + e]];
    const auto point = [&](std::uint32_t slot) -> const Vec3& {
        const PatchEdge& pe = p.edges[p.tri_edges[slot]];
        if (!pe.valid || !next.verts[pe.point].has_position) stencil_cut("an edge point around an edge's midpoint");
        return next.verts[pe.point].position;
    };
    const Vec3& m = point(3 * t + e);
    // The ring around the midpoint, counter-clockwise: b, m_bc, m_ca, a on
    // this side, then a, m_ad, m_db, b on the other.
    std::array<Vec3, 6> ring;
    std::size_t count = 0;
    ring[count++] = next.verts[b].position;
    ring[count++] = point(3 * t + (e + 1) % 3);
    ring[count++] = point(3 * t + (e + 2) % 3);
    ring[count++] = next.verts[a].position;
    const bool closed = continues_one_fan(p, edge);
    if (closed) {
        const std::uint32_t other = edge.slot[0] == 3 * t + static_cast<std::uint32_t>(e) ? edge.slot[1] : edge.slot[0];
        const std::uint32_t t2 = other / 3, e2 = other % 3;
        ring[count++] = point(3 * t2 + (e2 + 1) % 3);
        ring[count++] = point(3 * t2 + (e2 + 2) % 3);
    }
    if (closed && ctx.scheme == SchemeKind::loop) {
        // The edge point is a regular vertex of level L+1 (valence 6).
        const Vec3 n = loop_tangent_normal(6, [&](std::size_t k) -> const Vec3& { return ring[k]; });
        if (n != Vec3(0.0)) return n;
    }
    Vec3 sum(0.0);
    for (std::size_t k = 0; k + 1 < count + (closed ? 1 : 0); ++k)
        sum += angle_weighted_normal(m, ring[k], ring[(k + 1) % count]);
    return finish_normal(sum);
}

/// compute_edge_midpoint_normal, shared by the edge's two triangles where
/// they continue one fan (then both sides' rings are the same six points,
/// and it is computed from the first triangle's side, whichever asks).
Vec3 edge_midpoint_normal(const TileContext& ctx, const Patch& p, const Patch& next, std::uint32_t t,
                          int e, ShadingMemo& memo) {
    const std::uint32_t id = p.tri_edges[3 * t + static_cast<std::uint32_t>(e)];
    const PatchEdge& edge = p.edges[id];
    if (!continues_one_fan(p, edge)) return compute_edge_midpoint_normal(ctx, p, next, t, e);
    const std::uint32_t s0 = edge.slot[0];
    if (!memo.edge_done[id]) {
        memo.edge[id] = compute_edge_midpoint_normal(ctx, p, next, s0 / 3, static_cast<int>(s0 % 3));
        memo.edge_done[id] = 1;
    }
    return memo.edge[id];
}

/// Record of triangle t of patch p (level L), with `next` the patch p
/// subdivided once (untrimmed; only read when L < max_level).
NodeRecord make_record(const TileContext& ctx, const Patch& p, const Patch* next, std::uint32_t t,
                       ShadingMemo& memo) {
    const PatchTriangle& tri = p.tris[t];
    NodeRecord rec;
    // At max_level too (the tile computes the next level's points for it):
    // the displacement tells whether the rule would have gone further.
    const bool refinable = next != nullptr;
    // The user's normals shade linearly, as mesh2 does (and are what the
    // user wants shaded); so does max_level, which draws the uniform
    // level-max_level mesh as it is.
    const bool given = ctx.scheme == SchemeKind::normal && ctx.topo.has_given_normals() && p.level == 0;
    const bool quadratic = tri.id.level < ctx.max_level && !given;
    for (int c = 0; c < 3; ++c) {
        const PatchVertex& v = p.verts[tri.v[c]];
        const VertexDerived& d = p.derived[tri.v[c]];
        if (!d.has_normal || !v.has_draw) stencil_cut("a corner's normal or drawn position");
        rec.position[c] = v.position;
        rec.normal[c] = p.corner_normal[3 * t + c];
        rec.draw_position[c] = v.draw;
        rec.shading_normal[c] = quadratic ? shading_normal(ctx, p, *next, t, c, memo) : rec.normal[c];
        if (refinable && !d.has_displacement) stencil_cut("an edge point next to a corner");
        rec.displacement[c] = refinable ? round_up(d.displacement) : 0.0f;
    }
    for (int e = 0; e < 3; ++e)
        rec.edge_normal[e] = glm::vec3(quadratic ? edge_midpoint_normal(ctx, p, *next, t, e, memo) : Vec3(0.0));
    rec.linear_shading = !quadratic;

    rec.shell = descendant_shell(p, next, t, rec, ctx.scheme, ctx.shell_kind, ctx.max_level);
    return rec;
}

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

/// Triangle index of local grid position (x, y) among the n^2 triangles of
/// resolution n: "up" triangles row by row, then "down" ones.
std::size_t local_triangle_index(std::uint32_t n, std::uint32_t x, std::uint32_t y, bool down) {
    if (!down) return std::size_t{y} * n - std::size_t{y} * (y - 1) / 2 + x;
    const std::size_t ups = std::size_t{n} * (n + 1) / 2;
    return ups + std::size_t{y} * (n - 1) - std::size_t{y} * (y - 1) / 2 + x;
}

}  // namespace

NodeId tile_root_of(const NodeId& id) {
    return ancestor_at(id, ((id.level - 1) / k_tile_depth) * k_tile_depth);
}

std::size_t Tile::index_in_level(const NodeId& id) const {
    const std::uint32_t n = std::uint32_t{1} << (id.level - root_.level);
    // The root's sub-grid in local coordinates; a "down" root's is point-reflected.
    if (!root_.down) return local_triangle_index(n, id.i - root_.i * n, id.j - root_.j * n, id.down);
    return local_triangle_index(n, (root_.i + 1) * n - id.i - 1, (root_.j + 1) * n - id.j - 1,
                                !id.down);
}

NodeId parent_tile_root(const NodeId& root) { return ancestor_at(root, root.level - k_tile_depth); }

Tile::Tile(const TileContext& ctx, const NodeId& root, const Patch* parent_patch)
    : ctx_(&ctx), root_(root), levels_(std::min(k_tile_depth, ctx.max_level - root.level)) {
    depth_ = static_cast<int>(levels_.size());
    const BuildTimer timer(ctx.build_ns);
    // The root's children and their border: cut from the parent tile's last
    // patch, or subdivided from the base triangles around the root.
    if (parent_patch) {
        frontier_ = Patch::copy_of(*parent_patch,
                                   parent_patch->band([&](const NodeId& id) { return in_tile(id); }));
    } else {
        Patch p = base_patch(ctx.topo, &root.face, 1);
        p.finish(ctx.topo, ctx.scheme);
        if (ctx.roots) ctx.roots->lend_normals(p);
        std::vector<bool> kept;
        frontier_ = p.subdivide_band(ctx.topo, ctx.scheme, [&](const NodeId& id) { return in_tile(id); }, kept);
        frontier_.keep_only(kept);
    }
    build_level(1);
}

bool Tile::in_tile(const NodeId& id) const {
    return id.face == root_.face && id.level > root_.level && ancestor_at(id, root_.level) == root_;
}

void Tile::advance_frontier() {
    // The frontier's triangles split, cut to the tile's triangles and their
    // border: the next level's start, or after the deepest level where
    // child tiles start (its positions are recomputed here from scratch, as
    // only a tile that goes deeper pays for that level's topology).
    Patch& q = frontier_;
    q.finish(ctx_->topo, ctx_->scheme);
    std::vector<bool> kept;
    Patch next = q.subdivide_band(ctx_->topo, ctx_->scheme, [&](const NodeId& id) { return in_tile(id); }, kept);
    next.keep_only(kept);
    frontier_ = std::move(next);
}

void Tile::build_level(int j) {
    // frontier_ is level root.level + j - 1 for j > 1 (its records built):
    // split it first. Then it is level root.level + j, cut to the tile's
    // triangles and their border; the records of that level read the next
    // level's points around them, computed here and dropped after.
    if (j > 1) advance_frontier();
    Patch& q = frontier_;
    q.finish(ctx_->topo, ctx_->scheme);
    std::vector<bool> in_this_tile(q.tris.size());
    for (std::size_t t = 0; t < q.tris.size(); ++t) in_this_tile[t] = in_tile(q.tris[t].id);
    // At max_level too: the corners' displacement tells a leaf there that
    // the rule would have refined it.
    const std::vector<bool> needed = q.points_around(in_this_tile);
    const Patch next = q.next_positions(ctx_->topo, ctx_->scheme, &needed);
    TileLevel& out = levels_[j - 1];
    const std::size_t n = std::size_t{1} << j;
    out.position.resize((n + 1) * (n + 2) / 2);
    out.normal.resize(out.position.size());
    out.shading.resize(out.position.size());
    out.displacement.resize(out.position.size());
    for (auto& edges : out.edge_normal) edges.resize(out.position.size());
    if (ctx_->scheme == SchemeKind::loop) out.draw.resize(out.position.size());
    out.shells.resize(n * n);
    std::vector<Shell> shells(n * n);
    ShadingMemo memo(q);
    for (std::uint32_t t = 0; t < q.tris.size(); ++t) {
        if (!in_this_tile[t]) continue;
        const PatchTriangle& tri = q.tris[t];
        for (std::uint32_t v : tri.v) q.ensure_normal(ctx_->topo, ctx_->scheme, v);
        const NodeRecord rec = make_record(*ctx_, q, &next, t, memo);
        shells[index_in_level(tri.id)] = rec.shell;
        const auto grid = node_corner_grid(tri.id);
        for (int c = 0; c < 3; ++c) {
            const std::size_t v = vertex_index(tri.id, grid[c][0], grid[c][1]);
            out.position[v] = rec.position[c];
            out.normal[v] = rec.normal[c];
            out.shading[v] = glm::vec3(rec.shading_normal[c]);
            out.displacement[v] = rec.displacement[c];
            if (!out.draw.empty()) out.draw[v] = rec.draw_position[c];
            const auto [direction, at] = edge_slot(tri.id, c);
            out.edge_normal[direction][at] = rec.edge_normal[c];
        }
    }
    // Shells relative to a point of the tile: its first grid point at level 1.
    if (j == 1) origin_ = out.position[0];
    for (std::size_t k = 0; k < shells.size(); ++k) out.shells[k] = CompactShell::from(shells[k], origin_);
    // Waits, without rings and edges, for the next level or child tiles.
    q.drop_derived();
    ctx_->records_built->fetch_add(out.shells.size(), std::memory_order_relaxed);
    ready_.store(j, std::memory_order_release);
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

std::size_t Tile::vertex_index(const NodeId& id, std::uint32_t gi, std::uint32_t gj) const {
    const std::size_t n = std::size_t{1} << (id.level - root_.level);
    const std::size_t x = root_.down ? (root_.i + 1) * n - gi : gi - root_.i * n;
    const std::size_t y = root_.down ? (root_.j + 1) * n - gj : gj - root_.j * n;
    // Points row by row: row y holds n + 1 - y of them.
    return y * (n + 1) - y * (y - 1) / 2 + x;
}

void Tile::children(const NodeId& parent, std::array<NodeRecord, 4>& out) const {
    const int j = parent.level + 1 - root_.level;
    if (ready_.load(std::memory_order_acquire) < j) ensure_level(j);
    const TileLevel& level = levels_[j - 1];
    // The six grid points of the children: the parent's corners and edge
    // midpoints, at the children's level.
    const auto g = node_corner_grid(parent);
    const NodeId first = child_of(parent, 0);
    GridPoint corner_grid[3], mid_grid[3];
    std::size_t corner[3], mid[3];
    for (int c = 0; c < 3; ++c) {
        const int d = (c + 1) % 3;
        corner_grid[c] = {2 * g[c][0], 2 * g[c][1]};
        mid_grid[c] = {g[c][0] + g[d][0], g[c][1] + g[d][1]};
        corner[c] = vertex_index(first, corner_grid[c][0], corner_grid[c][1]);
        mid[c] = vertex_index(first, mid_grid[c][0], mid_grid[c][1]);
    }
    for (int c = 0; c < 4; ++c) {
        const NodeId child = c == 0 ? first : child_of(parent, c);
        const auto& map = child_corners(parent.down, c);
        NodeRecord& rec = out[c];
        const GridPoint* at[3];
        std::size_t index[3];
        for (int k = 0; k < 3; ++k) {
            const std::size_t v = map[k].is_edge ? mid[map[k].index] : corner[map[k].index];
            index[k] = v;
            at[k] = map[k].is_edge ? &mid_grid[map[k].index] : &corner_grid[map[k].index];
            rec.position[k] = level.position[v];
            rec.normal[k] = level.normal[v];
            rec.shading_normal[k] = Vec3(level.shading[v]);
            rec.displacement[k] = level.displacement[v];
            rec.draw_position[k] = level.draw.empty() ? level.position[v] : level.draw[v];
        }
        for (int k = 0; k < 3; ++k) {
            // As edge_slot(), with both ends' indices already known.
            const int l = (k + 1) % 3;
            const GridEdge e = grid_edge(*at[k], *at[l]);
            rec.edge_normal[k] = level.edge_normal[e.direction][e.p_first ? index[k] : index[l]];
        }
        rec.shell = level.shells[index_in_level(child)].expand(origin_);
    }
}

NodeRecord Tile::assemble(const TileLevel& level, const NodeId& id) const {
    NodeRecord rec;
    const auto grid = node_corner_grid(id);
    for (int c = 0; c < 3; ++c) {
        const std::size_t v = vertex_index(id, grid[c][0], grid[c][1]);
        rec.position[c] = level.position[v];
        rec.normal[c] = level.normal[v];
        rec.shading_normal[c] = Vec3(level.shading[v]);
        rec.displacement[c] = level.displacement[v];
        rec.draw_position[c] = level.draw.empty() ? level.position[v] : level.draw[v];
        const auto [direction, slot] = edge_slot(id, grid[c], grid[(c + 1) % 3]);
        rec.edge_normal[c] = level.edge_normal[direction][slot];
    }
    rec.shell = level.shells[index_in_level(id)].expand(origin_);
    return rec;
}

void Tile::ensure_level(int j) const {
    std::lock_guard<std::mutex> lock(mutex_);
    if (ready_.load(std::memory_order_relaxed) >= j) return;  // another thread built it
    const BuildTimer timer(ctx_->build_ns);
    auto* self = const_cast<Tile*>(this);
    for (int k = ready_.load(std::memory_order_relaxed) + 1; k <= j; ++k) self->build_level(k);
}

const Patch& Tile::last_patch() const {
    if (last_ready_.load(std::memory_order_acquire)) return frontier_;
    ensure_level(depth_);
    std::lock_guard<std::mutex> lock(mutex_);
    if (!last_ready_.load(std::memory_order_relaxed)) {
        const BuildTimer timer(ctx_->build_ns);
        auto* self = const_cast<Tile*>(this);
        if (root_.level + depth_ < ctx_->max_level) self->advance_frontier();
        else self->frontier_ = Patch();  // no tile starts below max_level
        last_ready_.store(true, std::memory_order_release);
    }
    return frontier_;
}

std::size_t Tile::bytes_when_complete() const {
    std::size_t bytes = sizeof(Tile) + levels_.capacity() * sizeof(TileLevel) + 2 * frontier_.owned_bytes();
    const std::size_t per_vertex = (ctx_->scheme == SchemeKind::loop ? 3 : 2) * sizeof(Vec3) +
                                   4 * sizeof(glm::vec3) + sizeof(float);
    for (int j = 1; j <= depth_; ++j) {
        const std::size_t n = std::size_t{1} << j;
        bytes += (n + 1) * (n + 2) / 2 * per_vertex + n * n * sizeof(CompactShell);
    }
    return bytes;
}

RootRecords::RootRecords(const TileContext& ctx) : mesh_(&ctx.topo.mesh()) {
    const std::size_t face_count = ctx.topo.face_count();
    const std::size_t vertex_count = mesh_->positions.size();
    normal_.resize(vertex_count);
    shading_.resize(vertex_count);
    displacement_.resize(vertex_count);
    edge_normal_.resize(3 * face_count);
    if (ctx.scheme == SchemeKind::loop) draw_.resize(vertex_count);
    shells_.resize(face_count);

    // A vertex keeps the values of its first corner (the lowest slot 3f + c);
    // the corners whose normals differ (across a crease) are kept apart.
    // Knowing each vertex's first corner up front lets the chunks below run
    // on several threads: each per-vertex value has exactly one writer.
    std::vector<std::uint32_t> first_slot(vertex_count, k_no_slot);
    for (std::size_t f = 0; f < face_count; ++f)
        for (int c = 0; c < 3; ++c) {
            std::uint32_t& first = first_slot[mesh_->triangles[f][c]];
            if (first == k_no_slot) first = static_cast<std::uint32_t>(3 * f + c);
        }

    // In chunks of base triangles, each with the border its records read:
    // the whole mesh at once made the base level's patch most of a large
    // mesh's construction peak.
    const std::size_t chunk_count = (face_count + k_root_chunk - 1) / k_root_chunk;
    std::vector<ChunkCorners> corners(chunk_count);
    run_in_parallel(chunk_count, [&](std::size_t chunk, BasePatchScratch& scratch) {
        build_chunk(ctx, chunk * k_root_chunk, std::min(face_count, (chunk + 1) * k_root_chunk),
                    first_slot, scratch, corners[chunk]);
    });
    // The corners a chunk could not compare (their vertex's first corner is
    // in an earlier chunk) are compared now; chunks and their lists are in
    // slot order, so split_corners_ ascends.
    for (ChunkCorners& chunk : corners) {
        std::vector<SplitCorner> merged;
        merged.reserve(chunk.split.size() + chunk.deferred.size());
        auto split = chunk.split.begin();
        for (const SplitCorner& d : chunk.deferred) {
            for (; split != chunk.split.end() && split->slot < d.slot; ++split) merged.push_back(*split);
            const std::uint32_t v = mesh_->triangles[d.slot / 3][d.slot % 3];
            if (d.normal != normal_[v] || d.shading != shading_[v]) merged.push_back(d);
        }
        merged.insert(merged.end(), split, chunk.split.end());
        split_corners_.insert(split_corners_.end(), merged.begin(), merged.end());
    }
    split_corners_.shrink_to_fit();
    linear_shading_ = !corners.empty() && corners.front().linear_shading;
    ctx.records_built->fetch_add(shells_.size(), std::memory_order_relaxed);
}

void RootRecords::build_chunk(const TileContext& ctx, std::size_t first, std::size_t last,
                              const std::vector<std::uint32_t>& first_slot,
                              BasePatchScratch& scratch, ChunkCorners& out) {
    std::vector<std::uint32_t> region;
    for (std::size_t f = first; f < last; ++f) region.push_back(static_cast<std::uint32_t>(f));
    Patch p = base_patch(ctx.topo, region.data(), region.size(), &scratch);
    p.finish(ctx.topo, ctx.scheme);
    // The next level's positions only: the shells read its edge points
    // (and Loop's moved corners), never its triangles.
    std::vector<bool> in_chunk(p.tris.size());
    for (std::size_t t = 0; t < p.tris.size(); ++t)
        in_chunk[t] = p.tris[t].id.face >= first && p.tris[t].id.face < last;
    const std::vector<bool> needed = p.points_around(in_chunk);
    const Patch next = p.next_positions(ctx.topo, ctx.scheme, &needed);
    ShadingMemo memo(p);
    // The patch's triangles ascend by face, so its corners by slot.
    for (std::uint32_t t = 0; t < p.tris.size(); ++t) {
        if (!in_chunk[t]) continue;  // border
        const std::uint32_t f = p.tris[t].id.face;
        for (std::uint32_t v : p.tris[t].v) p.ensure_normal(ctx.topo, ctx.scheme, v);
        const NodeRecord rec = make_record(ctx, p, &next, t, memo);
        shells_[f] = CompactShell::from(rec.shell, rec.position[0]);
        out.linear_shading = rec.linear_shading;  // the same for every level-0 record
        for (int e = 0; e < 3; ++e) edge_normal_[3 * f + e] = rec.edge_normal[e];
        for (int c = 0; c < 3; ++c) {
            const std::uint32_t v = p.verts[p.tris[t].v[c]].key.a;
            const std::uint32_t slot = 3 * f + static_cast<std::uint32_t>(c);
            const SplitCorner corner{slot, rec.normal[c], glm::vec3(rec.shading_normal[c])};
            if (slot == first_slot[v]) {
                normal_[v] = rec.normal[c];
                shading_[v] = corner.shading;
                displacement_[v] = rec.displacement[c];
                if (!draw_.empty()) draw_[v] = rec.draw_position[c];
            } else if (first_slot[v] / 3 < first) {
                // Written by an earlier chunk. A vertex with one sector has
                // the same normals at every corner (one sum over its whole
                // ring, in canonical order), so only crease vertices wait:
                // keeping every such corner cost 17 MB at 943k triangles.
                if (!p.derived[p.tris[t].v[c]].single_sector) out.deferred.push_back(corner);
            } else if (corner.normal != normal_[v] || corner.shading != shading_[v]) {
                out.split.push_back(corner);
            }
        }
    }
}

Vec3 RootRecords::corner_normal(std::uint32_t face, int c) const {
    const std::uint32_t slot = 3 * face + static_cast<std::uint32_t>(c);
    if (!split_corners_.empty()) {
        const auto it = std::lower_bound(
            split_corners_.begin(), split_corners_.end(), slot,
            [](const SplitCorner& x, std::uint32_t s) { return x.slot < s; });
        if (it != split_corners_.end() && it->slot == slot) return it->normal;
    }
    return normal_[mesh_->triangles[face][c]];
}

void RootRecords::lend_normals(Patch& p) const {
    // A level-0 patch triangle is its base triangle, corners in the same order.
    for (std::uint32_t v = 0; v < p.verts.size(); ++v)
        p.adopt_normal(v, [&](std::uint32_t slot) {
            return corner_normal(p.tris[slot / 3].id.face, static_cast<int>(slot % 3));
        });
}

NodeRecord RootRecords::record(std::uint32_t face) const {
    NodeRecord rec;
    const Triangle& t = mesh_->triangles[face];
    for (int c = 0; c < 3; ++c) {
        rec.position[c] = mesh_->positions[t[c]];
        rec.normal[c] = normal_[t[c]];
        rec.shading_normal[c] = Vec3(shading_[t[c]]);
        rec.displacement[c] = displacement_[t[c]];
        rec.draw_position[c] = draw_.empty() ? rec.position[c] : draw_[t[c]];
        rec.edge_normal[c] = edge_normal_[3 * std::size_t{face} + c];
    }
    rec.linear_shading = linear_shading_;
    if (!split_corners_.empty()) {
        const auto lo = std::lower_bound(
            split_corners_.begin(), split_corners_.end(), 3 * face,
            [](const SplitCorner& x, std::uint32_t slot) { return x.slot < slot; });
        for (auto it = lo; it != split_corners_.end() && it->slot < 3 * face + 3; ++it) {
            rec.normal[it->slot - 3 * face] = it->normal;
            rec.shading_normal[it->slot - 3 * face] = Vec3(it->shading);
        }
    }
    rec.shell = shells_[face].expand(rec.position[0]);
    return rec;
}

std::size_t RootRecords::owned_bytes() const {
    return (normal_.capacity() + draw_.capacity()) * sizeof(Vec3) +
           (shading_.capacity() + edge_normal_.capacity()) * sizeof(glm::vec3) +
           displacement_.capacity() * sizeof(float) +
           shells_.capacity() * sizeof(CompactShell) + split_corners_.capacity() * sizeof(SplitCorner);
}

}  // namespace subdivtrace::detail
