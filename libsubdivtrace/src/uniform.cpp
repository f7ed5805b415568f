// Uniform 1-to-4 subdivision over plain arrays: the reference level-k mesh and
// the baseline the adaptive tracer is measured against.
#include "subdivtrace/uniform.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>

#include "creases.h"
#include "edge_rings.h"
#include "huge_pages.h"
#include "level_topology.h"
#include "scheme_rules.h"

namespace subdivtrace {

using detail::rules_of;
using detail::SchemeRules;

namespace {

/// What one level carries besides positions: per triangle its "down" flag
/// and crease mask (bit e: edge e is a crease), and per corner its UV.
struct LevelState {
    detail::HugeArray<std::uint8_t> down;
    std::vector<std::uint8_t> creases;  ///< empty: the mesh has none
    std::vector<Vec2> corner_uvs;       ///< empty: the mesh has none
};

/// Given normals at the corners of this level (normal scheme): a base
/// vertex's (index below the base count) in its base triangle, zero elsewhere.
detail::HugeArray<Vec3> given_corner_normals(const Mesh& base, const std::vector<Triangle>& triangles,
                                             int level) {
    detail::HugeArray<Vec3> given(3 * triangles.size(), Vec3(0.0));
    for (std::size_t t = 0; t < triangles.size(); ++t) {
        const auto face = static_cast<std::uint32_t>(t >> (2 * level));
        for (int c = 0; c < 3; ++c)
            if (triangles[t][c] < base.positions.size())
                given[3 * t + c] = detail::given_normal_of(base, face, triangles[t][c]);
    }
    return given;
}

/// Whether the mesh's given normals are the scheme's at this level.
bool given_at_level(const Mesh& base, const SchemeRules& scheme, int level, bool given_every_level) {
    return scheme.takes_given_normals && base.has_normals() && (level == 0 || given_every_level);
}

/// A level's normals at triangle corners, as the edge rules read them. Where
/// every vertex has one sector (no crease, no bowtie) and no given normal,
/// a corner's normal is its vertex's: one per vertex (about 12 bytes a
/// triangle), where one per corner wrote and read 72 bytes a triangle at
/// every level. The same bits either way (smooth_vertex_normals).
struct CornerNormals {
    detail::HugeArray<Vec3> per_corner;  ///< 3t + c; empty when per_vertex holds them
    detail::HugeArray<Vec3> per_vertex;
    /// The normal at corner `slot` (3t + c), whose vertex is v.
    const Vec3& at(std::size_t slot, std::uint32_t v) const {
        return per_corner.empty() ? per_vertex[v] : per_corner[slot];
    }
    bool empty() const { return per_corner.empty() && per_vertex.empty(); }
};

/// The scheme's normals at the corners of one level.
CornerNormals scheme_normals(const Mesh& base, const SchemeRules& scheme, const LevelTopology& topo,
                             const std::vector<Vec3>& positions, const std::vector<Triangle>& triangles,
                             int level, bool given_every_level) {
    CornerNormals normals;
    const bool given = given_at_level(base, scheme, level, given_every_level);
    if (!given && topo.one_sector_everywhere())
        smooth_vertex_normals(positions, triangles, normals.per_vertex);
    else
        normals.per_corner = topo.sector_normals(
            positions, triangles, given ? given_corner_normals(base, triangles, level) : detail::HugeArray<Vec3>{});
    return normals;
}

/// One level of subdivision: positions of old vertices, then edge points,
/// then the triangles rewritten (children 4t..4t+3, see uniform.h) and `topo`
/// replaced by theirs (or reset where `child_topology` is false: the last
/// level needs one only for creases' sectors and given normals).
void subdivide_once(const Mesh& base, const SchemeRules& scheme, int level, bool given_every_level,
                    std::vector<Vec3>& positions, std::vector<Triangle>& triangles,
                    LevelState& state, std::optional<LevelTopology>& topo_slot,
                    bool child_topology) {
    const LevelTopology& topo = *topo_slot;
    const CornerNormals normals =
        scheme.edge_rule_reads_normals
            ? scheme_normals(base, scheme, topo, positions, triangles, level, given_every_level)
            : CornerNormals{};

    // Positions of the old vertices (Loop moves them; interpolating schemes keep them).
    const std::size_t old_count = positions.size();
    std::vector<Vec3> next;
    detail::resize_huge(next, old_count + topo.edge_count());
    VertexRing ring_a;
    VertexRing ring_b;
    for (std::size_t v = 0; v < old_count; ++v) {
        if (scheme.moves_old_vertices()) {
            topo.fill_ring(static_cast<std::uint32_t>(v), positions, ring_a);
            next[v] = scheme.vertex_rule(ring_a);
        } else {
            next[v] = positions[v];
        }
    }

    // The curve beyond endpoint v of curve edge (v, other).
    const auto curve_end = [&](std::uint32_t v, std::uint32_t other, bool& has_far, Vec3& far,
                               Vec3& normal) {
        const std::uint32_t nbr[2] = {topo.curve_nbr(v, 0), topo.curve_nbr(v, 1)};
        const detail::CurveEnd end = detail::curve_end(topo.curve_count(v), nbr, other, topo.single_sector(v));
        has_far = end.has_far;
        if (has_far) far = positions[end.far];
        normal = end.dart && !normals.empty() ? normals.at(topo.first_slot(v), v) : Vec3(0.0);
    };

    // Edge points.
    const auto position_of = [&](std::uint32_t v) { return positions[v]; };
    const auto end_of = [&](std::uint32_t v) {
        return detail::EdgeEnd{v, topo.ring_indices(v), topo.single_sector(v) ? nullptr : topo.ring_curve(v)};
    };
    const auto regular_six = [&](std::uint32_t v) { return topo.regular_six(v); };
    EdgeStencil stencil;
    for (std::uint32_t e = 0; e < topo.edge_count(); ++e) {
        const LevelTopology::Edge& edge = topo.edge(e);
        if (detail::takes_regular_edge_rule(scheme, edge.interior, edge.curve, edge.a, edge.b, regular_six)) {
            next[old_count + e] = detail::regular_edge_point(scheme, end_of(edge.a), end_of(edge.b),
                                                             positions[edge.c], positions[edge.d], position_of);
            continue;
        }
        stencil.a = positions[edge.a];
        stencil.b = positions[edge.b];
        stencil.interior = edge.interior;
        stencil.curve = edge.curve;
        if (edge.interior) {
            stencil.c = positions[edge.c];
            stencil.d = positions[edge.d];
        }
        if (edge.curve) {
            curve_end(edge.a, edge.b, stencil.has_a_far, stencil.a_far, stencil.normal_a);
            curve_end(edge.b, edge.a, stencil.has_b_far, stencil.b_far, stencil.normal_b);
        } else if (scheme.edge_rule_reads_normals) {
            // Both endpoints' normals in the sector of the edge's first triangle.
            const std::size_t slot_a = 3 * edge.face + edge.corner;
            const std::size_t slot_b = 3 * edge.face + (edge.corner + 1) % 3;
            stencil.normal_a = normals.at(slot_a, triangles[edge.face][edge.corner]);
            stencil.normal_b = normals.at(slot_b, triangles[edge.face][(edge.corner + 1) % 3]);
        }
        if (scheme.edge_rule_reads_rings)
            detail::fill_edge_rings(end_of(edge.a), end_of(edge.b), position_of, ring_a, ring_b, stencil);
        next[old_count + e] = scheme.edge_rule(stencil);
    }

    // Topology: each triangle becomes four; a crease's halves stay creases.
    std::vector<Triangle> children;
    detail::reserve_huge(children, triangles.size() * 4);
    LevelState out;
    out.down.reserve(triangles.size() * 4);
    if (!state.creases.empty()) detail::reserve_huge(out.creases, triangles.size() * 4);
    // Each corner stored in place: a Triangle built on the stack and copied
    // in reads back its three 4-byte stores as one 8-byte load, which the
    // processor cannot forward (this loop was about half of this function's
    // own time at level 4).
    const auto add_child = [&children](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
        Triangle& child = children.emplace_back();
        child[0] = a;
        child[1] = b;
        child[2] = c;
    };
    for (std::size_t t = 0; t < triangles.size(); ++t) {
        const Triangle& tri = triangles[t];
        const std::uint32_t m_ab = static_cast<std::uint32_t>(old_count) + topo.face_edge(t, 0);
        const std::uint32_t m_bc = static_cast<std::uint32_t>(old_count) + topo.face_edge(t, 1);
        const std::uint32_t m_ca = static_cast<std::uint32_t>(old_count) + topo.face_edge(t, 2);
        add_child(tri[0], m_ab, m_ca);
        add_child(m_ab, tri[1], m_bc);
        add_child(m_ca, m_bc, tri[2]);
        // The middle child is the same triangle either way; rotating it for
        // "down" parents keeps corner order equal to the hierarchy's grid order.
        if (state.down[t]) add_child(m_ca, m_ab, m_bc);
        else add_child(m_ab, m_bc, m_ca);
        for (int c = 0; c < 3; ++c) out.down.push_back(state.down[t]);
        out.down.push_back(!state.down[t]);
        if (!state.creases.empty()) {
            const std::uint8_t m = state.creases[t];
            out.creases.push_back(m & 0b101);  // A-mAB on AB, mCA-A on CA
            out.creases.push_back(m & 0b011);  // mAB-B on AB, B-mBC on BC
            out.creases.push_back(m & 0b110);  // mBC-C on BC, C-mCA on CA
            out.creases.push_back(0);
        }
    }

    // Per-corner UVs are linear over the base triangle: midpoints of corners.
    if (!state.corner_uvs.empty()) {
        const std::vector<Vec2>& corners = state.corner_uvs;
        detail::reserve_huge(out.corner_uvs, corners.size() * 4);
        for (std::size_t t = 0; t < triangles.size(); ++t) {
            const Vec2 a = corners[3 * t], b = corners[3 * t + 1], c = corners[3 * t + 2];
            const Vec2 ab = (a + b) * 0.5, bc = (b + c) * 0.5, ca = (c + a) * 0.5;
            for (const Vec2& x : {a, ab, ca, ab, b, bc, ca, bc, c}) out.corner_uvs.push_back(x);
            if (state.down[t]) {
                for (const Vec2& x : {ca, ab, bc}) out.corner_uvs.push_back(x);
            } else {
                for (const Vec2& x : {ab, bc, ca}) out.corner_uvs.push_back(x);
            }
        }
    }

    // The children's connectivity follows from the parent's, unless an edge
    // has three or more triangles (then sorting decides as for any mesh).
    if (!child_topology) topo_slot.reset();
    else if (topo.manifold_edges())
        topo_slot = LevelTopology::refined(topo, triangles, old_count, children, out.creases);
    else
        topo_slot.emplace(next, children, out.creases, topo.has_rings());
    positions.swap(next);
    triangles.swap(children);
    state = std::move(out);
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
    return detail::subdivide_uniform(mesh, scheme, levels, detail::k_given_normals_every_level);
}

SubdividedMesh detail::subdivide_uniform(const Mesh& mesh, SchemeKind kind, int levels,
                                         bool given_every_level) {
    const SchemeRules& scheme = rules_of(kind);
    SubdividedMesh out;
    out.levels = levels;
    out.positions = mesh.positions;
    out.triangles = mesh.triangles;
    LevelState state;
    state.down.assign(out.triangles.size(), 0);
    state.creases = detail::crease_masks(mesh);
    if (std::all_of(state.creases.begin(), state.creases.end(), [](std::uint8_t m) { return m == 0; }))
        state.creases.clear();
    state.corner_uvs = mesh.corner_uvs;
    // The last level's normals need its topology only for sectors and given normals.
    const bool given_last = given_at_level(mesh, scheme, levels, given_every_level);
    // Rings only for the schemes that read them (the normal scheme reads none).
    std::optional<LevelTopology> topo(std::in_place, out.positions, out.triangles, state.creases,
                                      scheme.reads_ordered_rings());
    for (int k = 0; k < levels; ++k) {
        const bool last = k + 1 == levels;
        subdivide_once(mesh, scheme, k, given_every_level, out.positions, out.triangles, state,
                       topo, !last || !state.creases.empty() || given_last);
    }
    out.corner_uvs = std::move(state.corner_uvs);
    out.crease_masks = std::move(state.creases);
    if (!topo) {
        // No crease and no given normal at the last level: one normal per
        // vertex, summed directly (no per-corner array).
        smooth_vertex_normals(out.positions, out.triangles, out.vertex_normals);
    } else {
        CornerNormals normals =
            scheme_normals(mesh, scheme, *topo, out.positions, out.triangles, levels, given_every_level);
        if (normals.per_corner.empty()) {
            out.vertex_normals.assign(normals.per_vertex.begin(), normals.per_vertex.end());
        } else {
            // A vertex's first corner (in slot order) names its normal; the
            // corners that differ are kept apart.
            const detail::HugeArray<Vec3>& corners = normals.per_corner;
            detail::assign_huge(out.vertex_normals, out.positions.size(), Vec3(0.0));
            detail::HugeArray<std::uint8_t> named(out.positions.size(), 0);
            for (std::size_t slot = 0; slot < corners.size(); ++slot) {
                const std::uint32_t v = out.triangles[slot / 3][slot % 3];
                if (!named[v]) {
                    named[v] = 1;
                    out.vertex_normals[v] = corners[slot];
                } else if (corners[slot] != out.vertex_normals[v]) {
                    out.split_corners.push_back({static_cast<std::uint32_t>(slot), corners[slot]});
                }
            }
        }
    }
    detail::resize_huge(out.base_face, out.triangles.size());
    const std::size_t per_base = std::size_t{1} << (2 * levels);
    for (std::size_t t = 0; t < out.triangles.size(); ++t) {
        out.base_face[t] = static_cast<std::uint32_t>(t / per_base);
    }
    return out;
}

void push_to_limit(SubdividedMesh& sub, SchemeKind scheme) {
    const SchemeRules& rules = rules_of(scheme);
    if (!rules.draws_limit_points()) return;
    const LevelTopology topo(sub.positions, sub.triangles, sub.crease_masks);
    std::vector<Vec3> limit;
    detail::resize_huge(limit, sub.positions.size());
    VertexRing ring;
    for (std::uint32_t v = 0; v < sub.positions.size(); ++v) {
        topo.fill_ring(v, sub.positions, ring);
        limit[v] = rules.drawn_point(ring);
    }
    sub.positions.swap(limit);
}

Mesh to_mesh(const SubdividedMesh& sub) {
    Mesh mesh;
    mesh.positions = sub.positions;
    mesh.triangles = sub.triangles;
    mesh.corner_uvs = sub.corner_uvs;
    mesh.corner_normals = sub.corner_normals();
    return mesh;
}

Mesh to_mesh(SubdividedMesh&& sub) {
    Mesh mesh;
    mesh.corner_normals = sub.corner_normals();
    std::vector<Vec3>().swap(sub.vertex_normals);
    std::vector<SubdividedMesh::SplitCorner>().swap(sub.split_corners);
    mesh.positions = std::move(sub.positions);
    mesh.triangles = std::move(sub.triangles);
    mesh.corner_uvs = std::move(sub.corner_uvs);
    return mesh;
}

Vec3 SubdividedMesh::corner_normal(std::size_t t, int c) const {
    const auto slot = static_cast<std::uint32_t>(3 * t + static_cast<std::size_t>(c));
    if (!split_corners.empty()) {
        const auto it = std::lower_bound(
            split_corners.begin(), split_corners.end(), slot,
            [](const SplitCorner& s, std::uint32_t x) { return s.slot < x; });
        if (it != split_corners.end() && it->slot == slot) return it->normal;
    }
    return vertex_normals[triangles[t][c]];
}

std::vector<Vec3> SubdividedMesh::corner_normals() const {
    std::vector<Vec3> out;
    detail::resize_huge(out, 3 * triangles.size());
    for (std::size_t t = 0; t < triangles.size(); ++t)
        for (int c = 0; c < 3; ++c) out[3 * t + c] = vertex_normals[triangles[t][c]];
    for (const SplitCorner& s : split_corners) out[s.slot] = s.normal;
    return out;
}

}  // namespace subdivtrace
