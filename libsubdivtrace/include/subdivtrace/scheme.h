#pragma once
/// \file scheme.h
/// The subdivision operator F (DESIGN.md section 3): which scheme, and the
/// stencils that compute one level's new positions from the previous level.

#include <optional>
#include <string>
#include <vector>

#include "subdivtrace/mesh.h"

namespace subdivtrace {

/// The three schemes we ship.
enum class SchemeKind {
    /// The paper's interpolating scheme: edge points from the two endpoint
    /// normals, normals recomputed by Gouraud on every level.
    normal,
    /// Loop (1987), approximating; weights as OpenMesh's LoopT.
    loop,
    /// Modified Butterfly (Zorin, Schroeder, Sweldens 1996), interpolating;
    /// weights as OpenMesh's ModifiedButterflyT.
    butterfly,
};

/// "normal" | "loop" | "butterfly"; nullopt for anything else.
std::optional<SchemeKind> parse_scheme(const std::string& name);
const char* scheme_name(SchemeKind kind);

/// True for schemes whose old vertices keep their positions.
inline bool is_interpolating(SchemeKind kind) { return kind != SchemeKind::loop; }

/// The ordered 1-ring of a vertex at some level: neighbours counter-clockwise
/// (seen from the side the triangles' winding makes "outside").
/// - closed: the fan goes all the way round (interior manifold vertex);
/// - open (closed == false, regular == true): one fan from nbrs.front() to
///   nbrs.back(), both joined to the centre by boundary edges;
/// - regular == false: several fans or non-manifold edges; the schemes keep
///   such a vertex fixed (a corner), see docs/schemes.md.
struct VertexRing {
    Vec3 center;
    std::vector<Vec3> nbrs;
    bool closed = false;
    bool regular = true;
};

/// Loop's limit point of a vertex from its ring at any level (the limit mask
/// chi = 8a / (n (8a + 3)) per neighbour; boundary (q_first + 4p + q_last)/6;
/// corners stay). The same point whichever level's ring it is computed from.
Vec3 loop_limit_point(const VertexRing& ring);

/// Loop's vertex rule: interior (1-a)p + a/n sum(q), a = (40 - (3 + 2cos(2pi/n))^2)/64;
/// boundary (q_first + 6p + q_last)/8; corners (irregular) stay.
Vec3 loop_vertex_point(const VertexRing& ring);

/// Everything an edge rule may read about edge (a, b) at the coarser level.
struct EdgeStencil {
    Vec3 a{0.0};
    Vec3 b{0.0};
    Vec3 normal_a{0.0};  ///< Gouraud normals (normal scheme only)
    Vec3 normal_b{0.0};
    /// True if the edge has exactly two triangles; then c and d are their
    /// third vertices (c in the triangle that runs a -> b).
    bool interior = false;
    Vec3 c{0.0};
    Vec3 d{0.0};
    /// Rings of the endpoints (Butterfly's wings and extraordinary stencils);
    /// b is ring_a->nbrs[index_b_in_a] and a is ring_b->nbrs[index_a_in_b].
    const VertexRing* ring_a = nullptr;
    const VertexRing* ring_b = nullptr;
    std::size_t index_b_in_a = 0;
    std::size_t index_a_in_b = 0;
};

/// One scheme's new point on an edge (dispatches on kind).
Vec3 edge_point(SchemeKind kind, const EdgeStencil& s);
/// One scheme's new position of an old vertex (dispatches on kind).
Vec3 vertex_point(SchemeKind kind, const VertexRing& ring);

/// The new point on edge (a, b) for each scheme.
Vec3 normal_edge_point(const Vec3& a, const Vec3& b, const Vec3& na, const Vec3& nb);
Vec3 loop_edge_point(const EdgeStencil& s);
Vec3 butterfly_edge_point(const EdgeStencil& s);

/// Angle-weighted face normal contribution of triangle (p, q, r) at corner p:
/// the unit face normal times the corner angle at p (Thuermer & Wuethrich 1998).
/// Zero for degenerate triangles, never NaN.
Vec3 angle_weighted_normal(const Vec3& p, const Vec3& q, const Vec3& r);

/// Normalises a sum of angle-weighted normals; a zero sum gives (0, 0, 0).
Vec3 finish_normal(const Vec3& sum);

}  // namespace subdivtrace
