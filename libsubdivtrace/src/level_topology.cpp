#include "level_topology.h"

#include <algorithm>
#include <type_traits>

#include "creases.h"
#include "edge_sides.h"
#include "huge_pages.h"
#include "ring_order.h"
#include "vertex_faces.h"

namespace subdivtrace {

LevelTopology::LevelTopology(const std::vector<Vec3>& positions,
                             const std::vector<Triangle>& triangles,
                             const std::vector<std::uint8_t>& crease_masks, bool ordered_rings)
    : ordered_rings_(ordered_rings) {
    const std::size_t vertex_count = positions.size();
    const std::size_t face_count = triangles.size();

    // Edges: each distinct pair of the sorted sides gets an id.
    const detail::HugeArray<detail::EdgeSide> sides = detail::sorted_edge_sides(triangles, vertex_count);
    face_edges_.assign(3 * face_count, 0);
    detail::for_each_edge(sides, [&](const detail::EdgeSide* first, const detail::EdgeSide* last) {
        Edge e;
        const Triangle& first_face = triangles[first->face];
        e.a = first_face[first->corner];
        e.b = first_face[(first->corner + 1) % 3];
        e.c = first_face[(first->corner + 2) % 3];
        e.face_count = static_cast<std::uint32_t>(last - first);
        e.interior = e.face_count == 2;
        e.face = first->face;
        e.corner = first->corner;
        e.curve = e.face_count == 1;
        if (!crease_masks.empty() && e.face_count == 2)
            for (const detail::EdgeSide* s = first; s != last; ++s)
                e.curve = e.curve || (crease_masks[s->face] >> s->corner & 1u) != 0;
        if (e.face_count >= 2) {
            e.face2 = first[1].face;
            e.corner2 = first[1].corner;
        }
        if (e.face_count > 2) manifold_edges_ = false;
        if (e.interior) {
            const Triangle& second = triangles[first[1].face];
            e.d = second[(first[1].corner + 2) % 3];
        }
        const std::uint32_t id = static_cast<std::uint32_t>(edges_.size());
        for (const detail::EdgeSide* s = first; s != last; ++s) face_edges_[3 * s->face + s->corner] = id;
        edges_.push_back(e);
    });
    build_vertex_data(vertex_count, triangles, crease_masks, nullptr);
}

namespace {

/// The slot s of triangle t with {t[s], t[s+1]} = {x, y}.
std::uint8_t slot_of(const Triangle& t, std::uint32_t x, std::uint32_t y) {
    for (std::uint8_t s = 0; s < 3; ++s) {
        const std::uint32_t p = t[s], q = t[(s + 1) % 3];
        if ((p == x && q == y) || (p == y && q == x)) return s;
    }
    return 0;
}

}  // namespace

LevelTopology LevelTopology::refined(const LevelTopology& parent,
                                     const std::vector<Triangle>& parent_triangles,
                                     std::size_t parent_vertex_count,
                                     const std::vector<Triangle>& children,
                                     const std::vector<std::uint8_t>& crease_masks) {
    LevelTopology topo;
    topo.ordered_rings_ = parent.ordered_rings_;
    const auto old_count = static_cast<std::uint32_t>(parent_vertex_count);
    const std::uint32_t parent_edges = parent.edge_count();
    const std::size_t face_count = children.size();
    topo.edges_.resize(2 * std::size_t{parent_edges} + 3 * parent_triangles.size());
    topo.face_edges_.assign(3 * face_count, 0);

    // Fills edge `id` {x, y} from its first and second child triangles
    // (slots as in the sorting constructor: first = lowest face index).
    const auto set_edge = [&](std::uint32_t id, std::uint32_t first, std::uint32_t second,
                              std::uint32_t x, std::uint32_t y, std::uint32_t face_count_,
                              bool curve) {
        Edge& e = topo.edges_[id];
        const Triangle& t1 = children[first];
        const std::uint8_t s1 = slot_of(t1, x, y);
        e.a = t1[s1];
        e.b = t1[(s1 + 1) % 3];
        e.c = t1[(s1 + 2) % 3];
        e.face = first;
        e.corner = s1;
        e.face_count = face_count_;
        e.interior = face_count_ == 2;
        e.curve = curve;
        if (face_count_ >= 2) {
            const Triangle& t2 = children[second];
            const std::uint8_t s2 = slot_of(t2, x, y);
            e.face2 = second;
            e.corner2 = s2;
            if (e.interior) e.d = t2[(s2 + 2) % 3];
        }
    };

    // Halves of parent edge e: 2e at its end a, 2e + 1 at its end b, each
    // in the corner children of e's triangles at that end.
    for (std::uint32_t pe = 0; pe < parent_edges; ++pe) {
        const Edge& e = parent.edges_[pe];
        const std::uint32_t m = old_count + pe;
        for (int half = 0; half < 2; ++half) {
            const std::uint32_t end = half == 0 ? e.a : e.b;
            const std::uint32_t first = 4 * e.face + detail::corner_of(parent_triangles[e.face], end);
            const std::uint32_t second =
                e.face_count >= 2 ? 4 * e.face2 + detail::corner_of(parent_triangles[e.face2], end) : 0;
            set_edge(2 * pe + half, first, second, end, m, e.face_count, e.curve);
        }
    }
    // Inner edges of parent triangle t: 2E + 3t + k, between its edge points
    // on edges k and k - 1, shared by corner child k and the middle child.
    for (std::uint32_t t = 0; t < parent_triangles.size(); ++t) {
        for (std::uint32_t k = 0; k < 3; ++k) {
            const std::uint32_t x = old_count + parent.face_edges_[3 * t + k];
            const std::uint32_t y = old_count + parent.face_edges_[3 * t + (k + 2) % 3];
            set_edge(2 * parent_edges + 3 * t + k, 4 * t + k, 4 * t + 3, x, y, 2, false);
        }
    }
    // Each child slot names its edge.
    for (std::uint32_t t = 0; t < parent_triangles.size(); ++t) {
        const Triangle& p = parent_triangles[t];
        for (std::uint32_t k = 0; k < 3; ++k) {
            // Corner child k: its slots k and k + 2 are halves at p[k], k + 1 inner.
            const std::uint32_t e_next = parent.face_edges_[3 * t + k];
            const std::uint32_t e_prev = parent.face_edges_[3 * t + (k + 2) % 3];
            const std::uint32_t child = 4 * t + k;
            topo.face_edges_[3 * child + k] = 2 * e_next + (parent.edges_[e_next].a == p[k] ? 0 : 1);
            topo.face_edges_[3 * child + (k + 2) % 3] =
                2 * e_prev + (parent.edges_[e_prev].a == p[k] ? 0 : 1);
            topo.face_edges_[3 * child + (k + 1) % 3] = 2 * parent_edges + 3 * t + k;
        }
        const Triangle& middle = children[4 * t + 3];
        for (std::uint32_t k = 0; k < 3; ++k) {
            const std::uint32_t inner = 2 * parent_edges + 3 * t + k;
            const Edge& e = topo.edges_[inner];
            topo.face_edges_[3 * (4 * t + 3) + slot_of(middle, e.a, e.b)] = inner;
        }
    }
    const RefinedFrom from{&parent, &parent_triangles, old_count};
    topo.build_vertex_data(parent_vertex_count + parent_edges, children, crease_masks, &from);
    return topo;
}

void LevelTopology::build_vertex_data(std::size_t vertex_count,
                                      const std::vector<Triangle>& triangles,
                                      const std::vector<std::uint8_t>& crease_masks,
                                      const RefinedFrom* refined_from) {
    const std::size_t face_count = triangles.size();
    // Curves: the boundary and crease edges at each vertex.
    curve_count_.assign(vertex_count, 0);
    curve_nbr_.assign(2 * vertex_count, 0);
    for (const Edge& e : edges_) {
        if (!e.curve) continue;
        for (const auto& [v, w] : {std::pair{e.a, e.b}, std::pair{e.b, e.a}}) {
            if (curve_count_[v] < 2) curve_nbr_[2 * v + curve_count_[v]] = w;
            if (curve_count_[v] < 3) ++curve_count_[v];
        }
    }

    // Rings: incident corner slots per vertex (CSR), then chained into fans.
    detail::HugeArray<std::size_t>& inc_offsets = inc_offsets_;
    inc_offsets.assign(vertex_count + 1, 0);
    for (const Triangle& t : triangles)
        for (std::uint32_t v : t) ++inc_offsets[v + 1];
    for (std::size_t v = 0; v < vertex_count; ++v) inc_offsets[v + 1] += inc_offsets[v];
    inc_slots_.resize(inc_offsets.back());
    detail::HugeArray<std::size_t> fill(inc_offsets.begin(), inc_offsets.end() - 1);
    for (std::uint32_t t = 0; t < face_count; ++t)
        for (std::uint32_t c = 0; c < 3; ++c) inc_slots_[fill[triangles[t][c]]++] = 3 * t + c;

    // Sectors, where creases pass.
    sector_labels_.clear();
    single_sector_.assign(vertex_count, 1);
    if (!crease_masks.empty()) {
        std::vector<detail::FanCorner> corners;
        std::vector<std::uint32_t> labels;
        for (std::uint32_t v = 0; v < vertex_count; ++v) {
            if (curve_count_[v] == 0) continue;
            corners.clear();
            for (std::size_t k = inc_offsets[v]; k < inc_offsets[v + 1]; ++k) {
                const std::uint32_t slot = inc_slots_[k], c = slot % 3;
                const std::uint32_t e_next = face_edges_[slot];
                const std::uint32_t e_prev = face_edges_[slot - c + (c + 2) % 3];
                corners.push_back({e_prev, e_next, edges_[e_prev].curve, edges_[e_next].curve});
            }
            if (detail::label_sectors(corners, labels) > 1) {
                single_sector_[v] = 0;
                sector_labels_.insert(sector_labels_.end(), labels.begin(), labels.end());
            }
        }
    }

    if (!ordered_rings_) return;
    ring_offsets_.assign(vertex_count + 1, 0);
    ring_closed_.assign(vertex_count, 0);
    ring_regular_.assign(vertex_count, 0);
    ring_nbrs_.reserve(3 * face_count);
    ring_edges_.reserve(3 * face_count);
    ring_curve_.reserve(3 * face_count);
    std::vector<detail::FanPair<std::uint32_t>> pairs;
    detail::OrderedRing<std::uint32_t> ordered;
    const auto eq = [](std::uint32_t x, std::uint32_t y) { return x == y; };
    for (std::uint32_t v = 0; v < vertex_count; ++v) {
        if (refined_from != nullptr && single_sector_[v] &&
            append_refined_ring(*refined_from, v)) {
            ring_curve_.resize(ring_nbrs_.size(), 0);
            ring_offsets_[v + 1] = ring_nbrs_.size();
            continue;
        }
        pairs.clear();
        for (std::size_t k = inc_offsets[v]; k < inc_offsets[v + 1]; ++k) {
            const Triangle& t = triangles[inc_slots_[k] / 3];
            const std::uint32_t i = inc_slots_[k] % 3;
            pairs.push_back({t[(i + 1) % 3], t[(i + 2) % 3]});
        }
        detail::order_ring(pairs, ordered, eq);
        ring_nbrs_.insert(ring_nbrs_.end(), ordered.nbrs.begin(), ordered.nbrs.end());
        for (std::uint32_t w : ordered.nbrs) {
            // The edge to w, and whether it is a curve edge (when creases
            // split v's triangles, Butterfly reads that).
            std::uint32_t edge = 0;
            bool curve = false;
            for (std::size_t k = inc_offsets[v]; k < inc_offsets[v + 1]; ++k) {
                const std::uint32_t slot = inc_slots_[k], c = slot % 3;
                const Triangle& t = triangles[slot / 3];
                for (const std::uint32_t e : {t[(c + 1) % 3] == w ? face_edges_[slot] : ~0u,
                                              t[(c + 2) % 3] == w ? face_edges_[slot - c + (c + 2) % 3]
                                                                  : ~0u}) {
                    if (e == ~0u) continue;
                    edge = e;
                    curve = curve || edges_[e].curve;
                }
            }
            ring_edges_.push_back(edge);
            ring_curve_.push_back(!single_sector_[v] && curve ? 1 : 0);
        }
        ring_offsets_[v + 1] = ring_nbrs_.size();
        ring_closed_[v] = ordered.closed;
        ring_regular_[v] = ordered.regular;
    }
}

bool LevelTopology::append_refined_ring(const RefinedFrom& from, std::uint32_t v) {
    const LevelTopology& parent = *from.parent;
    const std::uint32_t old_count = from.old_count;
    if (v < old_count) {
        // An old vertex: its parent ring, each neighbour w replaced by the
        // point of edge (v, w), in the same order (the children around v are
        // the parent's triangles' corner children, one per parent triangle).
        for (std::size_t k = parent.ring_offsets_[v]; k < parent.ring_offsets_[v + 1]; ++k) {
            const std::uint32_t pe = parent.ring_edges_[k];
            ring_nbrs_.push_back(old_count + pe);
            ring_edges_.push_back(2 * pe + (parent.edges_[pe].a == v ? 0 : 1));
        }
        ring_closed_[v] = parent.ring_closed_[v];
        ring_regular_[v] = parent.ring_regular_[v];
        return true;
    }
    // The point m of an interior, non-curve parent edge (a, b) whose two
    // triangles (a, b, c) and (b, a, d) agree in orientation: its ring is
    // b, m(bc), m(ca), a, m(ad), m(db), closed (the children of both triangles
    // that touch m, counter-clockwise).
    const std::uint32_t pe = v - old_count;
    const Edge& e = parent.edges_[pe];
    if (!e.interior || e.curve || (*from.parent_triangles)[e.face2][e.corner2] != e.b) return false;
    const std::uint32_t inner = 2 * parent.edge_count();
    const std::uint32_t f1 = e.face, i1 = e.corner, f2 = e.face2, i2 = e.corner2;
    const auto point = [&](std::uint32_t f, std::uint32_t k) {
        return old_count + parent.face_edges_[3 * f + k % 3];
    };
    const std::uint32_t nbrs[6] = {e.b,           point(f1, i1 + 1), point(f1, i1 + 2),
                                   e.a,           point(f2, i2 + 1), point(f2, i2 + 2)};
    const std::uint32_t edges[6] = {2 * pe + 1,          inner + 3 * f1 + (i1 + 1) % 3,
                                    inner + 3 * f1 + i1, 2 * pe,
                                    inner + 3 * f2 + (i2 + 1) % 3, inner + 3 * f2 + i2};
    ring_nbrs_.insert(ring_nbrs_.end(), nbrs, nbrs + 6);
    ring_edges_.insert(ring_edges_.end(), edges, edges + 6);
    ring_closed_[v] = 1;
    ring_regular_[v] = 1;
    return true;
}

void LevelTopology::fill_ring(std::uint32_t v, const std::vector<Vec3>& positions,
                              VertexRing& ring) const {
    detail::gather_ring(positions[v], ring_indices(v), [&](std::uint32_t w) { return positions[w]; }, ring);
}

namespace {

/// Each corner's own angle-weighted normal (a triangle's three share one
/// cross product), or the given one where `given` has it.
detail::HugeArray<Vec3> weighted_corner_normals(const std::vector<Vec3>& positions,
                                                const std::vector<Triangle>& triangles,
                                                const detail::HugeArray<Vec3>& given) {
    detail::HugeArray<Vec3> out(3 * triangles.size());
    angle_weighted_corners(positions.data(), triangles.data(), triangles.size(), out.data());
    if (!given.empty())
        for (std::size_t slot = 0; slot < out.size(); ++slot)
            if (given[slot] != Vec3(0.0)) out[slot] = given[slot];
    return out;
}

/// Per vertex, the normalised sum of its corners' normals, in triangle
/// order (as the incidence lists run, so both give the same bits).
detail::HugeArray<Vec3> vertex_sums(std::size_t vertex_count, const std::vector<Triangle>& triangles,
                                    const detail::HugeArray<Vec3>& corners) {
    detail::HugeArray<Vec3> sums(vertex_count, Vec3(0.0));
    for (std::size_t t = 0; t < triangles.size(); ++t)
        for (int c = 0; c < 3; ++c) sums[triangles[t][c]] += corners[3 * t + c];
    for (Vec3& sum : sums) sum = finish_normal(sum);
    return sums;
}

}  // namespace

detail::HugeArray<Vec3> LevelTopology::sector_normals(const std::vector<Vec3>& positions,
                                                     const std::vector<Triangle>& triangles,
                                                     const detail::HugeArray<Vec3>& given) const {
    detail::HugeArray<Vec3> out = weighted_corner_normals(positions, triangles, given);
    // Vertices that creases split: a sum per sector, written back over the
    // corners it was summed from (each corner is read for its own vertex only).
    std::vector<Vec3> sums;
    const std::uint32_t* labels = sector_labels_.data();  // the split vertices' in turn
    for (std::uint32_t v = 0; v < positions.size(); ++v) {
        if (single_sector_[v]) continue;
        const std::size_t first = inc_offsets_[v], count = inc_offsets_[v + 1] - first;
        std::uint32_t sectors = 1;
        for (std::size_t k = 0; k < count; ++k) sectors = std::max(sectors, labels[k] + 1);
        sums.assign(sectors, Vec3(0.0));
        for (std::size_t k = 0; k < count; ++k) sums[labels[k]] += out[inc_slots_[first + k]];
        for (Vec3& sum : sums) sum = finish_normal(sum);
        for (std::size_t k = 0; k < count; ++k) out[inc_slots_[first + k]] = sums[labels[k]];
        labels += count;
    }
    const detail::HugeArray<Vec3> smooth = vertex_sums(positions.size(), triangles, out);
    for (std::size_t t = 0; t < triangles.size(); ++t)
        for (int c = 0; c < 3; ++c)
            if (single_sector_[triangles[t][c]]) out[3 * t + c] = smooth[triangles[t][c]];
    return out;
}

template <class Normals>
void smooth_vertex_normals(const std::vector<Vec3>& positions, const std::vector<Triangle>& triangles,
                           Normals& sums) {
    if constexpr (std::is_same_v<Normals, std::vector<Vec3>>) detail::assign_huge(sums, positions.size(), Vec3(0.0));
    else sums.assign(positions.size(), Vec3(0.0));
    // A block of triangles at a time, so the corners' angles vectorise.
    constexpr std::size_t k_block = 256;
    Vec3 corners[3 * k_block];
    for (std::size_t start = 0; start < triangles.size(); start += k_block) {
        const std::size_t n = std::min(k_block, triangles.size() - start);
        angle_weighted_corners(positions.data(), triangles.data() + start, n, corners);
        for (std::size_t k = 0; k < n; ++k)
            for (int c = 0; c < 3; ++c) sums[triangles[start + k][c]] += corners[3 * k + c];
    }
    for (Vec3& sum : sums) sum = finish_normal(sum);
}

template void smooth_vertex_normals(const std::vector<Vec3>&, const std::vector<Triangle>&, std::vector<Vec3>&);
template void smooth_vertex_normals(const std::vector<Vec3>&, const std::vector<Triangle>&,
                                    detail::HugeArray<Vec3>&);

}  // namespace subdivtrace
