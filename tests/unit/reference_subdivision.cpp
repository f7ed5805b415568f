// The brute-force normal scheme of reference_subdivision.h.
#include "unit/reference_subdivision.h"

#include <algorithm>
#include <array>
#include <map>
#include <stdexcept>
#include <utility>

#include "subdivtrace/scheme.h"

namespace subdivtrace::testmesh {

namespace {

using EdgeKey = std::pair<std::uint32_t, std::uint32_t>;

EdgeKey undirected(std::uint32_t a, std::uint32_t b) { return {std::min(a, b), std::max(a, b)}; }

std::vector<Vec3> vertex_normals(const std::vector<Vec3>& p, const std::vector<Triangle>& tris) {
    std::vector<Vec3> sum(p.size(), Vec3(0.0));
    for (const Triangle& t : tris)
        for (int c = 0; c < 3; ++c)
            sum[t[c]] += angle_weighted_normal(p[t[c]], p[t[(c + 1) % 3]], p[t[(c + 2) % 3]]);
    for (Vec3& n : sum) n = finish_normal(n);
    return sum;
}

/// One level: every edge's new point, then the four children of each triangle.
void refine(std::vector<Vec3>& p, std::vector<Triangle>& tris, std::vector<std::uint8_t>& down) {
    const std::vector<Vec3> normal = vertex_normals(p, tris);
    std::map<EdgeKey, int> triangles_on_edge;
    for (const Triangle& t : tris)
        for (int c = 0; c < 3; ++c) ++triangles_on_edge[undirected(t[c], t[(c + 1) % 3])];
    // Boundary neighbours of each vertex (edges with one triangle).
    std::vector<std::vector<std::uint32_t>> boundary(p.size());
    for (const auto& [edge, count] : triangles_on_edge) {
        if (count > 2) throw std::invalid_argument("reference: non-manifold edge");
        if (count != 1) continue;
        boundary[edge.first].push_back(edge.second);
        boundary[edge.second].push_back(edge.first);
    }
    // The boundary's next vertex beyond `v`, walking away from `other`.
    const auto far_beyond = [&](std::uint32_t v, std::uint32_t other, Vec3& far) {
        if (boundary[v].size() != 2) return false;
        far = p[boundary[v][0] == other ? boundary[v][1] : boundary[v][0]];
        return true;
    };

    std::map<EdgeKey, std::uint32_t> new_vertex;
    std::vector<Vec3> next = p;
    for (const auto& [edge, count] : triangles_on_edge) {
        const auto [a, b] = edge;
        Vec3 point;
        if (count == 1) {
            EdgeStencil s;
            s.a = p[a];
            s.b = p[b];
            s.curve = true;
            s.has_a_far = far_beyond(a, b, s.a_far);
            s.has_b_far = far_beyond(b, a, s.b_far);
            point = normal_curve_edge_point(s);
        } else {
            point = normal_edge_point(p[a], p[b], normal[a], normal[b]);
        }
        new_vertex[edge] = static_cast<std::uint32_t>(next.size());
        next.push_back(point);
    }

    std::vector<Triangle> children;
    std::vector<std::uint8_t> child_down;
    for (std::size_t t = 0; t < tris.size(); ++t) {
        const auto [A, B, C] = std::array<std::uint32_t, 3>{tris[t][0], tris[t][1], tris[t][2]};
        const std::uint32_t ab = new_vertex.at(undirected(A, B));
        const std::uint32_t bc = new_vertex.at(undirected(B, C));
        const std::uint32_t ca = new_vertex.at(undirected(C, A));
        children.push_back({A, ab, ca});
        children.push_back({ab, B, bc});
        children.push_back({ca, bc, C});
        children.push_back(down[t] ? Triangle{ca, ab, bc} : Triangle{ab, bc, ca});
        for (int k = 0; k < 3; ++k) child_down.push_back(down[t]);
        child_down.push_back(!down[t]);
    }
    p.swap(next);
    tris.swap(children);
    down.swap(child_down);
}

}  // namespace

ReferenceLevel reference_normal_scheme(const Mesh& mesh, int levels) {
    if (mesh.has_normals()) throw std::invalid_argument("reference: given normals");
    ReferenceLevel out;
    out.positions = mesh.positions;
    out.triangles = mesh.triangles;
    std::vector<std::uint8_t> down(mesh.triangles.size(), 0);
    for (int k = 0; k < levels; ++k) refine(out.positions, out.triangles, down);
    out.vertex_normals = vertex_normals(out.positions, out.triangles);
    return out;
}

}  // namespace subdivtrace::testmesh
