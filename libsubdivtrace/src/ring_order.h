#pragma once
// Orders the neighbours of a vertex into a fan from its incident triangles.
// Shared by uniform subdivision (integer vertex ids) and the lazy hierarchy
// (grid vertex keys), so both see the same rings.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "subdivtrace/scheme.h"

namespace subdivtrace::detail {

/// An ordered ring as a level holds it: neighbour indices counter-clockwise,
/// the ring's kind, and the curve through the centre (VertexRing::curve).
struct RingIndices {
    const std::uint32_t* nbrs;
    std::size_t count;
    bool closed;
    bool regular;
    int curve_count;
    const std::uint32_t* curve;  ///< read where curve_count == 2
};

/// The scheme rules' view of a ring: the positions of `centre` and of the
/// ring's points (position_of(index)). Uniform levels and tiles both gather
/// rings here, so both hand the rules the same values.
template <class PositionOf>
void gather_ring(const Vec3& centre, const RingIndices& r, PositionOf position_of, VertexRing& ring) {
    ring.center = centre;
    ring.closed = r.closed;
    ring.regular = r.regular;
    ring.nbrs.clear();
    for (std::size_t k = 0; k < r.count; ++k) ring.nbrs.push_back(position_of(r.nbrs[k]));
    ring.curve_count = r.curve_count;
    if (r.curve_count == 2)
        for (int k = 0; k < 2; ++k) ring.curve[k] = position_of(r.curve[k]);
}

/// Whether a ring is whole, manifold, of valence 6 and in one sector: an
/// endpoint of a RegularEdge (scheme_rules.h).
inline bool regular_six(const RingIndices& r, bool single_sector) {
    return r.closed && r.regular && r.count == 6 && single_sector;
}

/// Triangle (center, from, to) contributes the directed pair from -> to.
template <class Id>
struct FanPair {
    Id from;
    Id to;
};

/// Result of chaining: neighbours counter-clockwise, and the ring's kind.
template <class Id>
struct OrderedRing {
    std::vector<Id> nbrs;
    bool closed = false;
    bool regular = true;
    /// Scratch for the walk, kept so that reusing one OrderedRing allocates
    /// nothing per vertex.
    std::vector<std::uint8_t> used;
};

/// Chains pairs into one fan. Regular when every neighbour starts at most one
/// pair and ends at most one, and the pairs form a single cycle (closed) or a
/// single path (open, from the neighbour that ends no pair). Anything else
/// (non-manifold edges, several fans, flipped neighbours) is irregular: nbrs
/// then lists each neighbour once, in first-seen order.
template <class Id, class Eq>
void order_ring(const std::vector<FanPair<Id>>& pairs, OrderedRing<Id>& out, Eq eq) {
    out.nbrs.clear();
    out.closed = false;
    out.regular = true;
    const std::size_t n = pairs.size();
    if (n == 0) {
        out.regular = false;
        return;
    }
    // Fans are small (valence), so quadratic scans beat hashing here.
    auto count_from = [&](const Id& v) {
        std::size_t c = 0;
        for (const auto& p : pairs) c += eq(p.from, v) ? 1 : 0;
        return c;
    };
    auto count_to = [&](const Id& v) {
        std::size_t c = 0;
        for (const auto& p : pairs) c += eq(p.to, v) ? 1 : 0;
        return c;
    };
    std::size_t start = 0;
    std::size_t path_starts = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const std::size_t f = count_from(pairs[i].from);
        const std::size_t t = count_to(pairs[i].from);
        if (f > 1 || t > 1 || count_to(pairs[i].to) > 1) out.regular = false;
        if (t == 0) {
            start = i;
            ++path_starts;
        }
    }
    if (out.regular && path_starts <= 1) {
        // Walk from the start pair following from == previous to.
        std::vector<std::uint8_t>& used = out.used;
        used.assign(n, 0);
        std::size_t current = start;
        out.nbrs.push_back(pairs[current].from);
        for (std::size_t step = 0; step < n; ++step) {
            used[current] = 1;
            const Id& next_vertex = pairs[current].to;
            std::size_t next = n;
            for (std::size_t j = 0; j < n; ++j) {
                if (!used[j] && eq(pairs[j].from, next_vertex)) {
                    next = j;
                    break;
                }
            }
            if (next == n) {
                // Path ends: closed if it came back to the first neighbour.
                if (eq(next_vertex, out.nbrs.front())) {
                    out.closed = true;
                } else {
                    out.nbrs.push_back(next_vertex);
                }
                break;
            }
            out.nbrs.push_back(next_vertex);
            current = next;
        }
        bool all_used = true;
        for (std::uint8_t u : used) all_used = all_used && u != 0;
        if (all_used && (out.closed ? out.nbrs.size() == n : out.nbrs.size() == n + 1)) return;
        out.regular = false;
        out.closed = false;
    }
    out.regular = false;
    out.closed = false;
    out.nbrs.clear();
    for (const auto& p : pairs) {
        for (const Id* v : {&p.from, &p.to}) {
            bool seen = false;
            for (const Id& w : out.nbrs) seen = seen || eq(w, *v);
            if (!seen) out.nbrs.push_back(*v);
        }
    }
}

}  // namespace subdivtrace::detail
