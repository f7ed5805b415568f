#include "vertex_eval.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace subdivtrace::detail {

namespace {

enum What : std::uint8_t { k_position = 0, k_normal = 1, k_draw = 2, k_displacement = 3 };

const auto key_eq = [](const VertexKey& x, const VertexKey& y) { return x == y; };

/// The two level-(L-1) grid points whose edge grid point (i, j) of level L
/// halves. Exactly two of the weights (n - i - j, i, j) are odd.
void parent_edge(std::uint32_t i, std::uint32_t j, std::uint32_t p[4]) {
    if (i % 2 == 1 && j % 2 == 1) {
        p[0] = i - 1, p[1] = j + 1, p[2] = i + 1, p[3] = j - 1;
    } else if (i % 2 == 1) {
        p[0] = i - 1, p[1] = j, p[2] = i + 1, p[3] = j;
    } else {
        p[0] = i, p[1] = j - 1, p[2] = i, p[3] = j + 1;
    }
    for (int k = 0; k < 4; ++k) p[k] /= 2;
}

}  // namespace

VertexEvaluator::VertexEvaluator(const BaseTopology& topo, SchemeKind scheme,
                                 std::size_t budget_bytes)
    : topo_(topo), scheme_(scheme), cache_(budget_bytes) {}

Vec3 VertexEvaluator::lookup(const EvalKey& key, EvalScratch& scratch) {
    Vec3 value;
    if (scratch.find(key, value)) return value;
    if (!cache_.lookup(key, value)) {
        value = compute(key, scratch);
        cache_.insert(key, value);
    }
    scratch.insert(key, value);
    return value;
}

Vec3 VertexEvaluator::position(const VertexKey& v, int level, EvalScratch& scratch) {
    // Interpolating schemes never move a vertex: one entry, at its birth level.
    const int at = is_interpolating(scheme_) ? v.level : level;
    return lookup({v, static_cast<std::uint8_t>(at), k_position}, scratch);
}

Vec3 VertexEvaluator::normal(const VertexKey& v, int level, EvalScratch& scratch) {
    return lookup({v, static_cast<std::uint8_t>(level), k_normal}, scratch);
}

Vec3 VertexEvaluator::draw_position(const VertexKey& v, EvalScratch& scratch) {
    if (is_interpolating(scheme_)) return position(v, v.level, scratch);
    return lookup({v, v.level, k_draw}, scratch);
}

Vec3 VertexEvaluator::compute(const EvalKey& key, EvalScratch& scratch) {
    switch (key.what) {
        case k_position: return compute_position(key.vertex, key.level, scratch);
        case k_normal: return compute_normal(key.vertex, key.level, scratch);
        case k_displacement: return compute_edge_displacement(key.vertex, key.level, scratch);
        default: return compute_draw_position(key.vertex, scratch);
    }
}

double VertexEvaluator::edge_displacement(const VertexKey& v, int level, EvalScratch& scratch) {
    return lookup({v, static_cast<std::uint8_t>(level), k_displacement}, scratch).x;
}

Vec3 VertexEvaluator::compute_edge_displacement(const VertexKey& v, int level,
                                                EvalScratch& scratch) {
    std::vector<GridPoint> reps;
    topo_.representations(v, level, reps);
    const std::uint32_t n = std::uint32_t{1} << level;
    const Vec3 pv = position(v, level, scratch);
    double largest = 0.0;
    for (const GridPoint& g : reps) {
        for_each_incident_grid_triangle(
            n, g.i, g.j, [&](std::uint32_t i1, std::uint32_t j1, std::uint32_t, std::uint32_t) {
                const VertexKey q = topo_.canonical(g.face, level, i1, j1);
                const VertexKey mid = topo_.canonical(g.face, level + 1, g.i + i1, g.j + j1);
                const Vec3 pq = position(q, level, scratch);
                const Vec3 pm = position(mid, level + 1, scratch);
                largest = std::max(largest, glm::length(pm - (pv + pq) * 0.5));
            });
    }
    return Vec3(largest, 0.0, 0.0);
}

void VertexEvaluator::incident_pairs(const VertexKey& v, int level, KeyPairs& out) const {
    out.clear();
    std::vector<GridPoint> reps;
    topo_.representations(v, level, reps);
    const std::uint32_t n = std::uint32_t{1} << level;
    for (const GridPoint& g : reps) {
        for_each_incident_grid_triangle(
            n, g.i, g.j, [&](std::uint32_t i1, std::uint32_t j1, std::uint32_t i2, std::uint32_t j2) {
                out.push_back({topo_.canonical(g.face, level, i1, j1),
                               topo_.canonical(g.face, level, i2, j2)});
            });
    }
}

