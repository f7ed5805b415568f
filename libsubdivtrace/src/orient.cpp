// Consistent winding by a breadth-first walk over manifold edges (orient.h).
#include "orient.h"

#include "vertex_faces.h"

namespace subdivtrace {

namespace {

constexpr std::uint32_t k_none = ~std::uint32_t{0};

}  // namespace

Orientation consistent_orientation(const std::vector<Triangle>& triangles,
                                   std::size_t vertex_count) {
    // Faces per vertex, 4 bytes per corner: a table of every edge would take
    // three times the memory at a million triangles.
    const detail::VertexFaces at(triangles, vertex_count);
    const std::size_t n = triangles.size();
    Orientation out;
    out.flipped.assign(n, 0);

    // The triangle across t's edge from corner c to c + 1 when exactly two
    // triangles hold that edge, and whether it runs the edge the same way.
    const auto across = [&](std::uint32_t t, int c, bool& same_way) {
        const std::uint32_t a = triangles[t][c], b = triangles[t][(c + 1) % 3];
        std::uint32_t found = k_none, count = 0;
        at.for_each_face_of_edge(triangles, a, b, [&](std::uint32_t u) {
            if (u == t || ++count > 1) return;
            found = u;
            same_way = triangles[u][(detail::corner_of(triangles[u], a) + 1) % 3] == b;  // u also runs a -> b
        });
        return count == 1 ? found : k_none;  // a non-manifold edge joins nothing
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
