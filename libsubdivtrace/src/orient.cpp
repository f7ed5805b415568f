// Consistent winding by a breadth-first walk over manifold edges (orient.h).
#include "orient.h"

#include <algorithm>

namespace subdivtrace {

namespace {

constexpr std::uint32_t k_none = ~std::uint32_t{0};

/// One side of an undirected edge: which triangle corner starts it, and
/// whether that triangle runs it from the lower vertex index to the higher.
struct EdgeSide {
    std::uint32_t high;
    std::uint32_t corner;  // 3 * triangle + c: the edge from corner c to c + 1
    bool ascending;
};

/// neighbour[3t + c]: the triangle across t's edge c when exactly two
/// triangles share that edge, else k_none; same_way[3t + c]: both run it in
/// the same direction (so their windings disagree).
struct EdgeNeighbours {
    std::vector<std::uint32_t> neighbour;
    std::vector<std::uint8_t> same_way;  // bytes, not vector<bool>: read in the hot loop
};

EdgeNeighbours manifold_neighbours(const std::vector<Triangle>& triangles,
                                   std::size_t vertex_count) {
    // Edges bucketed by their lower vertex (a counting sort, linear time);
    // a bucket holds a few edges, so matching inside one is a short sort.
    const std::size_t corners = 3 * triangles.size();
    std::vector<std::uint32_t> start(vertex_count + 1, 0);
    for (const Triangle& t : triangles)
        for (int c = 0; c < 3; ++c) ++start[std::min(t[c], t[(c + 1) % 3]) + 1];
    for (std::size_t v = 0; v < vertex_count; ++v) start[v + 1] += start[v];
    std::vector<EdgeSide> sides(corners);
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    for (std::size_t t = 0; t < triangles.size(); ++t)
        for (int c = 0; c < 3; ++c) {
            const std::uint32_t a = triangles[t][c], b = triangles[t][(c + 1) % 3];
            sides[fill[std::min(a, b)]++] = {std::max(a, b), static_cast<std::uint32_t>(3 * t + c),
                                            a < b};
        }

    EdgeNeighbours out{std::vector<std::uint32_t>(corners, k_none),
                       std::vector<std::uint8_t>(corners, 0)};
    for (std::size_t v = 0; v < vertex_count; ++v) {
        const auto first = sides.begin() + start[v], last = sides.begin() + start[v + 1];
        // Within a bucket the sides are in corner order already (filled in
        // triangle order), so ordering by `high` alone, stably, keeps it.
        const auto by_high = [](const EdgeSide& x, const EdgeSide& y) { return x.high < y.high; };
        if (last - first <= 16) {
            for (auto i = first + 1; i < last; ++i)  // insertion sort: a bucket holds ~3
                for (auto j = i; j != first && by_high(*j, *(j - 1)); --j) std::iter_swap(j, j - 1);
        } else {
            std::stable_sort(first, last, by_high);
        }
        for (auto run = first; run != last;) {
            auto end = run;
            while (end != last && end->high == run->high) ++end;
            if (end - run == 2) {
                const EdgeSide& x = run[0];
                const EdgeSide& y = run[1];
                out.neighbour[x.corner] = y.corner / 3;
                out.neighbour[y.corner] = x.corner / 3;
                out.same_way[x.corner] = out.same_way[y.corner] = x.ascending == y.ascending ? 1 : 0;
            }
            run = end;
        }
    }
    return out;
}

}  // namespace

Orientation consistent_orientation(const std::vector<Triangle>& triangles,
                                   std::size_t vertex_count) {
    const EdgeNeighbours edges = manifold_neighbours(triangles, vertex_count);
    const std::size_t n = triangles.size();
    Orientation out;
    out.flipped.assign(n, 0);
    std::vector<std::uint8_t> reached(n, 0);
    std::vector<std::uint32_t> order;  // triangles in visiting order, component by component
    order.reserve(n);
    std::size_t conflicts = 0;  // each conflicting edge is seen from both sides
    for (std::size_t seed = 0; seed < n; ++seed) {
        if (reached[seed]) continue;
        const std::size_t component = order.size();
        reached[seed] = 1;
        order.push_back(static_cast<std::uint32_t>(seed));
        std::size_t component_flips = 0;
        for (std::size_t next = component; next < order.size(); ++next) {
            const std::uint32_t t = order[next];
            for (int c = 0; c < 3; ++c) {
                const std::uint32_t u = edges.neighbour[3 * t + c];
                if (u == k_none) continue;
                // Running the edge the same way means one of the two turns.
                const bool want = (out.flipped[t] ^ edges.same_way[3 * t + c]) != 0;
                if (!reached[u]) {
                    reached[u] = 1;
                    out.flipped[u] = want ? 1 : 0;
                    component_flips += want ? 1 : 0;
                    order.push_back(u);
                } else if ((out.flipped[u] != 0) != want) {
                    ++conflicts;
                }
            }
        }
        // Keep the winding most of the component's triangles already have.
        const std::size_t size = order.size() - component;
        if (2 * component_flips > size) {
            for (std::size_t i = component; i < order.size(); ++i)
                out.flipped[order[i]] ^= 1;
            component_flips = size - component_flips;
        }
        out.flipped_count += component_flips;
    }
    out.conflicting_edges = conflicts / 2;
    return out;
}

}  // namespace subdivtrace
