// Records of a patch's triangles (patch_records.h).
#include "patch_records.h"

#include <glm/geometric.hpp>

#include "fan_scratch.h"
#include "float_step.h"
#include "node_shell.h"

namespace subdivtrace::detail {

namespace {

/// The scheme's limit normal at a vertex whose ring is one closed fan;
/// false where no such mask applies (the scheme has none; open or irregular
/// rings, creases, curve vertices).
bool ring_limit_normal(const SchemeRules& scheme, const Patch& p, std::uint32_t v, Vec3& normal) {
    const VertexDerived& d = p.derived[v];
    const Patch::Ring& r = p.rings[v];
    if (scheme.limit_normal == nullptr || !d.has_ring || !d.single_sector || d.curve_count != 0 ||
        !r.closed || !r.regular || r.count < 3)
        return false;
    thread_local std::vector<Vec3> ring;
    ring.resize(r.count);
    for (std::uint32_t k = 0; k < r.count; ++k) ring[k] = p.verts[p.ring_nbrs[r.offset + k]].position;
    normal = scheme.limit_normal(ring.data(), r.count);
    return normal != Vec3(0.0);
}

/// The normal a leaf shades corner c of triangle t with (NodeRecord::shading_normal):
/// closer to the limit surface's than the level's own Gouraud normal, so a leaf
/// that stops early does not shade as a coarse mesh would.
Vec3 compute_shading_normal(const TileContext& ctx, const Patch& p, const Patch& next,
                            std::uint32_t t, int c) {
    const std::uint32_t v = p.tris[t].v[c];
    const Vec3 own = p.corner_normal[3 * t + c];
    Vec3 limit;
    if (ring_limit_normal(ctx.scheme, p, v, limit))
        return glm::dot(limit, own) < 0.0 ? -limit : limit;
    // One level down: the corner's triangles there are (v, edge point, edge
    // point) for each of its triangles in the corner's sector.
    const bool one_sector = p.derived[v].single_sector;
    const std::uint16_t sector = p.corner_sector[3 * t + c];
    const std::size_t incident = p.incident_offsets[v + 1] - p.incident_offsets[v];
    FanScratch from_room, to_room;
    Vec3* from = from_room.room(incident);
    Vec3* to = to_room.room(incident);
    std::size_t count = 0;
    for (std::uint32_t k = p.incident_offsets[v]; k < p.incident_offsets[v + 1]; ++k) {
        const std::uint32_t slot = p.incident_slots[k];
        if (!one_sector && p.corner_sector[slot] != sector) continue;
        const std::uint32_t first = slot - slot % 3;
        const PatchEdge& out = p.edges[p.tri_edges[slot]];
        const PatchEdge& in = p.edges[p.tri_edges[first + (slot % 3 + 2) % 3]];
        if (!out.valid || !in.valid) stencil_cut("an edge point next to a corner");
        from[count] = next.verts[out.point].position;
        to[count] = next.verts[in.point].position;
        ++count;
    }
    const Vec3 n = fan_normal(next.verts[v].position, from, to, count);
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
/// Where the scheme has limit normals, that of the regular ring (valence 6)
/// the edge point has when the two triangles close it; otherwise the Gouraud
/// normal of the ring's triangles.
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
    if (closed && ctx.scheme.limit_normal != nullptr) {
        // The edge point is a regular vertex of level L+1 (valence 6).
        const Vec3 n = ctx.scheme.limit_normal(ring.data(), 6);
        if (n != Vec3(0.0)) return n;
    }
    // The triangles (m, ring[k], ring[k + 1]), around the ring when it closes.
    const std::size_t triangles = closed ? count : count - 1;
    std::array<Vec3, 6> to;
    for (std::size_t k = 0; k < triangles; ++k) to[k] = ring[(k + 1) % count];
    return fan_normal(m, ring.data(), to.data(), triangles);
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

}  // namespace

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
    const bool given = ctx.scheme.takes_given_normals && ctx.topo.has_given_normals() && p.level == 0;
    const bool quadratic = tri.id.level < ctx.max_level && !given;
    for (int c = 0; c < 3; ++c) {
        const PatchVertex& v = p.verts[tri.v[c]];
        const VertexDerived& d = p.derived[tri.v[c]];
        if (!d.has_normal || !v.has_draw) stencil_cut("a corner's normal or drawn position");
        rec.position[c] = v.position;
        rec.draw_position[c] = p.drawn_at(tri.v[c]);
        rec.shading_normal[c] = quadratic ? shading_normal(ctx, p, *next, t, c, memo) : p.corner_normal[3 * t + c];
        if (refinable && !d.has_displacement) stencil_cut("an edge point next to a corner");
        rec.displacement[c] = refinable ? round_up(d.deviation) : 0.0f;
    }
    for (int e = 0; e < 3; ++e)
        rec.edge_normal[e] = glm::vec3(quadratic ? edge_midpoint_normal(ctx, p, *next, t, e, memo) : Vec3(0.0));
    rec.linear_shading = !quadratic;

    rec.shell = descendant_shell(p, next, t, rec, ctx.scheme, ctx.shell_kind, ctx.max_level);
    return rec;
}

}  // namespace subdivtrace::detail
