#pragma once
// Connectivity of one level of a mesh held in plain arrays: edges with their
// opposite vertices, curves (boundaries and creases), ordered vertex rings,
// and per-sector normals.

#include <algorithm>
#include <cassert>
#include <cstdint>
#include <vector>

#include "huge_pages.h"
#include "ring_order.h"
#include "subdivtrace/mesh.h"
#include "subdivtrace/scheme.h"

namespace subdivtrace {

class LevelTopology {
public:
    struct Edge {
        std::uint32_t a = 0;  ///< as in the first triangle that has the edge
        std::uint32_t b = 0;
        std::uint32_t c = 0;  ///< third vertex of that triangle (interior only)
        std::uint32_t d = 0;  ///< third vertex of the other triangle (interior only)
        std::uint32_t face_count = 0;
        bool interior = false;  ///< exactly two triangles
        bool curve = false;     ///< one triangle (boundary), or a crease
        std::uint32_t face = 0;    ///< the first triangle that has the edge
        std::uint8_t corner = 0;   ///< a is that triangle's corner `corner`
        std::uint32_t face2 = 0;   ///< the second triangle (face_count >= 2)
        std::uint8_t corner2 = 0;  ///< the edge is its edge `corner2`
    };

    /// `crease_masks`: per triangle, bit e set if its edge e is a crease
    /// (creases.h); empty for none. Without `ordered_rings` the vertices'
    /// rings are not built (and the ring accessors below must not be called):
    /// the normal scheme reads none, and ordering them was about a tenth of
    /// its uniform subdivision.
    LevelTopology(const std::vector<Vec3>& positions, const std::vector<Triangle>& triangles,
                  const std::vector<std::uint8_t>& crease_masks = {}, bool ordered_rings = true);

    /// The topology of `parent`'s 1-to-4 split (uniform.h's layout: vertex
    /// V + e is the point of parent edge e, children 4t..4t+3) with the same
    /// result as the constructor above, edges derived from the parent's in
    /// linear time instead of sorted. `children` must be that split of
    /// `parent_triangles`; `crease_masks` the children's. It has rings where
    /// the parent has.
    static LevelTopology refined(const LevelTopology& parent,
                                 const std::vector<Triangle>& parent_triangles,
                                 std::size_t parent_vertex_count,
                                 const std::vector<Triangle>& children,
                                 const std::vector<std::uint8_t>& crease_masks);
    /// Whether refined() applies: every edge has at most two triangles.
    bool manifold_edges() const { return manifold_edges_; }
    /// Whether the vertices' ordered rings were built (the constructor's
    /// `ordered_rings`).
    bool has_rings() const { return ordered_rings_; }

    std::uint32_t edge_count() const { return static_cast<std::uint32_t>(edges_.size()); }
    const Edge& edge(std::uint32_t e) const { return edges_[e]; }
    /// Edge i of triangle t runs from corner i to corner (i + 1) % 3.
    std::uint32_t face_edge(std::size_t t, int i) const { return face_edges_[3 * t + i]; }

    /// Curve edges at v, and with exactly two, their other ends.
    int curve_count(std::uint32_t v) const { return curve_count_[v]; }
    std::uint32_t curve_nbr(std::uint32_t v, int k) const { return curve_nbr_[2 * v + k]; }

    /// Per corner (3t + c): the vertex's normal over its sector, the
    /// triangles around it between creases. `given` (per corner, or empty)
    /// replaces the angle-weighted Gouraud sum where it is non-zero.
    detail::HugeArray<Vec3> sector_normals(const std::vector<Vec3>& positions,
                                           const std::vector<Triangle>& triangles,
                                           const detail::HugeArray<Vec3>& given = {}) const;
    /// Whether v's triangles form one sector (no crease splits them).
    bool single_sector(std::uint32_t v) const { return single_sector_[v] != 0; }
    /// Whether every vertex's triangles form one sector (no crease, no
    /// bowtie): then each corner's sector normal is its vertex's.
    bool one_sector_everywhere() const {
        return std::all_of(single_sector_.begin(), single_sector_.end(), [](std::uint8_t s) { return s != 0; });
    }
    /// Per neighbour of v's ring (fill_ring's order): its edge is a curve edge.
    const std::uint8_t* ring_curve(std::uint32_t v) const {
        assert(ordered_rings_);
        return &ring_curve_[ring_offsets_[v]];
    }
    /// A corner slot 3t + c of v.
    std::uint32_t first_slot(std::uint32_t v) const { return inc_slots_[inc_offsets_[v]]; }

