#include "level_topology.h"

#include <algorithm>
#include <tuple>

#include "creases.h"
#include "ring_order.h"

namespace subdivtrace {

LevelTopology::LevelTopology(const std::vector<Vec3>& positions,
                             const std::vector<Triangle>& triangles,
                             const std::vector<std::uint8_t>& crease_masks) {
    const std::size_t vertex_count = positions.size();
    const std::size_t face_count = triangles.size();

    // Edges: sort (min, max, corner slot) and give each distinct pair an id.
    struct Slot {
        std::uint32_t lo, hi;
        std::uint32_t face;
        std::uint8_t corner;
    };
    std::vector<Slot> slots;
    slots.reserve(3 * face_count);
    for (std::uint32_t t = 0; t < face_count; ++t) {
        for (std::uint8_t i = 0; i < 3; ++i) {
            const std::uint32_t u = triangles[t][i], w = triangles[t][(i + 1) % 3];
            slots.push_back({std::min(u, w), std::max(u, w), t, i});
        }
    }
    std::sort(slots.begin(), slots.end(), [](const Slot& x, const Slot& y) {
        return std::tie(x.lo, x.hi, x.face, x.corner) < std::tie(y.lo, y.hi, y.face, y.corner);
    });
    face_edges_.assign(3 * face_count, 0);
    for (std::size_t i = 0; i < slots.size();) {
        std::size_t j = i;
        while (j < slots.size() && slots[j].lo == slots[i].lo && slots[j].hi == slots[i].hi) ++j;
        Edge e;
        const Triangle& first = triangles[slots[i].face];
        e.a = first[slots[i].corner];
        e.b = first[(slots[i].corner + 1) % 3];
        e.c = first[(slots[i].corner + 2) % 3];
        e.face_count = static_cast<std::uint32_t>(j - i);
        e.interior = e.face_count == 2;
        e.face = slots[i].face;
        e.corner = slots[i].corner;
        e.curve = e.face_count == 1;
        if (!crease_masks.empty() && e.face_count == 2)
            for (std::size_t k = i; k < j; ++k)
                e.curve = e.curve || (crease_masks[slots[k].face] >> slots[k].corner & 1u) != 0;
        if (e.interior) {
            const Triangle& second = triangles[slots[i + 1].face];
            e.d = second[(slots[i + 1].corner + 2) % 3];
        }
        const std::uint32_t id = static_cast<std::uint32_t>(edges_.size());
        for (std::size_t k = i; k < j; ++k) face_edges_[3 * slots[k].face + slots[k].corner] = id;
        edges_.push_back(e);
        i = j;
    }

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
    std::vector<std::size_t>& inc_offsets = inc_offsets_;
    inc_offsets.assign(vertex_count + 1, 0);
    for (const Triangle& t : triangles)
        for (std::uint32_t v : t) ++inc_offsets[v + 1];
    for (std::size_t v = 0; v < vertex_count; ++v) inc_offsets[v + 1] += inc_offsets[v];
    inc_slots_.resize(inc_offsets.back());
    std::vector<std::size_t> fill(inc_offsets.begin(), inc_offsets.end() - 1);
    for (std::uint32_t t = 0; t < face_count; ++t)
        for (std::uint32_t c = 0; c < 3; ++c) inc_slots_[fill[triangles[t][c]]++] = 3 * t + c;

    // Sectors, where creases pass.
    sector_labels_.assign(vertex_count, {});
    single_sector_.assign(vertex_count, 1);
    if (!crease_masks.empty()) {
        std::vector<detail::FanCorner> corners;
        for (std::uint32_t v = 0; v < vertex_count; ++v) {
            if (curve_count_[v] == 0) continue;
            corners.clear();
            for (std::size_t k = inc_offsets[v]; k < inc_offsets[v + 1]; ++k) {
                const std::uint32_t slot = inc_slots_[k], c = slot % 3;
                const std::uint32_t e_next = face_edges_[slot];
                const std::uint32_t e_prev = face_edges_[slot - c + (c + 2) % 3];
                corners.push_back({e_prev, e_next, edges_[e_prev].curve, edges_[e_next].curve});
            }
            if (detail::label_sectors(corners, sector_labels_[v]) > 1) single_sector_[v] = 0;
            else sector_labels_[v].clear();
        }
    }

    ring_offsets_.assign(vertex_count + 1, 0);
    ring_closed_.assign(vertex_count, 0);
    ring_regular_.assign(vertex_count, 0);
    ring_nbrs_.reserve(3 * face_count);
    std::vector<detail::FanPair<std::uint32_t>> pairs;
    detail::OrderedRing<std::uint32_t> ordered;
    const auto eq = [](std::uint32_t x, std::uint32_t y) { return x == y; };
    for (std::uint32_t v = 0; v < vertex_count; ++v) {
        pairs.clear();
        for (std::size_t k = inc_offsets[v]; k < inc_offsets[v + 1]; ++k) {
            const Triangle& t = triangles[inc_slots_[k] / 3];
            const std::uint32_t i = inc_slots_[k] % 3;
            pairs.push_back({t[(i + 1) % 3], t[(i + 2) % 3]});
        }
        detail::order_ring(pairs, ordered, eq);
        ring_nbrs_.insert(ring_nbrs_.end(), ordered.nbrs.begin(), ordered.nbrs.end());
        for (std::uint32_t w : ordered.nbrs) {
            bool curve = false;
            if (!single_sector_[v]) {
                for (std::size_t k = inc_offsets[v]; k < inc_offsets[v + 1]; ++k) {
                    const std::uint32_t slot = inc_slots_[k], c = slot % 3;
                    const Triangle& t = triangles[slot / 3];
                    if (t[(c + 1) % 3] == w) curve = curve || edges_[face_edges_[slot]].curve;
                    if (t[(c + 2) % 3] == w) curve = curve || edges_[face_edges_[slot - c + (c + 2) % 3]].curve;
                }
            }
            ring_curve_.push_back(curve ? 1 : 0);
        }
        ring_offsets_[v + 1] = ring_nbrs_.size();
        ring_closed_[v] = ordered.closed;
        ring_regular_[v] = ordered.regular;
    }
}

void LevelTopology::fill_ring(std::uint32_t v, const std::vector<Vec3>& positions,
                              VertexRing& ring) const {
    ring.center = positions[v];
    ring.closed = ring_closed_[v] != 0;
    ring.regular = ring_regular_[v] != 0;
    ring.nbrs.clear();
    for (std::size_t k = ring_offsets_[v]; k < ring_offsets_[v + 1]; ++k)
        ring.nbrs.push_back(positions[ring_nbrs_[k]]);
    ring.curve_count = curve_count_[v];
    if (ring.curve_count == 2)
        for (int k = 0; k < 2; ++k) ring.curve[k] = positions[curve_nbr_[2 * v + k]];
}

std::size_t LevelTopology::ring_index(std::uint32_t v, std::uint32_t w) const {
    for (std::size_t k = ring_offsets_[v]; k < ring_offsets_[v + 1]; ++k)
        if (ring_nbrs_[k] == w) return k - ring_offsets_[v];
    return 0;
}

std::vector<Vec3> LevelTopology::sector_normals(const std::vector<Vec3>& positions,
                                               const std::vector<Triangle>& triangles,
                                               const std::vector<Vec3>& given) const {
    std::vector<Vec3> out(3 * triangles.size(), Vec3(0.0));
    std::vector<Vec3> sums;
    for (std::uint32_t v = 0; v < positions.size(); ++v) {
        const std::vector<std::uint32_t>& labels = sector_labels_[v];
        std::uint32_t count = 1;
        for (std::uint32_t l : labels) count = std::max(count, l + 1);
        sums.assign(count, Vec3(0.0));
        for (std::size_t k = inc_offsets_[v]; k < inc_offsets_[v + 1]; ++k) {
            const std::uint32_t slot = inc_slots_[k], c = slot % 3;
            const Triangle& t = triangles[slot / 3];
            const Vec3 n = !given.empty() && given[slot] != Vec3(0.0)
                               ? given[slot]
                               : angle_weighted_normal(positions[v], positions[t[(c + 1) % 3]],
                                                       positions[t[(c + 2) % 3]]);
            sums[labels.empty() ? 0 : labels[k - inc_offsets_[v]]] += n;
        }
        for (Vec3& sum : sums) sum = finish_normal(sum);
        for (std::size_t k = inc_offsets_[v]; k < inc_offsets_[v + 1]; ++k)
            out[inc_slots_[k]] = sums[labels.empty() ? 0 : labels[k - inc_offsets_[v]]];
    }
    return out;
}

}  // namespace subdivtrace
