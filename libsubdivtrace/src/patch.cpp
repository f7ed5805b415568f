#include "patch.h"

#include <algorithm>

#include <glm/geometric.hpp>

#include "ring_order.h"

namespace subdivtrace::detail {

namespace {

/// How many triangles of a uniform level meet at the vertex `key` (its whole
/// ring): one per base face at a base vertex, three per face along a base
/// edge, six inside a face.
std::uint16_t true_incident_count(const BaseTopology& topo, const VertexKey& key) {
    // Saturates: a count this large never matches a patch's (it would need
    // 65535 triangles at one vertex), so such a vertex is simply never whole.
    std::size_t n = 6;
    if (key.kind == VertexKey::base_vertex) n = topo.faces_of_vertex(key.a).size();
    else if (key.kind == VertexKey::edge_point) n = 3 * topo.edge_face_count(key.a, key.b);
    return static_cast<std::uint16_t>(std::min<std::size_t>(n, UINT16_MAX));
}

}  // namespace

void Patch::finish(SchemeKind scheme) {
    const std::size_t n = verts.size();
    // Incident (triangle, corner) slots per vertex, CSR.
    std::vector<std::uint32_t>& offsets = incident_offsets;
    std::vector<std::uint32_t>& slots = incident_slots;
    offsets.assign(n + 1, 0);
    for (const PatchTriangle& t : tris)
        for (std::uint32_t v : t.v) ++offsets[v + 1];
    for (std::size_t v = 0; v < n; ++v) offsets[v + 1] += offsets[v];
    slots.resize(offsets.back());
    {
        std::vector<std::uint32_t> fill(offsets.begin(), offsets.end() - 1);
        for (std::uint32_t t = 0; t < tris.size(); ++t)
            for (std::uint32_t c = 0; c < 3; ++c) slots[fill[tris[t].v[c]]++] = 3 * t + c;
    }

    rings.assign(n, Ring{});
    derived.assign(n, VertexDerived{});
    ring_nbrs.clear();
    std::vector<FanPair<std::uint32_t>> pairs;
    OrderedRing<std::uint32_t> ordered;
    const auto eq = [](std::uint32_t x, std::uint32_t y) { return x == y; };
    const auto pair_less = [&](const FanPair<std::uint32_t>& x, const FanPair<std::uint32_t>& y) {
        if (x.from != y.from) return key_less(verts[x.from].key, verts[y.from].key);
        return key_less(verts[x.to].key, verts[y.to].key);
    };
    VertexRing ring;
    for (std::uint32_t v = 0; v < n; ++v) {
        PatchVertex& pv = verts[v];
        VertexDerived& dv = derived[v];
        const std::uint32_t count = offsets[v + 1] - offsets[v];
        dv.has_ring = pv.has_position && count == pv.true_ring;
        if (!dv.has_ring) continue;
        // The canonical order: pairs sorted by key, so every patch that holds
        // this whole ring sums and walks it in the same order.
        pairs.clear();
        bool ring_positions = true;
        for (std::uint32_t k = offsets[v]; k < offsets[v + 1]; ++k) {
            const PatchTriangle& t = tris[slots[k] / 3];
            const std::uint32_t c = slots[k] % 3;
            pairs.push_back({t.v[(c + 1) % 3], t.v[(c + 2) % 3]});
            ring_positions = ring_positions && verts[pairs.back().from].has_position &&
                             verts[pairs.back().to].has_position;
        }
        if (!ring_positions) {
            dv.has_ring = false;
            continue;
        }
        std::sort(pairs.begin(), pairs.end(), pair_less);
        if (scheme != SchemeKind::normal) {
            // Loop's and Butterfly's stencils read the ordered ring; the
            // normal scheme only sums the pairs.
            order_ring(pairs, ordered, eq);
            Ring& r = rings[v];
            r.offset = static_cast<std::uint32_t>(ring_nbrs.size());
            r.count = static_cast<std::uint32_t>(ordered.nbrs.size());
            r.closed = ordered.closed;
            r.regular = ordered.regular;
            ring_nbrs.insert(ring_nbrs.end(), ordered.nbrs.begin(), ordered.nbrs.end());
        }

        Vec3 sum(0.0);
        for (const auto& pr : pairs)
            sum += angle_weighted_normal(pv.position, verts[pr.from].position, verts[pr.to].position);
        dv.normal = finish_normal(sum);
        dv.has_normal = true;
        if (scheme == SchemeKind::loop && pv.key.level == level) {
            // Loop draws a vertex at its limit point, from its birth-level ring.
            fill_vertex_ring(v, ring);
            pv.draw = loop_limit_point(ring);
            pv.has_draw = true;
        }
    }
    if (scheme != SchemeKind::loop) {
        for (PatchVertex& pv : verts) {
            pv.draw = pv.position;
            pv.has_draw = pv.has_position;
        }
    }
}

void Patch::fill_vertex_ring(std::uint32_t v, VertexRing& ring) const {
    const Ring& r = rings[v];
    ring.center = verts[v].position;
    ring.closed = r.closed;
    ring.regular = r.regular;
    ring.nbrs.clear();
    for (std::uint32_t k = 0; k < r.count; ++k) ring.nbrs.push_back(verts[ring_nbrs[r.offset + k]].position);
}

void Patch::drop_derived() {
    derived = {};
    rings = {};
    ring_nbrs = {};
    incident_offsets = {};
    incident_slots = {};
    edges = {};
    tri_edges = {};
    verts.shrink_to_fit();
    tris.shrink_to_fit();
}

std::size_t Patch::owned_bytes() const {
    return verts.capacity() * sizeof(PatchVertex) + tris.capacity() * sizeof(PatchTriangle) +
           derived.capacity() * sizeof(VertexDerived) +
           rings.capacity() * sizeof(Ring) + ring_nbrs.capacity() * sizeof(std::uint32_t) +
           (incident_offsets.capacity() + incident_slots.capacity()) * sizeof(std::uint32_t) +
           edges.capacity() * sizeof(PatchEdge) + tri_edges.capacity() * sizeof(std::uint32_t);
}

namespace {

/// True if edge e of grid triangle `id` lies on its base triangle's boundary.
bool on_base_triangle_boundary(const NodeId& id, int e) {
    const auto g = node_corner_grid(id);
    const auto& p = g[e];
    const auto& q = g[(e + 1) % 3];
    const std::uint32_t n = std::uint32_t{1} << id.level;
    return (p[0] == 0 && q[0] == 0) || (p[1] == 0 && q[1] == 0) ||
           (p[0] + p[1] == n && q[0] + q[1] == n);
}

}  // namespace

void Patch::build_edges() {
    // Every edge once, found through the incident triangles of its endpoint
    // (finish() built them): the triangles on edge (u, w) all meet u.
    constexpr std::uint32_t k_unset = UINT32_MAX;
    edges.clear();
    tri_edges.assign(3 * tris.size(), k_unset);
    for (std::uint32_t t = 0; t < tris.size(); ++t) {
        for (std::uint32_t e = 0; e < 3; ++e) {
            if (tri_edges[3 * t + e] != k_unset) continue;
            const std::uint32_t u = tris[t].v[e], w = tris[t].v[(e + 1) % 3];
            const std::uint32_t id = static_cast<std::uint32_t>(edges.size());
            // An edge inside a base triangle belongs to that triangle alone
            // (its point is a face point): a duplicate base triangle over the
            // same vertices has its own. Edges on a base edge are shared.
            const bool on_base_edge = on_base_triangle_boundary(tris[t].id, e);
            PatchEdge edge;
            for (std::uint32_t k = incident_offsets[u]; k < incident_offsets[u + 1]; ++k) {
                const std::uint32_t slot = incident_slots[k];
                const PatchTriangle& other = tris[slot / 3];
                if (!on_base_edge && other.id.face != tris[t].id.face) continue;
                const std::uint32_t c = slot % 3;
                std::uint32_t edge_slot;
                if (other.v[(c + 1) % 3] == w) edge_slot = slot;                    // u -> w
                else if (other.v[(c + 2) % 3] == w) edge_slot = slot - c + (c + 2) % 3;  // w -> u
                else continue;
                tri_edges[edge_slot] = id;
                if (edge.slot_count < 2) edge.slot[edge.slot_count] = edge_slot;
                ++edge.slot_count;
            }
            const bool u_first = key_less(verts[u].key, verts[w].key);
            edge.a = u_first ? u : w;
            edge.b = u_first ? w : u;
            edge.valid = derived[edge.a].has_ring && derived[edge.b].has_ring;
            edges.push_back(edge);
        }
    }
}

Vec3 Patch::edge_point(SchemeKind scheme, const PatchEdge& e) const {
    EdgeStencil s;
    s.a = verts[e.a].position;
    s.b = verts[e.b].position;
    if (scheme == SchemeKind::normal) {
        s.normal_a = derived[e.a].normal;
        s.normal_b = derived[e.b].normal;
        return subdivtrace::edge_point(scheme, s);
    }
    // As LevelTopology: interior when exactly two triangles share the edge;
    // c is the third vertex of the one that runs a -> b, d of the other.
    s.interior = e.slot_count == 2;
    if (s.interior) {
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
    const Ring& ra = rings[e.a];
    VertexRing ring_a, ring_b;
    if (scheme == SchemeKind::butterfly) {
        fill_vertex_ring(e.a, ring_a);
        fill_vertex_ring(e.b, ring_b);
        const Ring& rb = rings[e.b];
        for (std::uint32_t k = 0; k < ra.count; ++k)
            if (ring_nbrs[ra.offset + k] == e.b) s.index_b_in_a = k;
        for (std::uint32_t k = 0; k < rb.count; ++k)
            if (ring_nbrs[rb.offset + k] == e.a) s.index_a_in_b = k;
        s.ring_a = &ring_a;
        s.ring_b = &ring_b;
    }
    return subdivtrace::edge_point(scheme, s);
}

Patch Patch::subdivide(const BaseTopology& topo, SchemeKind scheme, bool with_triangles) {
    build_edges();
    Patch next;
    next.level = level + 1;
    const std::uint32_t old_count = static_cast<std::uint32_t>(verts.size());
    next.verts.resize(old_count + edges.size());

    // Old vertices: interpolating schemes keep them; Loop moves them.
    VertexRing ring;
    for (std::uint32_t v = 0; v < old_count; ++v) {
        const PatchVertex& pv = verts[v];
        PatchVertex& nv = next.verts[v];
        nv.key = pv.key;
        nv.true_ring = pv.true_ring;
        nv.draw = pv.draw;
        nv.has_draw = pv.has_draw;
        if (scheme != SchemeKind::loop) {
            nv.position = pv.position;
            nv.has_position = pv.has_position;
        } else if (derived[v].has_ring) {
            fill_vertex_ring(v, ring);
            nv.position = loop_vertex_point(ring);
            nv.has_position = true;
        }
        derived[v].displacement = 0.0;
        derived[v].has_displacement = derived[v].has_ring;
    }

    // Edge points, and the displacement each causes at its endpoints.
    for (std::uint32_t e = 0; e < edges.size(); ++e) {
        PatchEdge& edge = edges[e];
        edge.point = old_count + e;
        PatchVertex& nv = next.verts[edge.point];
        if (!edge.valid) {
            derived[edge.a].has_displacement = false;
            derived[edge.b].has_displacement = false;
            continue;
        }
        nv.position = edge_point(scheme, edge);
        nv.has_position = true;
        const double d = glm::length(nv.position - (verts[edge.a].position + verts[edge.b].position) * 0.5);
        derived[edge.a].displacement = std::max(derived[edge.a].displacement, d);
        derived[edge.b].displacement = std::max(derived[edge.b].displacement, d);
    }

    if (!with_triangles) return next;
    // Each triangle becomes four, in the hierarchy's child order.
    next.tris.resize(4 * tris.size());
    std::vector<bool> keyed(edges.size(), false);
    for (std::uint32_t t = 0; t < tris.size(); ++t) {
        const PatchTriangle& pt = tris[t];
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
        for (int c = 0; c < 4; ++c) {
            PatchTriangle& child = next.tris[4 * t + c];
            child.id = child_of(pt.id, c);
            const auto& map = child_corners(pt.id.down, c);
            for (int k = 0; k < 3; ++k) {
                child.v[k] = map[k].is_edge ? old_count + tri_edges[3 * t + map[k].index]
                                            : pt.v[map[k].index];
            }
        }
    }
    return next;
}

Patch Patch::copy_of(const Patch& src, const std::vector<bool>& keep) {
    Patch out;
    out.level = src.level;
    std::vector<std::uint32_t> remap(src.verts.size(), UINT32_MAX);
    for (std::size_t t = 0; t < src.tris.size(); ++t) {
        if (!keep[t]) continue;
        PatchTriangle tri = src.tris[t];
        for (std::uint32_t& v : tri.v) {
            if (remap[v] == UINT32_MAX) {
                remap[v] = static_cast<std::uint32_t>(out.verts.size());
                out.verts.push_back(src.verts[v]);
            }
            v = remap[v];
        }
        out.tris.push_back(tri);
    }
    return out;
}

void Patch::trim_to(const std::vector<bool>& keep) {
    // Derived data (rings, edges) refers to the old indices: rebuilt later.
    *this = copy_of(*this, keep);
}

Patch base_patch(const BaseTopology& topo, std::uint32_t face) {
    // Faces touching the face's corners or their neighbours (the trim rule
    // at level 0), collected through the vertex-face lists.
    const Mesh& mesh = topo.mesh();
    std::vector<std::uint32_t> near_vertices(mesh.triangles[face].begin(), mesh.triangles[face].end());
    for (std::uint32_t c : mesh.triangles[face])
        for (std::uint32_t f : topo.faces_of_vertex(c))
            for (std::uint32_t v : mesh.triangles[f]) near_vertices.push_back(v);
    std::sort(near_vertices.begin(), near_vertices.end());
    near_vertices.erase(std::unique(near_vertices.begin(), near_vertices.end()), near_vertices.end());
    std::vector<std::uint32_t> faces;
    for (std::uint32_t v : near_vertices)
        for (std::uint32_t f : topo.faces_of_vertex(v)) faces.push_back(f);
    std::sort(faces.begin(), faces.end());
    faces.erase(std::unique(faces.begin(), faces.end()), faces.end());

    Patch p;
    p.level = 0;
    std::vector<std::uint32_t> local;  // sorted base vertex ids
    for (std::uint32_t f : faces)
        for (std::uint32_t v : mesh.triangles[f]) local.push_back(v);
    std::sort(local.begin(), local.end());
    local.erase(std::unique(local.begin(), local.end()), local.end());
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
        t.id = Hierarchy::root(f);
        for (int c = 0; c < 3; ++c) {
            t.v[c] = static_cast<std::uint32_t>(
                std::lower_bound(local.begin(), local.end(), mesh.triangles[f][c]) - local.begin());
        }
        p.tris.push_back(t);
    }
    return p;
}

Patch whole_base_patch(const BaseTopology& topo) {
    const Mesh& mesh = topo.mesh();
    Patch p;
    p.level = 0;
    p.verts.resize(mesh.positions.size());
    for (std::uint32_t v = 0; v < mesh.positions.size(); ++v) {
        p.verts[v].key.kind = VertexKey::base_vertex;
        p.verts[v].key.a = v;
        p.verts[v].position = mesh.positions[v];
        p.verts[v].has_position = true;
        p.verts[v].true_ring = true_incident_count(topo, p.verts[v].key);
    }
    p.tris.resize(mesh.triangles.size());
    for (std::uint32_t f = 0; f < mesh.triangles.size(); ++f) {
        p.tris[f].id = Hierarchy::root(f);
        p.tris[f].v = mesh.triangles[f];
    }
    return p;
}

}  // namespace subdivtrace::detail