    /// The ordered ring of v with positions (and curve neighbours) filled in.
    void fill_ring(std::uint32_t v, const std::vector<Vec3>& positions, VertexRing& ring) const;
    /// Neighbour k of v's ordered ring (k < valence(v)), and the edge to it.
    std::uint32_t ring_neighbour(std::uint32_t v, std::size_t k) const {
        assert(ordered_rings_);
        return ring_nbrs_[ring_offsets_[v] + k];
    }
    std::uint32_t ring_edge(std::uint32_t v, std::size_t k) const {
        assert(ordered_rings_);
        return ring_edges_[ring_offsets_[v] + k];
    }
    bool ring_closed(std::uint32_t v) const {
        assert(ordered_rings_);
        return ring_closed_[v] != 0;
    }
    /// v's ordered ring as indices (ring_order.h).
    detail::RingIndices ring_indices(std::uint32_t v) const {
        assert(ordered_rings_);
        return {&ring_nbrs_[ring_offsets_[v]], valence(v),        ring_closed_[v] != 0,
                ring_regular_[v] != 0,         curve_count_[v], &curve_nbr_[2 * v]};
    }
    /// Whether v's ring is whole, manifold, of valence 6 and in one sector:
    /// an endpoint of a detail::RegularEdge.
    bool regular_six(std::uint32_t v) const { return detail::regular_six(ring_indices(v), single_sector(v)); }
    bool ring_regular(std::uint32_t v) const {
        assert(ordered_rings_);
        return ring_regular_[v] != 0;
    }
    std::size_t valence(std::uint32_t v) const {
        assert(ordered_rings_);
        return ring_offsets_[v + 1] - ring_offsets_[v];
    }

private:
    LevelTopology() = default;
    /// The level this one is the 1-to-4 split of (refined()).
    struct RefinedFrom {
        const LevelTopology* parent;
        const std::vector<Triangle>* parent_triangles;
        std::uint32_t old_count;
    };
    /// Everything but the edges: curves, incidence, sectors and rings (rings
    /// that follow from `refined_from` are taken from it, the rest chained).
    void build_vertex_data(std::size_t vertex_count, const std::vector<Triangle>& triangles,
                           const std::vector<std::uint8_t>& crease_masks,
                           const RefinedFrom* refined_from);
    /// Appends v's ring as it follows from the parent level, if it does.
    bool append_refined_ring(const RefinedFrom& from, std::uint32_t v);

    // Level-sized arrays: on huge pages (huge_pages.h).
    bool manifold_edges_ = true;
    bool ordered_rings_ = true;
    detail::HugeArray<Edge> edges_;
    detail::HugeArray<std::uint32_t> face_edges_;
    detail::HugeArray<std::size_t> ring_offsets_;
    detail::HugeArray<std::uint32_t> ring_nbrs_;
    detail::HugeArray<std::uint32_t> ring_edges_;  ///< per ring_nbrs_ entry: its edge
    detail::HugeArray<std::uint8_t> ring_closed_;
    detail::HugeArray<std::uint8_t> ring_regular_;
    detail::HugeArray<std::uint8_t> ring_curve_;
    detail::HugeArray<std::uint8_t> curve_count_;
    detail::HugeArray<std::uint32_t> curve_nbr_;
    detail::HugeArray<std::size_t> inc_offsets_;   ///< incident corner slots 3t + c, CSR
    detail::HugeArray<std::uint32_t> inc_slots_;
    /// The sector of each incident slot (inc_slots_ order) of every vertex
    /// that creases split, those vertices one after another in index order;
    /// nothing for the others (most of them), which had cost an empty
    /// std::vector each (24 bytes a vertex, zeroed at every level).
    std::vector<std::uint32_t> sector_labels_;
    detail::HugeArray<std::uint8_t> single_sector_;
};

/// LevelTopology::sector_normals for a level without creases or given
/// normals, once per vertex (every corner of a vertex has it) and without
/// building the topology or a per-corner array: the same bits.
/// Into `normals` (std::vector, for what uniform subdivision returns, or
/// HugeArray, for its levels' own: those faulted 4 kB at a time).
template <class Normals>
void smooth_vertex_normals(const std::vector<Vec3>& positions, const std::vector<Triangle>& triangles,
                           Normals& normals);

}  // namespace subdivtrace
