#pragma once
/// \file scheme.h
/// The subdivision operator F (DESIGN.md section 3): which scheme, and the
/// stencils that compute one level's new positions from the previous level.

#include <cstddef>
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
    /// Curve edges at the vertex: boundary edges (one triangle) and creases
    /// (docs/schemes.md, "Creases and boundaries"). With exactly two the vertex
    /// lies on a curve and `curve` holds their other ends; with three or more
    /// it is a corner and stays.
    int curve_count = 0;
    Vec3 curve[2] = {Vec3(0.0), Vec3(0.0)};
};

/// Loop's limit point of a vertex from its ring at any level (the limit mask
/// chi = 8a / (n (8a + 3)) per neighbour; on a curve (q_0 + 4p + q_1)/6 with
/// the curve neighbours; corners stay). The same point whichever level's ring
/// it is computed from.
Vec3 loop_limit_point(const VertexRing& ring);

/// Loop's limit normal at a vertex from its closed ring of n points in
/// counter-clockwise order (Halstead, Kass and DeRose 1993: the tangent masks
/// cos(2 pi k / n) and sin(2 pi k / n), centre weight 0); zero where the
/// tangents are parallel.
Vec3 loop_limit_normal(const Vec3* ring, std::size_t n);

/// Loop's vertex rule: interior (1-a)p + a/n sum(q), a = (40 - (3 + 2cos(2pi/n))^2)/64;
/// on a curve (boundary or crease) (q_0 + 6p + q_1)/8 with the curve
/// neighbours; corners (irregular, or three or more curve edges) stay.
Vec3 loop_vertex_point(const VertexRing& ring);

/// Everything an edge rule may read about edge (a, b) at the coarser level.
struct EdgeStencil {
    Vec3 a{0.0};
    Vec3 b{0.0};
    /// Normal scheme only: the endpoints' normals in the sector that holds
    /// the edge. On a curve edge, the normal at an endpoint that ends the
    /// curve inside a smooth sector (a dart), else zero.
    Vec3 normal_a{0.0};
    Vec3 normal_b{0.0};
    /// A boundary or crease edge: its point depends only on the curve through
    /// it, so both sides of a crease (or two meshes sharing a boundary) get
    /// the same point. a_far / b_far: the curve's next vertex beyond a / b,
    /// when that endpoint has exactly two curve edges.
    bool curve = false;
    bool has_a_far = false;
    bool has_b_far = false;
    Vec3 a_far{0.0};
    Vec3 b_far{0.0};
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

/// The new point on edge (a, b) for each scheme.
Vec3 normal_edge_point(const Vec3& a, const Vec3& b, const Vec3& na, const Vec3& nb);
/// The normal scheme's curve rule: the midpoint of the cubic whose end
/// tangents are the edge projected on the curve's tangent at each end (the
/// direction between the end's two curve neighbours), or on the tangent plane
/// of a dart's normal, or the chord at a corner.
Vec3 normal_curve_edge_point(const EdgeStencil& s);
Vec3 loop_edge_point(const EdgeStencil& s);
Vec3 butterfly_edge_point(const EdgeStencil& s);

/// Angle-weighted face normal contribution of triangle (p, q, r) at corner p:
/// the unit face normal times the corner angle at p (Thuermer & Wuethrich 1998).
/// Zero for degenerate triangles, never NaN.
Vec3 angle_weighted_normal(const Vec3& p, const Vec3& q, const Vec3& r);
/// angle_weighted_normal(centre, from[k], to[k]) for each k < count, into
/// out[k], with the same bits: the triangles around one vertex side by side,
/// so their square roots and divisions (most of a normal's cost) run
/// vectorised.
void angle_weighted_fan(const Vec3& centre, const Vec3* from, const Vec3* to, std::size_t count, Vec3* out);
/// The angle-weighted normals at all three corners of each of `count`
/// triangles (indices into `positions`), into out[3 t + c]: a triangle's
/// three share one cross product and its third angle is pi minus the other
/// two. Eight triangles at a time, so the angles run vectorised.
void angle_weighted_corners(const Vec3* positions, const Triangle* triangles, std::size_t count,
                            Vec3* out);

/// Normalises a sum of angle-weighted normals; a zero sum gives (0, 0, 0).
Vec3 finish_normal(const Vec3& sum);

}  // namespace subdivtrace
