#include "base_topology.h"

#include <algorithm>

#include "creases.h"

#include "subdivtrace/scheme.h"

namespace subdivtrace::detail {

BaseTopology::BaseTopology(const Mesh& mesh)
    : mesh_(mesh), faces_(mesh.triangles, mesh.positions.size()) {
    const std::size_t nv = mesh.positions.size();
    // Closed: every edge, seen from each of its faces, has exactly two.
    for (const Triangle& t : mesh.triangles) {
        for (int c = 0; c < 3 && closed_; ++c)
            closed_ = edge_face_count(t[c], t[(c + 1) % 3]) == 2;
        if (!closed_) break;
    }
    if (mesh.has_normals()) {
        given_vertex_.assign(nv, Vec3(0.0));
        std::vector<bool> seen(nv, false);
        for (std::uint32_t f = 0; f < mesh.triangles.size(); ++f)
            for (std::uint32_t c = 0; c < 3; ++c) {
                const std::uint32_t v = mesh.triangles[f][c];
                const Vec3 n = given_normal_of(mesh, f, v);
                if (!seen[v]) {
                    seen[v] = true;
                    given_vertex_[v] = n;
                } else if (n != given_vertex_[v]) {
                    given_split_.push_back({3 * f + c, n});
                }
            }
        given_split_.shrink_to_fit();
    }
    crease_mask_ = crease_masks(mesh);
    const bool any_crease = std::any_of(crease_mask_.begin(), crease_mask_.end(),
                                        [](std::uint8_t m) { return m != 0; });
    if (!any_crease) crease_mask_ = std::vector<std::uint8_t>();  // frees it
    // A closed mesh without creases has no curve: it keeps no flags.
    if (closed_ && !any_crease) return;
    on_curve_.assign(mesh.positions.size(), 0);
    bool at_most_two = true;
    for (std::uint32_t f = 0; f < mesh.triangles.size(); ++f) {
        const Triangle& t = mesh.triangles[f];
        for (int e = 0; e < 3; ++e) {
            const std::uint32_t u = t[e], w = t[(e + 1) % 3];
            const std::size_t faces = edge_face_count(u, w);
            at_most_two = at_most_two && faces <= 2;
            if (is_crease(f, e) || faces == 1) on_curve_[u] = on_curve_[w] = 1;
        }
    }
    at_most_two_ = at_most_two;
}

Vec3 BaseTopology::given_normal(std::uint32_t face, std::uint32_t v) const {
    if (given_vertex_.empty()) return Vec3(0.0);
    const Triangle& t = mesh_.triangles[face];
    const std::uint32_t c = t[0] == v ? 0 : (t[1] == v ? 1 : (t[2] == v ? 2 : 3));
    if (c == 3) return Vec3(0.0);
    if (!given_split_.empty()) {
        const std::uint32_t slot = 3 * face + c;
        const auto it = std::lower_bound(given_split_.begin(), given_split_.end(), slot,
                                         [](const GivenCorner& g, std::uint32_t s) { return g.slot < s; });
        if (it != given_split_.end() && it->slot == slot) return it->normal;
    }
    return given_vertex_[v];
}

std::size_t BaseTopology::edge_face_count(std::uint32_t u, std::uint32_t w) const {
    std::size_t n = 0;
    for_each_face_of_edge(u, w, [&](std::uint32_t) { ++n; });
    return n;
}

VertexKey BaseTopology::canonical(std::uint32_t face, int level, std::uint32_t i,
                                  std::uint32_t j) const {
    std::uint32_t w[3] = {(std::uint32_t{1} << level) - i - j, i, j};
    // Reduce to the birth level: the coarsest level that has this point.
    while (level > 0 && (w[0] | w[1] | w[2]) % 2 == 0) {
        w[0] >>= 1;
        w[1] >>= 1;
        w[2] >>= 1;
        --level;
    }
    const Triangle& t = mesh_.triangles[face];
    VertexKey key;
    key.level = static_cast<std::uint8_t>(level);
    const int zeros = (w[0] == 0) + (w[1] == 0) + (w[2] == 0);
    if (zeros == 2) {
        key.kind = VertexKey::base_vertex;
        key.level = 0;
        key.a = t[w[0] ? 0 : (w[1] ? 1 : 2)];
        return key;
    }
    if (zeros == 1) {
        // On the base edge between the two corners with weight.
        const int x = w[0] == 0 ? 1 : 0;
        const int y = w[2] == 0 ? 1 : 2;
        const bool x_low = t[x] < t[y];
        key.kind = VertexKey::edge_point;
        key.a = x_low ? t[x] : t[y];
        key.b = x_low ? t[y] : t[x];
        key.c = x_low ? w[y] : w[x];
        return key;
    }
    key.kind = VertexKey::face_point;
    key.a = face;
    key.b = w[1];
    key.c = w[2];
    return key;
}

void BaseTopology::representations(const VertexKey& key, int level,
                                   std::vector<GridPoint>& out) const {
    out.clear();
    const std::uint32_t n = std::uint32_t{1} << level;
    const int shift = level - key.level;
    switch (key.kind) {
        case VertexKey::base_vertex:
            for (std::uint32_t f : faces_of_vertex(key.a)) {
                const Triangle& t = mesh_.triangles[f];
                if (t[0] == key.a) out.push_back({f, 0, 0});
                else if (t[1] == key.a) out.push_back({f, n, 0});
                else out.push_back({f, 0, n});
            }
            break;
        case VertexKey::edge_point: {
            const std::uint32_t w_hi = key.c << shift;
            for_each_face_of_edge(key.a, key.b, [&](std::uint32_t f) {
                const Triangle& t = mesh_.triangles[f];
                std::uint32_t w[3] = {0, 0, 0};
                for (int c = 0; c < 3; ++c) {
                    if (t[c] == key.b) w[c] = w_hi;
                    else if (t[c] == key.a) w[c] = n - w_hi;
                }
                out.push_back({f, w[1], w[2]});
            });
            break;
        }
        case VertexKey::face_point:
            out.push_back({key.a, key.b << shift, key.c << shift});
            break;
    }
}

}  // namespace subdivtrace::detail
