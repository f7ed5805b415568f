#pragma once
// The part of an edge's stencil that reads its endpoints' rings (Butterfly's
// wings and extraordinary stencils), for uniform levels and tiles alike: each
// hands over its rings as RingIndices and its positions, and both get the
// same values for the scheme's rules.

#include <algorithm>
#include <cstdint>

#include "creases.h"
#include "ring_order.h"
#include "scheme_rules.h"

namespace subdivtrace::detail {

/// One endpoint of an edge as its level holds it.
struct EdgeEnd {
    std::uint32_t vertex;
    RingIndices ring;
    /// Per ring neighbour, whether its edge is a curve; null where the
    /// vertex's triangles are one sector (its ring is read whole).
    const std::uint8_t* sector_curves;
};

/// Position of `w` in ring r (0 if absent; a regular ring holds each once).
inline std::size_t index_in_ring(const RingIndices& r, std::uint32_t w) {
    const std::uint32_t* at = std::find(r.nbrs, r.nbrs + r.count, w);
    return at == r.nbrs + r.count ? 0 : static_cast<std::size_t>(at - r.nbrs);
}

/// Whether an edge takes the scheme's regular edge rule (regular_edge_point):
/// the scheme has one, the edge is interior and no curve, and both ends pass
/// regular_six (asked last: it reads their rings).
template <class RegularSix>
bool takes_regular_edge_rule(const SchemeRules& scheme, bool interior, bool curve, std::uint32_t a,
                             std::uint32_t b, RegularSix regular_six) {
    return scheme.regular_edge_rule != nullptr && interior && !curve && regular_six(a) && regular_six(b);
}

/// The edge's point where both ends are regular_six and the scheme has a
/// regular edge rule: its eight points by ring index, without gathering
/// either ring (c and d as EdgeStencil has them).
template <class PositionOf>
Vec3 regular_edge_point(const SchemeRules& scheme, const EdgeEnd& a, const EdgeEnd& b, const Vec3& c,
                        const Vec3& d, PositionOf position_of) {
    const std::size_t i_b = index_in_ring(a.ring, b.vertex), i_a = index_in_ring(b.ring, a.vertex);
    const auto at = [&](const RingIndices& r, std::size_t k) { return position_of(r.nbrs[k % 6]); };
    return scheme.regular_edge_rule({position_of(a.vertex), position_of(b.vertex), c, d, at(b.ring, i_a + 4),
                                     at(a.ring, i_b + 2), at(b.ring, i_a + 2), at(a.ring, i_b + 4)});
}

/// Fills s's rings (into ring_a and ring_b, which s then points to) and
/// each end's index in the other's ring, each ring cut to the edge's
/// sector where a crease splits it (a crease is a boundary to each side).
template <class PositionOf>
void fill_edge_rings(const EdgeEnd& a, const EdgeEnd& b, PositionOf position_of, VertexRing& ring_a,
                     VertexRing& ring_b, EdgeStencil& s) {
    gather_ring(position_of(a.vertex), a.ring, position_of, ring_a);
    gather_ring(position_of(b.vertex), b.ring, position_of, ring_b);
    s.index_b_in_a = index_in_ring(a.ring, b.vertex);
    s.index_a_in_b = index_in_ring(b.ring, a.vertex);
    if (a.sector_curves) restrict_to_sector(ring_a, a.sector_curves, s.index_b_in_a);
    if (b.sector_curves) restrict_to_sector(ring_b, b.sector_curves, s.index_a_in_b);
    s.ring_a = &ring_a;
    s.ring_b = &ring_b;
}

}  // namespace subdivtrace::detail
