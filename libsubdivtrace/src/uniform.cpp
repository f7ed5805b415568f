// Uniform 1-to-4 subdivision over plain arrays: the reference level-k mesh and
// the baseline the adaptive tracer is measured against.
#include "subdivtrace/uniform.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "level_topology.h"

namespace subdivtrace {

namespace {

/// One level of subdivision: positions of old vertices, then edge points,
/// then the topology rewritten (children 4t..4t+3, see uniform.h).
void subdivide_once(SchemeKind scheme, std::vector<Vec3>& positions,
                    std::vector<Triangle>& triangles, std::vector<std::uint8_t>& down,
                    std::vector<Vec2>* corner_uvs, std::vector<Vec3>* corner_normals) {
    const LevelTopology topo(positions, triangles);
    const std::vector<Vec3> normals =
        scheme == SchemeKind::normal ? gouraud_normals(positions, triangles) : std::vector<Vec3>{};

    // Positions of the old vertices (Loop moves them; interpolating schemes keep them).
    const std::size_t old_count = positions.size();
    std::vector<Vec3> next(old_count + topo.edge_count());
    VertexRing ring_a;
    VertexRing ring_b;
    for (std::size_t v = 0; v < old_count; ++v) {
        if (scheme == SchemeKind::loop) {
            topo.fill_ring(static_cast<std::uint32_t>(v), positions, ring_a);
            next[v] = loop_vertex_point(ring_a);
        } else {
            next[v] = positions[v];
        }
    }

    // Edge points.
    EdgeStencil stencil;
    for (std::uint32_t e = 0; e < topo.edge_count(); ++e) {
        const LevelTopology::Edge& edge = topo.edge(e);
        stencil.a = positions[edge.a];
        stencil.b = positions[edge.b];
        stencil.interior = edge.interior;
        if (edge.interior) {
            stencil.c = positions[edge.c];
            stencil.d = positions[edge.d];
        }
        if (scheme == SchemeKind::normal) {
            stencil.normal_a = normals[edge.a];
            stencil.normal_b = normals[edge.b];
        } else if (scheme == SchemeKind::butterfly) {
            topo.fill_ring(edge.a, positions, ring_a);
            topo.fill_ring(edge.b, positions, ring_b);
            stencil.ring_a = &ring_a;
            stencil.ring_b = &ring_b;
            stencil.index_b_in_a = topo.ring_index(edge.a, edge.b);
            stencil.index_a_in_b = topo.ring_index(edge.b, edge.a);
        }
        next[old_count + e] = edge_point(scheme, stencil);
    }

    // Topology: each triangle becomes four.
    std::vector<Triangle> children;
    children.reserve(triangles.size() * 4);
    std::vector<std::uint8_t> children_down;
    children_down.reserve(triangles.size() * 4);
    for (std::size_t t = 0; t < triangles.size(); ++t) {
        const Triangle& tri = triangles[t];
        const std::uint32_t m_ab = static_cast<std::uint32_t>(old_count) + topo.face_edge(t, 0);
        const std::uint32_t m_bc = static_cast<std::uint32_t>(old_count) + topo.face_edge(t, 1);
        const std::uint32_t m_ca = static_cast<std::uint32_t>(old_count) + topo.face_edge(t, 2);
        children.push_back({tri[0], m_ab, m_ca});
        children.push_back({m_ab, tri[1], m_bc});
        children.push_back({m_ca, m_bc, tri[2]});
        // The middle child is the same triangle either way; rotating it for
        // "down" parents keeps corner order equal to the hierarchy's grid order.
        if (down[t]) children.push_back({m_ca, m_ab, m_bc});
        else children.push_back({m_ab, m_bc, m_ca});
        for (int c = 0; c < 3; ++c) children_down.push_back(down[t]);
        children_down.push_back(!down[t]);
    }

    // Per-corner attributes are linear over the base triangle: midpoints of corners.
    auto split_corners = [&](auto& corners) {
        using T = typename std::decay_t<decltype(corners)>::value_type;
        std::vector<T> out;
        out.reserve(corners.size() * 4);
        for (std::size_t t = 0; t < triangles.size(); ++t) {
            const T a = corners[3 * t], b = corners[3 * t + 1], c = corners[3 * t + 2];
            const T ab = (a + b) * 0.5, bc = (b + c) * 0.5, ca = (c + a) * 0.5;
            for (const T& x : {a, ab, ca, ab, b, bc, ca, bc, c}) out.push_back(x);
            if (down[t]) {
                for (const T& x : {ca, ab, bc}) out.push_back(x);
            } else {
                for (const T& x : {ab, bc, ca}) out.push_back(x);
            }
        }
        corners.swap(out);
    };
    if (corner_uvs && !corner_uvs->empty()) split_corners(*corner_uvs);
    if (corner_normals && !corner_normals->empty()) split_corners(*corner_normals);

    positions.swap(next);
    triangles.swap(children);
    down.swap(children_down);
}

}  // namespace

SubdividedMesh subdivide_uniform(const Mesh& mesh, SchemeKind scheme, int levels) {
    if (levels < 0 || levels > k_max_uniform_levels) {
        throw std::invalid_argument("levels must be in 0.." +
                                    std::to_string(k_max_uniform_levels) + ", got " +
                                    std::to_string(levels));
    }
    const double triangle_count =
        static_cast<double>(mesh.triangles.size()) * std::pow(4.0, levels);
    if (triangle_count > 1.0e9) {
        throw std::invalid_argument("uniform level " + std::to_string(levels) + " would have " +
                                    std::to_string(static_cast<long long>(triangle_count)) +
                                    " triangles (more than 1e9)");
    }
    SubdividedMesh out;
    out.levels = levels;
    out.positions = mesh.positions;
    out.triangles = mesh.triangles;
    out.corner_uvs = mesh.corner_uvs;
    out.corner_normals = mesh.corner_normals;
    std::vector<std::uint8_t> down(out.triangles.size(), 0);
    for (int k = 0; k < levels; ++k) {
        subdivide_once(scheme, out.positions, out.triangles, down, &out.corner_uvs,
                       &out.corner_normals);
    }
    for (Vec3& n : out.corner_normals) n = finish_normal(n);
    out.vertex_normals = gouraud_normals(out.positions, out.triangles);
    out.base_face.resize(out.triangles.size());
    const std::size_t per_base = std::size_t{1} << (2 * levels);
    for (std::size_t t = 0; t < out.triangles.size(); ++t) {
        out.base_face[t] = static_cast<std::uint32_t>(t / per_base);
    }
    return out;
}

void push_to_limit(SubdividedMesh& sub, SchemeKind scheme) {
    if (scheme != SchemeKind::loop) return;
    const LevelTopology topo(sub.positions, sub.triangles);
    std::vector<Vec3> limit(sub.positions.size());
    VertexRing ring;
    for (std::uint32_t v = 0; v < sub.positions.size(); ++v) {
        topo.fill_ring(v, sub.positions, ring);
        limit[v] = loop_limit_point(ring);
    }
    sub.positions.swap(limit);
}

Mesh to_mesh(const SubdividedMesh& sub) {
    Mesh mesh;
    mesh.positions = sub.positions;
    mesh.triangles = sub.triangles;
    mesh.corner_uvs = sub.corner_uvs;
    mesh.corner_normals.reserve(sub.triangles.size() * 3);
    for (const Triangle& t : sub.triangles) {
        for (std::uint32_t v : t) mesh.corner_normals.push_back(sub.vertex_normals[v]);
    }
    return mesh;
}

}  // namespace subdivtrace
