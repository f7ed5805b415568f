#include "patch.h"

#include <algorithm>
#include <array>
#include <stdexcept>
#include <string>

#include <glm/geometric.hpp>

#include "creases.h"
#include "edge_rings.h"
#include "fan_scratch.h"
#include "id_table.h"
#include "ring_order.h"

namespace subdivtrace::detail {

[[noreturn]] void stencil_cut(const char* what) {
    throw std::logic_error(std::string("subdivtrace tile: ") + what +
                           " outside the patch's complete region");
}

namespace {

/// How many triangles of a uniform level meet at the vertex `key` (its whole
/// ring): one per base face at a base vertex, three per face along a base
/// edge, six inside a face.
std::uint16_t true_incident_count(const BaseTopology& topo, const VertexKey& key) {
    // Saturates: a count this large never matches a patch's (it would need
    // 65535 triangles at one vertex), so such a vertex is simply never whole.
    std::size_t n = 6;
    if (key.kind == VertexKey::base_vertex) n = topo.faces_of_vertex(key.a).size();
    else if (key.kind == VertexKey::edge_point)
        n = 3 * (topo.closed() ? 2 : topo.faces_on_edge(key.a, key.b));  // closed: two on every edge
    return static_cast<std::uint16_t>(std::min<std::size_t>(n, UINT16_MAX));
}

}  // namespace

namespace {

/// Empties `v` and returns its memory (`v = {}` would keep the capacity).
template <class T>
void release(std::vector<T>& v) {
    std::vector<T>().swap(v);
}

/// The derived arrays of the last patch this thread dropped, for the next
/// one it finishes: a tile level finishes two patches and drops both, and
/// allocating their ten arrays anew each time was a fifth of a render's
/// allocations. A patch whose derived arrays alone are used; arrays above
/// k_spare_bytes are freed, not kept.
thread_local Patch spare;
constexpr std::size_t k_spare_bytes = std::size_t{1} << 20;
/// The most a thread's scratch tables keep between patches.
constexpr std::size_t k_scratch_bytes = std::size_t{256} << 10;

/// Gives `v` the spare's block if it has none.
template <class T>
void borrow(std::vector<T>& v, std::vector<T>& from) {
    if (v.capacity() == 0 && from.capacity() != 0) {
        v.swap(from);
        v.clear();
    }
}

/// Keeps v's block as the spare (the larger of the two, up to
/// k_spare_bytes), and leaves v without memory.
template <class T>
void give_back(std::vector<T>& v, std::vector<T>& to) {
    if (v.capacity() > to.capacity() && v.capacity() * sizeof(T) <= k_spare_bytes) v.swap(to);
    release(v);
}

/// Applies op(patch array, spare array) to each derived array.
template <class Op>
void for_each_derived(Patch& p, Op op) {
    op(p.derived, spare.derived);
    op(p.corner_normal, spare.corner_normal);
    op(p.corner_sector, spare.corner_sector);
    op(p.rings, spare.rings);
    op(p.ring_nbrs, spare.ring_nbrs);
    op(p.ring_curve, spare.ring_curve);
    op(p.incident_offsets, spare.incident_offsets);
    op(p.incident_slots, spare.incident_slots);
    op(p.edges, spare.edges);
    op(p.tri_edges, spare.tri_edges);
}

}  // namespace

void Patch::build_incidence() {
    // Incident (triangle, corner) slots per vertex, CSR.
    const std::size_t n = verts.size();
    std::vector<std::uint32_t>& offsets = incident_offsets;
    std::vector<std::uint32_t>& slots = incident_slots;
    offsets.assign(n + 1, 0);
    for (const PatchTriangle& t : tris)
        for (std::uint32_t v : t.v) ++offsets[v + 1];
    for (std::size_t v = 0; v < n; ++v) offsets[v + 1] += offsets[v];
    slots.resize(offsets.back());
    thread_local std::vector<std::uint32_t> fill;
    fill.assign(offsets.begin(), offsets.end() - 1);
    for (std::uint32_t t = 0; t < tris.size(); ++t)
        for (std::uint32_t c = 0; c < 3; ++c) slots[fill[tris[t].v[c]]++] = 3 * t + c;
}

void Patch::finish(const BaseTopology& topo, const SchemeRules& scheme) {
    const std::size_t n = verts.size();
    for_each_derived(*this, [](auto& v, auto& from) { borrow(v, from); });
    build_incidence();
    if (edge_names.size() != 3 * tris.size()) name_edges(topo);
    const std::vector<std::uint32_t>& offsets = incident_offsets;
    const std::vector<std::uint32_t>& slots = incident_slots;

    // Which vertices have their whole ring (with positions) in the patch;
    // then the edges, which need to know it.
    rings.assign(n, Ring{});
    derived.assign(n, VertexDerived{});
    // A triangle is whole when its three corners have positions; a vertex's
    // ring, when all its level's triangles are here and whole.
    thread_local Flags whole;
    whole.resize(tris.size());
    for (std::size_t t = 0; t < tris.size(); ++t) {
        const auto& v = tris[t].v;
        whole[t] = verts[v[0]].has_position & verts[v[1]].has_position & verts[v[2]].has_position;
    }
    for (std::uint32_t v = 0; v < n; ++v) {
        VertexDerived& dv = derived[v];
        dv.has_ring = verts[v].has_position && offsets[v + 1] - offsets[v] == verts[v].true_ring;
        for (std::uint32_t k = offsets[v]; k < offsets[v + 1] && dv.has_ring; ++k)
            dv.has_ring = whole[slots[k] / 3] != 0;
    }
    build_edges();

    ring_nbrs.clear();
    ring_curve.clear();
    corner_normal.assign(3 * tris.size(), Vec3(0.0));
    corner_sector.assign(3 * tris.size(), 0);
    if (scheme.draws_limit_points()) draw.resize(verts.size(), Vec3(0.0));
    for (std::uint32_t v = 0; v < n; ++v)
        if (derived[v].has_ring) finish_vertex(topo, scheme, v);
    if (!scheme.draws_limit_points())
        for (PatchVertex& pv : verts) pv.has_draw = pv.has_position;
}

namespace {

/// The triangles around a vertex as (from, to) pairs with their corner slot.
struct SlotPair {
    std::uint32_t from;
    std::uint32_t to;
    std::uint32_t slot;
};

/// The part of `offset` (an edge point's, from edge `e`'s midpoint) along
/// the surface normal there, estimated as the normal to the edge and to the
/// diagonal between its two triangles' third vertices; the whole offset on a
/// boundary, a crease or a non-manifold edge. Taking the triangles in the
/// other order negates that normal exactly, so every patch that holds the
/// edge gets the same bits.
double normal_offset(const Patch& p, const PatchEdge& e, const Vec3& offset) {
    if (e.curve || e.slot_count != 2) return glm::length(offset);
    const auto third = [&](std::uint32_t slot) { return p.tris[slot / 3].v[(slot % 3 + 2) % 3]; };
    const Vec3 normal = glm::cross(p.verts[e.b].position - p.verts[e.a].position,
                                   p.verts[third(e.slot[0])].position - p.verts[third(e.slot[1])].position);
    const double length = glm::length(normal);
    if (!(length > 0.0) || !std::isfinite(length)) return glm::length(offset);
    return std::abs(glm::dot(offset, normal)) / length;
}

/// True if the vertex can lie on a curve: a base vertex at a boundary or
/// crease, or a point of a base edge between two such vertices.
bool may_be_on_curve(const BaseTopology& topo, const VertexKey& key) {
    if (key.kind == VertexKey::base_vertex) return topo.on_curve(key.a);
    if (key.kind == VertexKey::edge_point) return topo.on_curve(key.a) && topo.on_curve(key.b);
    return false;
}

/// The triangles around v as (from, to, slot), in the canonical order: the
/// incident lists follow the patch's triangles, which every patch holds in
/// the hierarchy's order (patch.h), so every patch that holds this whole
/// ring sums and walks it in the same order.
void ring_pairs(const Patch& p, std::uint32_t v, std::vector<SlotPair>& pairs) {
    pairs.clear();
    for (std::uint32_t k = p.incident_offsets[v]; k < p.incident_offsets[v + 1]; ++k) {
        const std::uint32_t slot = p.incident_slots[k];
        const PatchTriangle& t = p.tris[slot / 3];
        const std::uint32_t c = slot % 3;
        pairs.push_back({t.v[(c + 1) % 3], t.v[(c + 2) % 3], slot});
    }
}

}  // namespace

bool ring_by_edges(const Patch& p, std::uint32_t v, OrderedRing<std::uint32_t>& out) {
    const std::uint32_t first = p.incident_offsets[v], n = p.incident_offsets[v + 1] - first;
    if (n == 0) return false;
    // Pair `slot` (v's corner) runs from its first edge, (v, from), to its
    // last, (to, v), which is its triangle's edge slot before v's.
    const auto last_edge_slot = [](std::uint32_t slot) { return slot - slot % 3 + (slot % 3 + 2) % 3; };
    const auto out_edge = [&](std::uint32_t slot) -> const PatchEdge& { return p.edges[p.tri_edges[slot]]; };
    const auto in_edge = [&](std::uint32_t slot) -> const PatchEdge& { return p.edges[p.tri_edges[last_edge_slot(slot)]]; };
    // An open fan starts at its one pair whose first edge has no other triangle.
    std::uint32_t start = p.incident_slots[first];
    int boundaries = 0;
    for (std::uint32_t k = first; k < first + n; ++k) {
        const PatchEdge& e = out_edge(p.incident_slots[k]);
        if (e.slot_count > 2) return false;
        if (e.slot_count == 1) {
            start = p.incident_slots[k];
            ++boundaries;
        }
    }
    if (boundaries > 1) return false;
    out.nbrs.clear();
    out.closed = false;
    out.regular = true;
    const auto corner = [&](std::uint32_t slot, int step) { return p.tris[slot / 3].v[(slot % 3 + step) % 3]; };
    out.nbrs.push_back(corner(start, 1));
    std::uint32_t slot = start;
    for (std::uint32_t step = 0;; ++step) {
        const std::uint32_t to = corner(slot, 2);
        const PatchEdge& e = in_edge(slot);
        if (e.slot_count > 2) return false;
        if (e.slot_count == 1) {
            // The fan ends: open, after all n pairs.
            if (boundaries != 1 || step + 1 != n) return false;
            out.nbrs.push_back(to);
            break;
        }
        // The other triangle on edge (v, to) must run it from v to `to`.
        const std::uint32_t other = e.slot[0] == last_edge_slot(slot) ? e.slot[1] : e.slot[0];
        if (p.tris[other / 3].v[other % 3] != v || p.tris[other / 3].v[(other % 3 + 1) % 3] != to) return false;
        if (other == start) {
            // Back at the start: closed, after all n pairs.
            if (boundaries != 0 || step + 1 != n) return false;
            out.closed = true;
            break;
        }
        if (step + 1 >= n) return false;
        out.nbrs.push_back(to);
        slot = other;
    }
    // order_ring joins pairs by their vertices: a neighbour met twice is not
    // one fan to it. Compared pair by pair in a small ring, and marked in a
    // large one (a valence-200 hub compared 20,000 pairs per patch).
    const std::size_t count = out.nbrs.size();
    if (count <= 16) {
        for (std::size_t i = 0; i < count; ++i)
            for (std::size_t j = i + 1; j < count; ++j)
                if (out.nbrs[i] == out.nbrs[j]) return false;
        return true;
    }
    thread_local std::vector<std::uint32_t> seen;  // a stamp per patch vertex
    thread_local std::uint32_t stamp = 0;
    if (seen.size() < p.verts.size() || ++stamp == 0) {
        seen.assign(std::max(seen.size(), p.verts.size()), 0);
        stamp = 1;
    }
    for (std::uint32_t w : out.nbrs) {
        if (seen[w] == stamp) return false;
        seen[w] = stamp;
    }
    return true;
}

void Patch::finish_vertex(const BaseTopology& topo, const SchemeRules& scheme, std::uint32_t v) {
    PatchVertex& pv = verts[v];
    VertexDerived& dv = derived[v];
    const bool on_curve = may_be_on_curve(topo, pv.key);
    // Ordered rings are walked in the canonical order; curves and sectors do
    // not depend on it.
    thread_local std::vector<SlotPair> pairs;
    if (on_curve) ring_pairs(*this, v, pairs);

    // Curves and sectors, where a boundary or crease can pass.
    if (on_curve) {
        thread_local std::vector<FanCorner> corners;
        thread_local std::vector<std::uint32_t> labels;
        corners.clear();
        std::uint32_t curve_edges[3] = {0, 0, 0};
        int curve_count = 0;
        for (const SlotPair& pr : pairs) {
            const std::uint32_t c = pr.slot % 3;
            const std::uint32_t e_next = tri_edges[pr.slot];
            const std::uint32_t e_prev = tri_edges[pr.slot - c + (c + 2) % 3];
            corners.push_back({e_prev, e_next, edges[e_prev].curve, edges[e_next].curve});
            for (std::uint32_t e : {e_prev, e_next}) {
                if (!edges[e].curve) continue;
                bool seen = false;
                for (int k = 0; k < std::min(curve_count, 3); ++k) seen = seen || curve_edges[k] == e;
                if (seen) continue;
                if (curve_count < 3) curve_edges[curve_count] = e;
                ++curve_count;
            }
        }
        dv.curve_count = static_cast<std::uint8_t>(std::min(curve_count, 3));
        if (curve_count == 2) {
            for (int k = 0; k < 2; ++k) {
                const PatchEdge& e = edges[curve_edges[k]];
                dv.curve[k] = e.a == v ? e.b : e.a;
            }
            if (key_less(verts[dv.curve[1]].key, verts[dv.curve[0]].key)) std::swap(dv.curve[0], dv.curve[1]);
        }
        dv.single_sector = label_sectors(corners, labels) == 1;
        if (!dv.single_sector)
            for (std::size_t k = 0; k < pairs.size(); ++k)
                corner_sector[pairs[k].slot] = static_cast<std::uint16_t>(labels[k]);
    }

    if (scheme.reads_ordered_rings()) {
        // Rules that read the ring read it ordered; normals only sum the pairs.
        thread_local std::vector<FanPair<std::uint32_t>> fan;
        thread_local OrderedRing<std::uint32_t> ordered;
        if (!ring_by_edges(*this, v, ordered)) {
            if (!on_curve) ring_pairs(*this, v, pairs);
            fan.clear();
            for (const SlotPair& pr : pairs) fan.push_back({pr.from, pr.to});
            order_ring(fan, ordered, [](std::uint32_t x, std::uint32_t y) { return x == y; });
        }
        Ring& r = rings[v];
        r.offset = static_cast<std::uint32_t>(ring_nbrs.size());
        r.count = static_cast<std::uint32_t>(ordered.nbrs.size());
        r.closed = ordered.closed;
        r.regular = ordered.regular;
        ring_nbrs.insert(ring_nbrs.end(), ordered.nbrs.begin(), ordered.nbrs.end());
        for (std::uint32_t w : ordered.nbrs) {
            bool curve = false;
            if (!dv.single_sector) {
                for (const SlotPair& pr : pairs) {
                    const std::uint32_t c = pr.slot % 3;
                    if (pr.from == w) curve = curve || edges[tri_edges[pr.slot]].curve;
                    if (pr.to == w) curve = curve || edges[tri_edges[pr.slot - c + (c + 2) % 3]].curve;
                }
            }
            ring_curve.push_back(curve ? 1 : 0);
        }
    }

    if (scheme.draws_limit_points() && pv.key.level == level) {
        // A vertex is drawn at its limit point, from its birth-level ring.
        thread_local VertexRing ring;
        fill_vertex_ring(v, ring);
        draw[v] = scheme.drawn_point(ring);
        pv.has_draw = true;
    }
}

void Patch::fill_vertex_ring(std::uint32_t v, VertexRing& ring) const {
    gather_ring(verts[v].position, ring_indices(v), [&](std::uint32_t w) { return verts[w].position; }, ring);
}

void Patch::give_back_derived() {
    for_each_derived(*this, [](auto& v, auto& to) { give_back(v, to); });
}

std::size_t Patch::owned_bytes() const {
    return (verts.capacity() * sizeof(PatchVertex) + draw.capacity() * sizeof(Vec3)) +
           tris.capacity() * sizeof(PatchTriangle) +
           derived.capacity() * sizeof(VertexDerived) + corner_normal.capacity() * sizeof(Vec3) +
           corner_sector.capacity() * sizeof(std::uint16_t) +
           rings.capacity() * sizeof(Ring) + ring_nbrs.capacity() * sizeof(std::uint32_t) +
           ring_curve.capacity() +
           (incident_offsets.capacity() + incident_slots.capacity()) * sizeof(std::uint32_t) +
           edges.capacity() * sizeof(PatchEdge) +
           (tri_edges.capacity() + edge_names.capacity()) * sizeof(std::uint32_t);
}

namespace {

/// The edge of its base triangle (0: corners 0-1, 1: 1-2, 2: 2-0) that edge
/// e of grid triangle `id` lies on, or -1 if it lies inside.
int base_edge_under(const NodeId& id, int e) {
    const auto g = node_corner_grid(id);
    const auto& p = g[e];
    const auto& q = g[(e + 1) % 3];
    const std::uint32_t n = std::uint32_t{1} << id.level;
    // Grid point (i, j) has weight n - i - j on corner 0, i on 1, j on 2.
    if (p[1] == 0 && q[1] == 0) return 0;
    if (p[0] + p[1] == n && q[0] + q[1] == n) return 1;
    if (p[0] == 0 && q[0] == 0) return 2;
    return -1;
}

}  // namespace

void Patch::name_edges(const BaseTopology& topo) {
    // By vertex pairs, in an open-addressing table: name k for the k-th
    // distinct edge met, with the crease bit of the base edge under it.
    constexpr std::uint32_t k_unset = UINT32_MAX;
    struct Entry {
        std::uint32_t lo, hi, face, name;  // name k_unset: empty
    };
    thread_local std::vector<Entry> table;
    std::size_t size = 16;
    while (size < 4 * tris.size()) size *= 2;
    table.assign(size, Entry{0, 0, 0, k_unset});
    const std::size_t mask = size - 1;
    std::uint32_t names = 0;
    edge_names.resize(3 * tris.size());
    for (std::size_t t = 0; t < tris.size(); ++t) {
        const PatchTriangle tri = tris[t];  // a copy: the stores below might alias it
        for (int e = 0; e < 3; ++e) {
            const std::uint32_t u = tri.v[e], w = tri.v[(e + 1) % 3];
            const std::uint32_t lo = std::min(u, w), hi = std::max(u, w);
            // An edge inside a base triangle belongs to that triangle alone
            // (its point is a face point): a duplicate base triangle over the
            // same vertices has its own. Edges on a base edge are shared.
            const int base_edge = base_edge_under(tri.id, e);
            const std::uint32_t face = base_edge >= 0 ? k_unset : tri.id.face;
            std::size_t h = (lo * 0x9E3779B1u ^ hi * 0x85EBCA77u ^ face * 0xC2B2AE3Du) & mask;
            while (table[h].name != k_unset &&
                   !(table[h].lo == lo && table[h].hi == hi && table[h].face == face))
                h = (h + 1) & mask;
            if (table[h].name == k_unset) table[h] = {lo, hi, face, names++};
            const bool crease = base_edge >= 0 && topo.is_crease(tri.id.face, base_edge);
            edge_names[3 * t + e] = (table[h].name << 1) | (crease ? 1u : 0u);
        }
    }
    // A base chunk's table (4096 triangles: 512 kB) is not kept for the
    // tiles' small patches after it: the thread that built the base records
    // held it for the whole render.
    if (table.size() * sizeof(Entry) > k_scratch_bytes) release(table);
}

void Patch::build_edges() {
    // Every edge once, by its name (edge_names): triangles are visited in
    // order, so an edge's id is its first use and slot[0] its
    // lowest-numbered triangle's slot.
    constexpr std::uint32_t k_unset = UINT32_MAX;
    edges.clear();
    // A patch is cut out of its level: its border edges have one triangle,
    // so it has up to 2 edges per triangle in a narrow band, not 3/2.
    edges.reserve(2 * tris.size() + 16);
    tri_edges.resize(3 * tris.size());
    // Edge id by name number; entries are reset after use, so a patch pays for its
    // own size, not for the largest name seen.
    thread_local std::vector<std::uint32_t> id_of_name;
    const std::size_t slot_count = edge_names.size();
    for (std::size_t slot = 0; slot < slot_count; ++slot) {
        const std::uint32_t name = edge_names[slot];
        const std::uint32_t number = name >> 1;
        if (number >= id_of_name.size())
            id_of_name.resize(std::max<std::size_t>(number + 1, 2 * id_of_name.size()), k_unset);
        std::uint32_t id = id_of_name[number];
        if (id == k_unset) {
            id = static_cast<std::uint32_t>(edges.size());
            id_of_name[number] = id;
            const std::uint32_t t = static_cast<std::uint32_t>(slot / 3), e = static_cast<std::uint32_t>(slot % 3);
            const std::uint32_t u = tris[t].v[e], w = tris[t].v[(e + 1) % 3];
            // Filled in place: a local PatchEdge copied in whole right
            // after its bytes were written stalled on store forwarding.
            PatchEdge& edge = edges.emplace_back();
            const bool u_first = key_less(verts[u].key, verts[w].key);
            edge.a = u_first ? u : w;
            edge.b = u_first ? w : u;
            edge.valid = derived[edge.a].has_ring && derived[edge.b].has_ring;
            edge.crease = (name & 1u) != 0;
        }
        PatchEdge& edge = edges[id];
        tri_edges[slot] = id;
        if (edge.slot_count < 2) edge.slot[edge.slot_count] = static_cast<std::uint32_t>(slot);
        ++edge.slot_count;
    }
    for (PatchEdge& edge : edges) {
        id_of_name[edge_names[edge.slot[0]] >> 1] = k_unset;
        edge.curve = edge.crease || edge.slot_count == 1;  // or a boundary
    }
}

Vec3 Patch::edge_point(const SchemeRules& scheme, const PatchEdge& e) const {
    if (!e.curve && scheme.smooth_edge_rule != nullptr) {
        // Most edges: the two endpoints' normals in the edge's sector (any
        // triangle on it), without filling a whole stencil.
        const std::uint32_t t = e.slot[0] / 3, c = e.slot[0] % 3;
        const bool a_first = tris[t].v[c] == e.a;
        return scheme.smooth_edge_rule(verts[e.a].position, verts[e.b].position,
                                       corner_normal[3 * t + (a_first ? c : (c + 1) % 3)],
                                       corner_normal[3 * t + (a_first ? (c + 1) % 3 : c)]);
    }
    EdgeStencil s;
    s.a = verts[e.a].position;
    s.b = verts[e.b].position;
    s.curve = e.curve;
    if (e.curve) {
        fill_curve_end(e.a, e.b, s.has_a_far, s.a_far, s.normal_a);
        fill_curve_end(e.b, e.a, s.has_b_far, s.b_far, s.normal_b);
    }
    // As LevelTopology: interior when exactly two triangles share the edge;
    // c is the third vertex of the one that runs a -> b, d of the other.
    s.interior = e.slot_count == 2;
    if (s.interior && scheme.edge_rule_reads_opposites) {
        std::uint32_t third[2];
        bool forward[2];
        for (int k = 0; k < 2; ++k) {
            const PatchTriangle& t = tris[e.slot[k] / 3];
            const std::uint32_t c = e.slot[k] % 3;
            third[k] = t.v[(c + 2) % 3];
            forward[k] = t.v[c] == e.a;
        }
        // Inconsistently oriented neighbours: order the two by key instead.
        const bool first_is_c = forward[0] != forward[1]
                                    ? forward[0]
                                    : key_less(verts[third[0]].key, verts[third[1]].key);
        s.c = verts[first_is_c ? third[0] : third[1]].position;
        s.d = verts[first_is_c ? third[1] : third[0]].position;
    }
    if (scheme.edge_rule_reads_rings) {
        const auto position_of = [&](std::uint32_t v) { return verts[v].position; };
        const auto end_of = [&](std::uint32_t v) {
            return EdgeEnd{v, ring_indices(v), derived[v].single_sector ? nullptr : &ring_curve[rings[v].offset]};
        };
        if (takes_regular_edge_rule(scheme, s.interior, s.curve, e.a, e.b,
                                    [&](std::uint32_t v) { return regular_six(v); }))
            return regular_edge_point(scheme, end_of(e.a), end_of(e.b), s.c, s.d, position_of);
        // Kept by the thread so an edge's rings reuse their arrays, and only
        // schemes that read rings build them.
        thread_local VertexRing ring_a, ring_b;
        fill_edge_rings(end_of(e.a), end_of(e.b), position_of, ring_a, ring_b, s);
    }
    return scheme.edge_rule(s);
}

void Patch::fill_curve_end(std::uint32_t v, std::uint32_t other, bool& has_far, Vec3& far,
                           Vec3& normal) const {
    const VertexDerived& d = derived[v];
    const CurveEnd end = curve_end(d.curve_count, d.curve, other, d.single_sector);
    has_far = end.has_far;
    if (has_far) far = verts[end.far].position;
    normal = end.dart ? corner_normal[incident_slots[incident_offsets[v]]] : Vec3(0.0);
}

void Patch::compute_normal(const BaseTopology& topo, const SchemeRules& scheme, std::uint32_t v) {
    VertexDerived& dv = derived[v];
    const PatchVertex& pv = verts[v];
    // The given normals of a base vertex (normal scheme, level 0), else
    // angle-weighted Gouraud over the sector's triangles.
    const bool given = scheme.takes_given_normals && topo.has_given_normals() &&
                       pv.key.kind == VertexKey::base_vertex &&
                       (level == 0 || k_given_normals_every_level);
    // One normal per sector, summed in the canonical order (ring_pairs).
    const std::uint32_t first = incident_offsets[v], count = incident_offsets[v + 1] - first;
    FanScratch from_room, to_room, weight_room;
    Vec3* from = from_room.room(count);
    Vec3* to = to_room.room(count);
    Vec3* weight = weight_room.room(count);
    for (std::uint32_t k = 0; k < count; ++k) {
        const std::uint32_t slot = incident_slots[first + k];
        const PatchTriangle& t = tris[slot / 3];
        const std::uint32_t c = slot % 3;
        from[k] = verts[t.v[(c + 1) % 3]].position;
        to[k] = verts[t.v[(c + 2) % 3]].position;
    }
    angle_weighted_fan(pv.position, from, to, count, weight);
    if (given)
        for (std::uint32_t k = 0; k < count; ++k) {
            const Vec3 g = topo.given_normal(tris[incident_slots[first + k] / 3].id.face, pv.key.a);
            if (g != Vec3(0.0)) weight[k] = g;
        }
    if (dv.single_sector) {
        Vec3 sum(0.0);
        for (std::uint32_t k = 0; k < count; ++k) sum += weight[k];
        const Vec3 normal = finish_normal(sum);
        for (std::uint32_t k = 0; k < count; ++k) corner_normal[incident_slots[first + k]] = normal;
        dv.has_normal = true;
        return;
    }
    // Sectors as finish_vertex() labelled them.
    std::uint32_t sector_count = 1;
    for (std::uint32_t k = 0; k < count; ++k)
        sector_count = std::max<std::uint32_t>(sector_count, corner_sector[incident_slots[first + k]] + 1u);
    thread_local std::vector<Vec3> sums;
    sums.assign(sector_count, Vec3(0.0));
    for (std::uint32_t k = 0; k < count; ++k) sums[corner_sector[incident_slots[first + k]]] += weight[k];
    for (Vec3& sum : sums) sum = finish_normal(sum);
    for (std::uint32_t k = 0; k < count; ++k)
        corner_normal[incident_slots[first + k]] = sums[corner_sector[incident_slots[first + k]]];
    dv.has_normal = true;
}

void Patch::next_positions(const BaseTopology& topo, const SchemeRules& scheme, const Flags* needed,
                           Patch& next) {
    next.level = level + 1;
    next.verts.assign(verts.size() + edges.size(), PatchVertex{});
    next.draw.clear();
    compute_positions(topo, scheme, next, needed);
}

Flags Patch::points_around(const Flags& region) const {
    Flags needed(verts.size() + edges.size(), false);
    for (std::uint32_t t = 0; t < tris.size(); ++t) {
        if (!region[t]) continue;
        for (std::uint32_t v : tris[t].v) {
            if (needed[v]) continue;
            needed[v] = true;
            for (std::uint32_t k = incident_offsets[v]; k < incident_offsets[v + 1]; ++k) {
                const std::uint32_t slot = incident_slots[k];
                const std::uint32_t first = slot - slot % 3;
                needed[verts.size() + tri_edges[slot]] = true;                        // v -> next corner
                needed[verts.size() + tri_edges[first + (slot % 3 + 2) % 3]] = true;  // previous -> v
            }
        }
    }
    return needed;
}

namespace {

/// child_corners as indices into a parent triangle's six points (corners,
/// then edge points) and nine edge names (Patch::subdivide_topology).
struct ChildTables {
    std::uint8_t point[4][3];
    std::uint8_t name[4][3];
};

const ChildTables& child_tables(bool parent_down) {
    static const std::array<ChildTables, 2> tables = [] {
        std::array<ChildTables, 2> out{};
        for (int down = 0; down < 2; ++down)
            for (int c = 0; c < 4; ++c) {
                const auto& map = child_corners(down != 0, c);
                for (int k = 0; k < 3; ++k) {
                    const ChildCorner& p = map[k];
                    const ChildCorner& q = map[(k + 1) % 3];
                    out[down].point[c][k] = static_cast<std::uint8_t>(p.is_edge ? 3 + p.index : p.index);
                    if (p.is_edge && q.is_edge) {
                        // The inner edge between two edge points lies opposite the third.
                        out[down].name[c][k] = static_cast<std::uint8_t>(6 + (3 - p.index - q.index));
                    } else {
                        const ChildCorner& corner = p.is_edge ? q : p;
                        const ChildCorner& mid = p.is_edge ? p : q;
                        out[down].name[c][k] =
                            static_cast<std::uint8_t>(2 * mid.index + (corner.index == mid.index ? 0 : 1));
                    }
                }
            }
        return out;
    }();
    return tables[parent_down ? 1 : 0];
}

}  // namespace

Patch Patch::subdivide_topology(const BaseTopology& topo, const Flags& split) const {
    Patch next;
    next.level = level + 1;
    const std::uint32_t old_count = static_cast<std::uint32_t>(verts.size());
    next.verts.resize(old_count + edges.size());
    for (std::uint32_t v = 0; v < old_count; ++v) {
        next.verts[v].key = verts[v].key;
        next.verts[v].true_ring = verts[v].true_ring;
    }
    // Each split triangle becomes four, in the hierarchy's child order.
    const std::size_t split_count = static_cast<std::size_t>(std::count(split.begin(), split.end(), 1));
    next.tris.resize(4 * split_count);
    next.edge_names.resize(3 * next.tris.size());
    const std::uint32_t inner_names = 2 * static_cast<std::uint32_t>(edges.size());
    Flags keyed(edges.size(), false);
    const std::uint32_t triangle_count = static_cast<std::uint32_t>(tris.size());
    std::uint32_t first_child = 0;
    for (std::uint32_t t = 0; t < triangle_count; ++t) {
        if (!split[t]) continue;
        const PatchTriangle pt = tris[t];  // a copy: the stores below might alias it
        const auto grid = node_corner_grid(pt.id);
        for (int e = 0; e < 3; ++e) {
            const std::uint32_t edge = tri_edges[3 * t + e];
            if (keyed[edge]) continue;
            keyed[edge] = true;
            PatchVertex& nv = next.verts[old_count + edge];
            nv.key = topo.canonical(pt.id.face, level + 1, grid[e][0] + grid[(e + 1) % 3][0],
                                    grid[e][1] + grid[(e + 1) % 3][1]);
            nv.true_ring = true_incident_count(topo, nv.key);
        }
        // The children's corners (the parent's, then its edge points) and
        // edge names (edge_names): the half of parent edge e at its corner e,
        // the half at corner e + 1, then the inner edge opposite edge point k.
        std::uint32_t point[6];
        std::uint32_t name[9];
        for (int e = 0; e < 3; ++e) {
            const std::uint32_t id = tri_edges[3 * t + e];
            const PatchEdge& parent = edges[id];
            const std::uint32_t first_half = pt.v[e] == parent.a ? 0u : 1u;
            const std::uint32_t crease = parent.crease ? 1u : 0u;
            point[e] = pt.v[e];
            point[3 + e] = old_count + id;
            name[2 * e] = ((2 * id + first_half) << 1) | crease;
            name[2 * e + 1] = ((2 * id + (1u - first_half)) << 1) | crease;
            name[6 + e] = (inner_names + 3 * t + static_cast<std::uint32_t>(e)) << 1;
        }
        const ChildTables& table = child_tables(pt.id.down);
        for (int c = 0; c < 4; ++c) {
            PatchTriangle& child = next.tris[first_child + c];
            child.id = child_of(pt.id, c);
            std::uint32_t* child_names = &next.edge_names[3 * (first_child + c)];
            for (int k = 0; k < 3; ++k) {
                child.v[k] = point[table.point[c][k]];
                child_names[k] = name[table.name[c][k]];
            }
        }
        first_child += 4;
    }
    return next;
}

void Patch::compute_positions(const BaseTopology& topo, const SchemeRules& scheme, Patch& next,
                              const Flags* needed) {
    start_positions(scheme, next);
    const auto wanted = [&](std::uint32_t nv) { return needed == nullptr || (*needed)[nv]; };
    const std::uint32_t old_count = static_cast<std::uint32_t>(verts.size());
    if (scheme.moves_old_vertices())
        for (std::uint32_t v = 0; v < old_count; ++v)
            if (wanted(v)) compute_point(topo, scheme, next, v);
    // An edge point the caller does not keep is skipped: its endpoints'
    // displacement is then only read where all their edges' points are kept
    // (the region's corners, patch.h).
    for (std::uint32_t e = 0; e < edges.size(); ++e)
        if (wanted(old_count + e)) compute_point(topo, scheme, next, old_count + e);
}

void Patch::start_positions(const SchemeRules& scheme, Patch& next) {
    const std::uint32_t old_count = static_cast<std::uint32_t>(verts.size());
    // Old vertices: interpolating schemes keep them (Loop moves them in
    // compute_point).
    if (!draw.empty()) {
        next.draw.assign(next.verts.size(), Vec3(0.0));
        std::copy(draw.begin(), draw.end(), next.draw.begin());
    }
    for (std::uint32_t v = 0; v < old_count; ++v) {
        const PatchVertex& pv = verts[v];
        PatchVertex& nv = next.verts[v];
        nv.has_draw = pv.has_draw;
        if (!scheme.moves_old_vertices()) {
            nv.position = pv.position;
            nv.has_position = pv.has_position;
        }
        derived[v].displacement = 0.0;
        derived[v].deviation = 0.0;
        derived[v].has_displacement = derived[v].has_ring;
    }
    // An edge point that cannot be computed leaves its endpoints'
    // displacement incomplete.
    for (std::uint32_t e = 0; e < edges.size(); ++e) {
        PatchEdge& edge = edges[e];
        edge.point = old_count + e;
        if (!edge.valid) {
            derived[edge.a].has_displacement = false;
            derived[edge.b].has_displacement = false;
        }
    }
}

void Patch::compute_point(const BaseTopology& topo, const SchemeRules& scheme, Patch& next,
                          std::uint32_t point) {
    const std::uint32_t old_count = static_cast<std::uint32_t>(verts.size());
    PatchVertex& nv = next.verts[point];
    if (point < old_count) {
        // Loop moves old vertices (the others were copied by start_positions).
        if (!scheme.moves_old_vertices() || !derived[point].has_ring) return;
        thread_local VertexRing ring;
        fill_vertex_ring(point, ring);
        nv.position = scheme.vertex_rule(ring);
        nv.has_position = true;
        return;
    }
    // An edge point, and the displacement it causes at its endpoints (a
    // maximum: the same bits in whatever order points are computed).
    const PatchEdge& edge = edges[point - old_count];
    if (!edge.valid) return;
    if (scheme.edge_rule_reads_normals) {
        ensure_normal(topo, scheme, edge.a);
        ensure_normal(topo, scheme, edge.b);
    }
    nv.position = edge_point(scheme, edge);
    nv.has_position = true;
    const Vec3 offset = nv.position - (verts[edge.a].position + verts[edge.b].position) * 0.5;
    const double d = glm::length(offset);
    const double deviation = scheme.sagitta_per_normal_offset * normal_offset(*this, edge, offset);
    for (const std::uint32_t end : {edge.a, edge.b}) {
        derived[end].displacement = std::max(derived[end].displacement, d);
        derived[end].deviation = std::max(derived[end].deviation, deviation);
    }
}

void Patch::add_points_around(const BaseTopology& topo, const SchemeRules& scheme,
                              const std::vector<std::uint32_t>& region, Patch& next, Flags& done) {
    const std::uint32_t old_count = static_cast<std::uint32_t>(verts.size());
    const auto add = [&](std::uint32_t point) {
        if (done[point]) return;
        done[point] = 1;
        compute_point(topo, scheme, next, point);
    };
    // As points_around: each corner, and the edge points at it.
    for (std::uint32_t t : region) {
        for (std::uint32_t v : tris[t].v) {
            if (done[v]) continue;  // its edge points were added with it
            add(v);
            for (std::uint32_t k = incident_offsets[v]; k < incident_offsets[v + 1]; ++k) {
                const std::uint32_t slot = incident_slots[k];
                const std::uint32_t first = slot - slot % 3;
                add(old_count + tri_edges[slot]);                        // v -> next corner
                add(old_count + tri_edges[first + (slot % 3 + 2) % 3]);  // previous -> v
            }
        }
    }
}

Patch Patch::copy_of(const Patch& src, const Flags& keep) {
    std::vector<std::uint32_t> kept;
    kept.reserve(static_cast<std::size_t>(std::count(keep.begin(), keep.end(), true)));
    for (std::uint32_t t = 0; t < src.tris.size(); ++t)
        if (keep[t]) kept.push_back(t);
    return copy_of(src, kept);
}

Patch Patch::copy_of(const Patch& src, const std::vector<std::uint32_t>& kept) {
    Patch out;
    out.level = src.level;
    // New index of each source vertex; only the entries set here are reset
    // after, so a small copy of a large patch stays small.
    thread_local std::vector<std::uint32_t> remap;
    if (remap.size() < src.verts.size()) remap.resize(src.verts.size(), UINT32_MAX);
    out.tris.reserve(kept.size());
    // A patch has fewer vertices than triangles, but for a sliver of a border.
    out.verts.reserve(std::min(src.verts.size(), kept.size() + 8));
    if (!src.draw.empty()) out.draw.reserve(out.verts.capacity());
    thread_local std::vector<std::uint32_t> sources;
    sources.clear();
    // Names carried where the source has them (else finish() names the copy).
    const bool named = src.edge_names.size() == 3 * src.tris.size();
    if (named) out.edge_names.reserve(3 * kept.size());
    for (std::uint32_t t : kept) {
        if (named)
            out.edge_names.insert(out.edge_names.end(), src.edge_names.begin() + 3 * t,
                                  src.edge_names.begin() + 3 * t + 3);
        // Written in place (out.tris has the room): a copy on the stack
        // whose corners were rewritten one by one was read back whole, which
        // stalled on store forwarding (nearly half of this function's time).
        const PatchTriangle& from = src.tris[t];
        PatchTriangle& tri = out.tris.emplace_back();
        tri.id = from.id;
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t v = from.v[k];
            if (remap[v] == UINT32_MAX) {
                remap[v] = static_cast<std::uint32_t>(out.verts.size());
                sources.push_back(v);
                out.verts.push_back(src.verts[v]);
                if (!src.draw.empty()) out.draw.push_back(src.draw[v]);
            }
            tri.v[k] = remap[v];
        }
    }
    for (std::uint32_t v : sources) remap[v] = UINT32_MAX;
    return out;
}

