#pragma once
// Each scheme as one small value: its rules, and what they read and do, as
// properties the level code (patch.cpp, uniform.cpp, patch_records.cpp,
// node_shell.cpp, root_records.cpp, tile.cpp) tests instead of naming
// schemes. The stencils themselves are in scheme.cpp, their sources in
// scheme.h and docs/schemes.md.

#include <cstddef>

#include "subdivtrace/scheme.h"

namespace subdivtrace::detail {

/// An edge both of whose endpoints have whole rings of valence 6 in one
/// sector (closed, manifold, no crease through them), the case of almost
/// every edge below level 0: its stencil is fixed points found by index
/// (ring position +-2 from the other endpoint), with nothing to copy or test.
struct RegularEdge {
    Vec3 a, b;  ///< endpoints
    Vec3 c, d;  ///< third vertices of the triangles a -> b (c) and b -> a (d)
    /// The wings: across edge (b, c) from a, (a, c) from b, (b, d) from a and
    /// (a, d) from b, as ring_b[i_a - 2], ring_a[i_b + 2], ring_b[i_a + 2] and
    /// ring_a[i_b - 2] (EdgeStencil's rings, i_x the index of x in the other's).
    Vec3 w_bc, w_ac, w_bd, w_ad;
};

struct SchemeRules {
    SchemeKind kind;
    /// As scene files and the command line name it.
    const char* name;
    /// The vertex rule: an old vertex's next position from its ordered ring;
    /// null where old vertices keep their positions (interpolating schemes).
    Vec3 (*vertex_rule)(const VertexRing&);
    /// The edge rule: an edge's new point from its stencil.
    Vec3 (*edge_rule)(const EdgeStencil&);
    /// The same rule off boundaries and creases where it reads nothing but
    /// the endpoints and their normals in the edge's sector (the normal
    /// scheme), so a patch need not fill a whole stencil; else null.
    Vec3 (*smooth_edge_rule)(const Vec3& a, const Vec3& b, const Vec3& normal_a, const Vec3& normal_b);
    /// The edge rule on a RegularEdge, with the bits edge_rule gives it, for
    /// schemes whose edge rule reads rings (Butterfly), so levels need not
    /// fill them; null where edge_rule reads no rings (it is cheap as it is).
    Vec3 (*regular_edge_rule)(const RegularEdge&);
    /// Where a vertex is drawn, from its birth-level ring (its limit point);
    /// null where the level's own position is drawn (it lies on the limit).
    Vec3 (*drawn_point)(const VertexRing&);
    /// The limit normal at a vertex from its closed regular ring of n points,
    /// counter-clockwise (Loop's tangent masks): a leaf shades with it
    /// instead of the next level's Gouraud normal. Null where the scheme has
    /// no such mask.
    Vec3 (*limit_normal)(const Vec3* ring, std::size_t n);
    /// The edge rule reads both endpoints' normals in the edge's sector, so
    /// a level has them before its edge points (the normal scheme).
    bool edge_rule_reads_normals;
    /// The edge rule reads the third vertices of the edge's two triangles.
    bool edge_rule_reads_opposites;
    /// The edge rule reads both endpoints' ordered rings, cut to the edge's
    /// sector at a crease (Butterfly's wings and extraordinary stencils).
    bool edge_rule_reads_rings;
    /// Every rule is a convex combination of 1-ring points (Loop), so a
    /// node's descendants lie in the hull of its corners' rings one level
    /// down; otherwise the shells bound them by the displacement series.
    bool convex_rules;
    /// The mesh's own normals are this scheme's at level 0 (the normal scheme).
    bool takes_given_normals;
    /// How far the limit surface lies off an edge's chord, per unit of the
    /// next level's edge point's offset from the edge's midpoint along the
    /// surface normal (the error rule's deviation, Patch): 1 where edge
    /// points lie on the surface (interpolating schemes), 2 for Loop, whose
    /// regular edge point is off by (c + d - a - b) / 8, half a quadratic's
    /// sagitta (on blob5k the limit points' offsets are 1.96x the control
    /// points', median over the level-2 edges).
    double sagitta_per_normal_offset;

    bool moves_old_vertices() const { return vertex_rule != nullptr; }
    bool draws_limit_points() const { return drawn_point != nullptr; }
    /// Whether a level orders each vertex's ring (for the vertex rule, the
    /// edge rule or the limit normals).
    bool reads_ordered_rings() const {
        return moves_old_vertices() || edge_rule_reads_rings || limit_normal != nullptr;
    }
};

/// The rules of a scheme (static storage).
const SchemeRules& rules_of(SchemeKind kind);

}  // namespace subdivtrace::detail
