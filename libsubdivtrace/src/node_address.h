#pragma once
// Addressing inside the hierarchy, below the public node names (node_id.h):
// the canonical name of every vertex of the uniform hierarchy (VertexKey),
// grid points of a base triangle, the grid triangles around a point, and a
// node's ancestors. Grid point (i, j) of base triangle f at level L has
// barycentric weights (N - i - j, i, j) on f's corners, N = 2^L; a point on
// a base edge or corner is shared with the neighbouring triangles, so it has
// one canonical VertexKey, the same whichever triangle names it.

#include <cstddef>
#include <cstdint>
#include <utility>

#include "subdivtrace/node_id.h"

namespace subdivtrace::detail {

/// Canonical name of a vertex of the uniform hierarchy, level-independent: the
/// level it is stored with is its birth level (coordinates reduced while even).
struct VertexKey {
    enum Kind : std::uint8_t { base_vertex = 0, edge_point = 1, face_point = 2 };
    std::uint8_t kind = base_vertex;
    std::uint8_t level = 0;  ///< birth level
    std::uint32_t a = 0;     ///< base vertex | lower edge vertex | base face
    std::uint32_t b = 0;     ///< -           | upper edge vertex | grid i
    std::uint32_t c = 0;     ///< -           | weight on upper   | grid j

