// Consistent winding by a breadth-first walk over manifold edges (orient.h).
#include "orient.h"

namespace subdivtrace {

namespace {

constexpr std::uint32_t k_none = ~std::uint32_t{0};

/// The triangles at each vertex, in compressed rows (4 bytes per corner plus
/// 4 per vertex: the walk below finds an edge's other triangle through them,
/// a per-edge table would take three times the memory at a million triangles).
struct VertexFaces {
    std::vector<std::uint32_t> start;
    std::vector<std::uint32_t> faces;

    VertexFaces(const std::vector<Triangle>& triangles, std::size_t vertex_count)
        : start(vertex_count + 1, 0), faces(3 * triangles.size()) {
        for (const Triangle& t : triangles)
            for (std::uint32_t v : t) ++start[v + 1];
        for (std::size_t v = 0; v < vertex_count; ++v) start[v + 1] += start[v];
        std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
        for (std::size_t t = 0; t < triangles.size(); ++t)
            for (std::uint32_t v : triangles[t]) faces[fill[v]++] = static_cast<std::uint32_t>(t);
    }
};

/// Position of `v` among t's corners (t holds it).
int corner_of(const Triangle& t, std::uint32_t v) {
    return t[0] == v ? 0 : t[1] == v ? 1 : 2;
}

}  // namespace

Orientation consistent_orientation(const std::vector<Triangle>& triangles,
                                   std::size_t vertex_count) {
    const VertexFaces at(triangles, vertex_count);
    const std::size_t n = triangles.size();
    Orientation out;
    out.flipped.assign(n, 0);

    // The triangle across t's edge from corner c to c + 1 when exactly two
    // triangles hold that edge, and whether it runs the edge the same way.
    const auto across = [&](std::uint32_t t, int c, bool& same_way) {
        const std::uint32_t a = triangles[t][c], b = triangles[t][(c + 1) % 3];
        // Through the endpoint with fewer triangles.
        const bool through_a = at.start[a + 1] - at.start[a] <= at.start[b + 1] - at.start[b];
        const std::uint32_t x = through_a ? a : b, y = through_a ? b : a;
        std::uint32_t found = k_none, count = 0;
        for (std::uint32_t k = at.start[x]; k < at.start[x + 1]; ++k) {
            const std::uint32_t u = at.faces[k];
            if (u == t) continue;
            const Triangle& tri = triangles[u];
            const int cx = corner_of(tri, x);
            const bool x_to_y = tri[(cx + 1) % 3] == y;
            if (!x_to_y && tri[(cx + 2) % 3] != y) continue;
            if (++count > 1) return k_none;  // a non-manifold edge joins nothing
            found = u;
            same_way = x_to_y == through_a;  // u also runs a -> b
        }
        return found;
    };

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
                bool same_way = false;
                const std::uint32_t u = across(t, c, same_way);
                if (u == k_none) continue;
                // Running the edge the same way means one of the two turns.
                const bool want = (out.flipped[t] != 0) != same_way;
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
            for (std::size_t i = component; i < order.size(); ++i) out.flipped[order[i]] ^= 1;
            component_flips = size - component_flips;
        }
        out.flipped_count += component_flips;
    }
    out.conflicting_edges = conflicts / 2;
    return out;
}

}  // namespace subdivtrace