std::vector<std::uint32_t> Patch::band_around(const std::vector<std::uint32_t>& region) const {
    // As band(): the region's vertices, then every vertex of a triangle at
    // one of them; the band is every triangle at any of those. Marks are
    // reset after use, so only the band's own size is paid for.
    if (!has_incidence())
        throw std::logic_error("subdivtrace tile: a band cut from a patch without incident lists "
                               "(Tile::below_deepest and finish() build them)");
    thread_local std::vector<std::uint8_t> vertex_mark, triangle_mark;
    thread_local std::vector<std::uint32_t> near;
    if (vertex_mark.size() < verts.size()) vertex_mark.resize(verts.size(), 0);
    if (triangle_mark.size() < tris.size()) triangle_mark.resize(tris.size(), 0);
    near.clear();
    const auto add = [&](std::uint32_t v) {
        if (vertex_mark[v]) return;
        vertex_mark[v] = 1;
        near.push_back(v);
    };
    for (std::uint32_t t : region)
        for (std::uint32_t v : tris[t].v) add(v);
    const std::size_t region_vertices = near.size();
    for (std::size_t k = 0; k < region_vertices; ++k) {
        const std::uint32_t v = near[k];
        for (std::uint32_t s = incident_offsets[v]; s < incident_offsets[v + 1]; ++s)
            for (std::uint32_t w : tris[incident_slots[s] / 3].v) add(w);
    }
    // Collected in scratch, returned in one allocation of its own size.
    thread_local std::vector<std::uint32_t> found;
    found.clear();
    for (std::uint32_t v : near) {
        for (std::uint32_t s = incident_offsets[v]; s < incident_offsets[v + 1]; ++s) {
            const std::uint32_t t = incident_slots[s] / 3;
            if (triangle_mark[t]) continue;
            triangle_mark[t] = 1;
            found.push_back(t);
        }
        vertex_mark[v] = 0;
    }
    if (found.empty()) return {};
    // Ascending: a scan of the marks between the lowest and highest where
    // they lie close (a tile's band in its group's level), else a sort.
    const auto [low, high] = std::minmax_element(found.begin(), found.end());
    const std::uint32_t first = *low, last = *high;
    if (last - first <= 16 * found.size()) {
        std::vector<std::uint32_t> band;
        band.reserve(found.size());
        for (std::uint32_t t = first; t <= last; ++t)
            if (triangle_mark[t]) {
                triangle_mark[t] = 0;
                band.push_back(t);
            }
        return band;
    }
    for (std::uint32_t t : found) triangle_mark[t] = 0;
    std::sort(found.begin(), found.end());
    return std::vector<std::uint32_t>(found.begin(), found.end());
}