void VertexEvaluator::fill_ring(const VertexKey& v, int level, VertexRing& ring,
                                OrderedRing<VertexKey>& ordered, EvalScratch& scratch) {
    KeyPairs pairs;
    incident_pairs(v, level, pairs);
    order_ring(pairs, ordered, key_eq);
    ring.center = position(v, level, scratch);
    ring.closed = ordered.closed;
    ring.regular = ordered.regular;
    ring.nbrs.clear();
    for (const VertexKey& q : ordered.nbrs) ring.nbrs.push_back(position(q, level, scratch));
}

Vec3 VertexEvaluator::compute_position(const VertexKey& v, int level, EvalScratch& scratch) {
    if (level == 0) return topo_.mesh().positions[v.a];
    if (level > v.level) {
        // An old vertex: only Loop moves it (interpolating schemes never get here).
        VertexRing ring;
        OrderedRing<VertexKey> ordered;
        fill_ring(v, level - 1, ring, ordered, scratch);
        return loop_vertex_point(ring);
    }
    // Born at this level: the edge rule on its parent edge at level - 1.
    std::vector<GridPoint> reps;
    topo_.representations(v, level, reps);
    const GridPoint& g = reps.front();
    std::uint32_t p[4];
    parent_edge(g.i, g.j, p);
    const VertexKey a = topo_.canonical(g.face, level - 1, p[0], p[1]);
    const VertexKey b = topo_.canonical(g.face, level - 1, p[2], p[3]);
    return edge_rule(a, b, level - 1, scratch);
}

Vec3 VertexEvaluator::edge_rule(const VertexKey& a, const VertexKey& b, int level,
                                EvalScratch& scratch) {
    EdgeStencil s;
    s.a = position(a, level, scratch);
    s.b = position(b, level, scratch);
    if (scheme_ == SchemeKind::normal) {
        s.normal_a = normal(a, level, scratch);
        s.normal_b = normal(b, level, scratch);
        return edge_point(scheme_, s);
    }
    // Opposite vertices from a's incident triangles that contain b: c in the
    // triangle that runs a -> b, d in the one that runs b -> a.
    KeyPairs pairs;
    incident_pairs(a, level, pairs);
    std::vector<VertexKey> opposite;
    for (const auto& pr : pairs)
        if (pr.from == b) opposite.insert(opposite.begin(), pr.to);
    for (const auto& pr : pairs)
        if (pr.to == b) opposite.push_back(pr.from);
    s.interior = opposite.size() == 2;
    if (s.interior) {
        s.c = position(opposite[0], level, scratch);
        s.d = position(opposite[1], level, scratch);
    }
    VertexRing ring_a, ring_b;
    if (scheme_ == SchemeKind::butterfly) {
        OrderedRing<VertexKey> ordered_a, ordered_b;
        fill_ring(a, level, ring_a, ordered_a, scratch);
        fill_ring(b, level, ring_b, ordered_b, scratch);
        for (std::size_t k = 0; k < ordered_a.nbrs.size(); ++k)
            if (ordered_a.nbrs[k] == b) s.index_b_in_a = k;
        for (std::size_t k = 0; k < ordered_b.nbrs.size(); ++k)
            if (ordered_b.nbrs[k] == a) s.index_a_in_b = k;
        s.ring_a = &ring_a;
        s.ring_b = &ring_b;
    }
    return edge_point(scheme_, s);
}

Vec3 VertexEvaluator::compute_normal(const VertexKey& v, int level, EvalScratch& scratch) {
    KeyPairs pairs;
    incident_pairs(v, level, pairs);
    const Vec3 p = position(v, level, scratch);
    Vec3 sum(0.0);
    for (const auto& pr : pairs) {
        sum += angle_weighted_normal(p, position(pr.from, level, scratch),
                                     position(pr.to, level, scratch));
    }
    return finish_normal(sum);
}

Vec3 VertexEvaluator::compute_draw_position(const VertexKey& v, EvalScratch& scratch) {
    // Loop's limit point, from the ring at the vertex's birth level.
    VertexRing ring;
    OrderedRing<VertexKey> ordered;
    fill_ring(v, v.level, ring, ordered, scratch);
    return loop_limit_point(ring);
}

}  // namespace subdivtrace::detail