    bool operator==(const VertexKey& o) const {
        return kind == o.kind && level == o.level && a == o.a && b == o.b && c == o.c;
    }
    bool operator!=(const VertexKey& o) const { return !(*this == o); }
};

inline std::uint64_t mix64(std::uint64_t x) {
    x ^= x >> 33;
    x *= 0xff51afd7ed558ccdULL;
    x ^= x >> 33;
    x *= 0xc4ceb9fe1a85ec53ULL;
    x ^= x >> 33;
    return x;
}

struct VertexKeyHash {
    std::size_t operator()(const VertexKey& k) const {
        const std::uint64_t h0 = (std::uint64_t{k.kind} << 56) ^ (std::uint64_t{k.level} << 48) ^ k.a;
        const std::uint64_t h1 = (std::uint64_t{k.b} << 32) ^ k.c;
        return static_cast<std::size_t>(mix64(h0 ^ mix64(h1)));
    }
};

/// A grid point of base triangle `face` at `level`.
struct GridPoint {
    std::uint32_t face = 0;
    std::uint32_t i = 0;
    std::uint32_t j = 0;
};

/// Orders VertexKeys (any fixed total order serves; this one is cheap).
inline bool key_less(const VertexKey& x, const VertexKey& y) {
    if (x.kind != y.kind) return x.kind < y.kind;
    if (x.level != y.level) return x.level < y.level;
    if (x.a != y.a) return x.a < y.a;
    if (x.b != y.b) return x.b < y.b;
    return x.c < y.c;
}

/// The node's ancestor at `level` (the node itself at its own level).
inline NodeId ancestor_at(const NodeId& id, int level) {
    if (id.level <= level) return id;
    // The ancestor's cell is the grid position shifted down; within a cell
    // of side 2^s, a descendant lies in the "down" half when its local
    // coordinates plus its own down flag reach 2^s (child_of's layout: an up
    // parent's children have at most one odd coordinate or down flag among
    // (i, j, down), a down parent's two or three; this is that, s levels at once).
    const int s = id.level - level;
    const std::uint32_t mask = (std::uint32_t{1} << s) - 1;
    NodeId a;
    a.face = id.face;
    a.level = static_cast<std::uint8_t>(level);
    a.i = id.i >> s;
    a.j = id.j >> s;
    a.down = (id.i & mask) + (id.j & mask) + (id.down ? 1u : 0u) > mask;
    return a;
}

/// Bit s of x at bit 2s (x < 2^32): one half of a Morton interleave.
inline std::uint64_t spread_bits(std::uint32_t x) {
    std::uint64_t v = x;
    v = (v | (v << 16)) & 0x0000FFFF0000FFFFULL;
    v = (v | (v << 8)) & 0x00FF00FF00FF00FFULL;
    v = (v | (v << 4)) & 0x0F0F0F0F0F0F0F0FULL;
    v = (v | (v << 2)) & 0x3333333333333333ULL;
    v = (v | (v << 1)) & 0x5555555555555555ULL;
    return v;
}

/// The node's place in the hierarchy's depth-first order within its face:
/// its child index at each level from 1 down, two bits each, from the top
/// bit. A node's descendants follow it, before its next sibling, so those
/// at one level are the contiguous range depth_first_span() gives. Levels
/// up to 31 (the tracer caps them at 16).
inline std::uint64_t depth_first_key(const NodeId& id) {
    const int levels = id.level;
    if (levels == 0) return 0;
    // Every level at once, without a loop over ancestors (binary searches
    // over a patch's triangles evaluate it at each step; the loop had been
    // 3% of a close-up's instructions). Bit s of each word below speaks of
    // the ancestor at level `levels - s`: its down flag is ancestor_at's
    // test, whether the low s bits of i and j plus the node's own down flag
    // reach 2^s, which is the carry into bit s of i + j + down; its parent's
    // is the carry into bit s + 1; its offset in its parent is bit s of i
    // and of j.
    const std::uint64_t i = id.i, j = id.j;
    const std::uint64_t down = (i + j + (id.down ? 1u : 0u)) ^ i ^ j;
    const std::uint64_t parent_down = down >> 1;
    // child_of's layout, as two bits of the child index: an up parent's
    // children 0-2 are up at offsets (0,0), (1,0), (0,1), child 3 down; a down
    // parent's 0-2 are down at (1,0), (1,1), (0,1), child 3 up.
    const std::uint64_t low = (parent_down & (~down | (j & i))) | (~parent_down & (down | i));
    const std::uint64_t high = (parent_down & (~down | (j & ~i))) | (~parent_down & (down | j));
    const std::uint64_t mask = (std::uint64_t{1} << levels) - 1;
    const std::uint64_t path = spread_bits(static_cast<std::uint32_t>(low & mask)) |
                               (spread_bits(static_cast<std::uint32_t>(high & mask)) << 1);
    return path << (62 - 2 * levels);
}

/// The keys depth_first_key() gives the descendants of `id` (any level):
/// [first, last).
inline std::pair<std::uint64_t, std::uint64_t> depth_first_span(const NodeId& id) {
    const std::uint64_t first = depth_first_key(id);
    return {first, first + (std::uint64_t{1} << (62 - 2 * id.level))};
}

/// The grid triangles of resolution n that have grid point (i, j) as a
/// corner, each rotated so that point comes first (counter-clockwise): calls
/// out(i1, j1, i2, j2) with the other two corners. "Up" triangle (x, y) has
/// corners (x,y) (x+1,y) (x,y+1); "down" triangle (x, y) has (x+1,y) (x+1,y+1) (x,y+1).
template <class Out>
void for_each_incident_grid_triangle(std::uint32_t n, std::uint32_t i, std::uint32_t j, Out out) {
    const long N = n, I = i, J = j;
    auto up_ok = [&](long x, long y) { return x >= 0 && y >= 0 && x + y <= N - 1; };
    auto down_ok = [&](long x, long y) { return x >= 0 && y >= 0 && x + y <= N - 2; };
    auto emit = [&](long i1, long j1, long i2, long j2) {
        out(static_cast<std::uint32_t>(i1), static_cast<std::uint32_t>(j1),
            static_cast<std::uint32_t>(i2), static_cast<std::uint32_t>(j2));
    };
    // Counter-clockwise around (i, j), starting towards +i.
    if (up_ok(I, J)) emit(I + 1, J, I, J + 1);              // up(i, j)
    if (down_ok(I - 1, J)) emit(I, J + 1, I - 1, J + 1);    // down(i-1, j)
    if (up_ok(I - 1, J)) emit(I - 1, J + 1, I - 1, J);      // up(i-1, j)
    if (down_ok(I - 1, J - 1)) emit(I - 1, J, I, J - 1);    // down(i-1, j-1)
    if (up_ok(I, J - 1)) emit(I, J - 1, I + 1, J - 1);      // up(i, j-1)
    if (down_ok(I, J - 1)) emit(I + 1, J - 1, I + 1, J);    // down(i, j-1)
}

}  // namespace subdivtrace::detail