void Patch::trim_to(const Flags& keep) {
    // Derived data (rings, edges) refers to the old indices: rebuilt later.
    *this = copy_of(*this, keep);
}

Patch base_patch(const BaseTopology& topo, const std::uint32_t* region, std::size_t count,
                 BasePatchScratch* scratch) {
    // Faces touching the region's corners or their neighbours (the trim
    // rule at level 0), collected through the vertex-face lists. Vertices
    // and faces are deduplicated by stamps sized to the mesh when there is
    // scratch (large regions), else by tables sized to the region (a chunk's
    // or a tile's few faces; sorting them had been 4% of a render of a fine
    // mesh). Either way in linear time, and the vertices come in the order
    // first met: values do not depend on it (every sum runs in the order of
    // the triangles, patch.h).
    const Mesh& mesh = topo.mesh();
    const bool stamped = scratch != nullptr;
    thread_local IdTable near_table, face_table, local_table;
    if (stamped) {
        scratch->vertex_stamp.resize(mesh.positions.size(), 0);
        scratch->face_stamp.resize(mesh.triangles.size(), 0);
        scratch->local_index.resize(mesh.positions.size(), 0);
        ++scratch->generation;
    } else {
        near_table.clear();
        face_table.clear();
        local_table.clear();
    }
    const auto first_time = [&](std::vector<std::uint32_t>& stamp, std::uint32_t x) {
        if (stamp[x] == scratch->generation) return false;
        stamp[x] = scratch->generation;
        return true;
    };
    const auto first_near = [&](std::uint32_t v) {
        return stamped ? first_time(scratch->vertex_stamp, v) : near_table.insert(v);
    };
    const auto first_face = [&](std::uint32_t f) {
        return stamped ? first_time(scratch->face_stamp, f) : face_table.insert(f);
    };
    // A large region has its own lists; a small one reuses this thread's
    // (growing these from empty was most of a tile's allocations).
    std::vector<std::uint32_t> own_near, own_faces, own_local;
    thread_local std::vector<std::uint32_t> small_near, small_faces, small_local;
    std::vector<std::uint32_t>& near_vertices = stamped ? own_near : small_near;
    std::vector<std::uint32_t>& faces = stamped ? own_faces : small_faces;
    std::vector<std::uint32_t>& local = stamped ? own_local : small_local;
    near_vertices.clear();
    for (std::size_t k = 0; k < count; ++k)
        for (std::uint32_t c : mesh.triangles[region[k]])
            for (std::uint32_t f : topo.faces_of_vertex(c))
                for (std::uint32_t v : mesh.triangles[f])
                    if (first_near(v)) near_vertices.push_back(v);
    faces.clear();
    for (std::uint32_t v : near_vertices)
        for (std::uint32_t f : topo.faces_of_vertex(v))
            if (first_face(f)) faces.push_back(f);
    // Ascending faces: records and their split corners come out in face order.
    std::sort(faces.begin(), faces.end());

    Patch p;
    p.level = 0;
    local.clear();  // base vertex ids of the patch's vertices
    if (stamped) ++scratch->generation;  // vertex_stamp now marks the patch's vertices
    for (std::uint32_t f : faces)
        for (std::uint32_t v : mesh.triangles[f]) {
            const auto index = static_cast<std::uint32_t>(local.size());
            if (stamped ? first_time(scratch->vertex_stamp, v) : local_table.insert(v, index)) {
                if (stamped) scratch->local_index[v] = index;
                local.push_back(v);
            }
        }
    p.verts.resize(local.size());
    for (std::size_t k = 0; k < local.size(); ++k) {
        PatchVertex& pv = p.verts[k];
        pv.key.kind = VertexKey::base_vertex;
        pv.key.a = local[k];
        pv.position = mesh.positions[local[k]];
        pv.has_position = true;
        pv.true_ring = true_incident_count(topo, pv.key);
    }
    p.tris.reserve(faces.size());
    for (std::uint32_t f : faces) {
        PatchTriangle t;
        t.id = root_node(f);
        for (int c = 0; c < 3; ++c) {
            const std::uint32_t v = mesh.triangles[f][c];
            t.v[c] = stamped ? scratch->local_index[v] : local_table.at(v);
        }
        p.tris.push_back(t);
    }
    return p;
}

}  // namespace subdivtrace::detail
