#pragma once
// A patch: the few triangles of one uniform level that a tile's values depend
// on (DESIGN.md section 5, "tiles"). A tile rooted at level L is computed by
// taking the base triangles around its level-0 ancestor and subdividing them
// level by level with array kernels, keeping at each level only the target
// region (the ancestor, then the tile's own triangles) plus a border two
// vertex rings wide: every stencil reads at most the 1-rings of an edge's
// endpoints, so such a border stays self-sufficient under subdivision and the
// region's values are those of global uniform subdivision.
//
// Both sides of every edge compute from bit-identical data: each value is
// evaluated from canonically ordered inputs (rings in the order of their
// triangles, edges oriented from the smaller key), so every patch that holds a
// vertex with its whole stencil gets the same bits, and values whose stencil
// is cut off by the border are marked invalid and never read.
//
// A patch's triangles are in the hierarchy's order: base faces ascending,
// each triangle's children together in child order (base_patch sorts;
// subdividing, copying and trimming keep the order). The incident lists,
// built in triangle order, are then already canonical: no ring is sorted.

#include <array>
#include <cstdint>
#include <vector>

#include "base_topology.h"
#include "node_address.h"
#include "ring_order.h"
#include "scheme_rules.h"

namespace subdivtrace::detail {

/// One flag per triangle, vertex or point (regions, bands, needed points):
/// bytes, as std::vector<bool>'s packed bits cost a few instructions per
/// read and write in the kernels' loops.
using Flags = std::vector<std::uint8_t>;

/// Reports a value read outside a patch's complete region: the border
/// arithmetic above guarantees every value a tile reads, so this is a bug,
/// never bad input (throws std::logic_error).
[[noreturn]] void stencil_cut(const char* what);

/// What a patch keeps of a vertex between levels.
struct PatchVertex {
    VertexKey key;
    Vec3 position{0.0};
    bool has_position = false;
    bool has_draw = false;  ///< where leaves draw it is known (Patch::drawn_at)
    /// Triangles around it at its level in the whole mesh (its ring is whole
    /// in a patch that holds this many).
    std::uint16_t true_ring = 0;
};

/// What finish() and the next level's positions derive of a vertex at one level. Its normals
/// are per corner (Patch::corner_normal): one per sector between creases.
struct VertexDerived {
    /// Largest distance of an edge point of the next level from its edge's
    /// midpoint, over the edges at this vertex (interpolating schemes' shells).
    double displacement = 0.0;
    /// The same offsets along the surface normal (scaled by the scheme's
    /// sagitta_per_normal_offset): how far the surface bends off the chords
    /// at this vertex, what the error rule reads (NodeRecord::displacement).
    /// The offsets' tangential part only slides points along the surface:
    /// on blob5k it is 10-12x the normal part for Loop and Butterfly, whose
    /// parametrisation relaxes level by level, and refining by it cut them
    /// two levels finer than the normal scheme.
    double deviation = 0.0;
    bool has_ring = false;  ///< every incident triangle of the level is in the patch
    bool has_normal = false;
    bool has_displacement = false;
    /// Curve (boundary or crease) edges at the vertex, and with exactly two,
    /// their other ends in key order (scheme.h, VertexRing::curve).
    std::uint8_t curve_count = 0;
    bool single_sector = true;  ///< no crease splits its triangles
    std::uint32_t curve[2] = {0, 0};
};

struct PatchTriangle {
    NodeId id;
    std::array<std::uint32_t, 3> v;  ///< local vertex indices, in node_corner_grid order
};

/// An edge of the patch with its canonical orientation (key(a) < key(b)).
struct PatchEdge {
    std::uint32_t a = 0;
    std::uint32_t b = 0;
    std::uint32_t point = 0;  ///< index of its edge point in the next level's patch
    bool valid = false;       ///< both endpoints have complete rings
    bool curve = false;       ///< a boundary (one triangle) or a crease
    bool crease = false;      ///< on a base edge that is a crease (creases.h)
    std::uint32_t slot_count = 0;  ///< triangles on the edge
    std::uint32_t slot[2] = {0, 0};  ///< the first two, as corner slots 3t + e
};

class Patch {
public:
    int level = 0;
    std::vector<PatchVertex> verts;
    /// Loop only, per vertex: where leaves draw it, its limit point, computed
    /// at its birth level and carried down. Empty for the interpolating
    /// schemes, which draw at the position (a copy in every vertex was a
    /// third of a vertex's bytes).
    std::vector<Vec3> draw;
    std::vector<PatchTriangle> tris;
    std::vector<VertexDerived> derived;  ///< per vertex, after finish()
    /// Normal at each corner slot 3t + c, after finish() (where the corner's
    /// vertex has_normal): the scheme's normal of the vertex in the sector of
    /// triangle t.
    std::vector<Vec3> corner_normal;
    /// Sector of each corner slot among its vertex's sectors (0 where a
    /// vertex has one), after finish(). A whole ring has fewer than 65535
    /// triangles (true_ring saturates there), so 16 bits hold every label.
    std::vector<std::uint16_t> corner_sector;

    /// Ordered (canonical) ring of vertex v: valid after finish() for
    /// vertices with has_ring.
    struct Ring {
        std::uint32_t offset = 0;
        std::uint32_t count = 0;
        bool closed = false;
        bool regular = false;
    };
    std::vector<Ring> rings;
    std::vector<std::uint32_t> ring_nbrs;
    /// Per ring_nbrs entry: its edge is a curve edge (filled for vertices
    /// that creases split into sectors; Butterfly reads it).
    std::vector<std::uint8_t> ring_curve;

    /// Incident corner slots (3t + c) of each vertex, CSR (built by finish()
    /// or build_incidence()).
    std::vector<std::uint32_t> incident_offsets;
    std::vector<std::uint32_t> incident_slots;

    /// Edges and, per triangle corner slot 3t+e, the edge from corner e to e+1.
    std::vector<PatchEdge> edges;
    std::vector<std::uint32_t> tri_edges;
    /// Per corner slot 3t+e, a name of the edge from corner e to e+1 that
    /// every triangle on it shares: (number << 1) | crease bit. Derived from
    /// the parent's edges by each subdivision (a half of parent edge p is
    /// number 2p or 2p + 1, an inner edge of parent triangle t 2E + 3t + k)
    /// and carried by copies, so finish() finds the edges by direct
    /// indexing; a patch without names (a base patch) is named by vertex
    /// pairs first (name_edges).
    std::vector<std::uint32_t> edge_names;

    /// Rings, completeness, edges, curves, normals and (Loop) draw positions
    /// of vertices born at this level.
    void finish(const BaseTopology& topo, const SchemeRules& scheme);
    /// The incident lists alone (finish() builds them first): what
    /// band_around() reads, for a patch cut many times before it is finished.
    void build_incidence();
    bool has_incidence() const { return incident_offsets.size() == verts.size() + 1; }

    /// The triangles with a vertex at most one ring from `in_region`
    /// triangles' vertices (so those vertices' rings are whole).
    template <class Pred>
    Flags band(Pred in_region) const;
    /// Keeps band(in_region), drops the rest.
    template <class Pred>
    void trim(Pred in_region) {
        trim_to(band(in_region));
    }
    /// A new patch holding only `src`'s triangles flagged in `keep`.
    static Patch copy_of(const Patch& src, const Flags& keep);
    /// The same for the triangles listed in `kept` (ascending): its cost
    /// follows the copy's size, not `src`'s.
    static Patch copy_of(const Patch& src, const std::vector<std::uint32_t>& kept);
    /// band() of the triangles listed in `region`, as ascending indices,
    /// found through the incident lists (has_incidence()): its cost follows
    /// the band's size, where band() scans the whole patch.
    std::vector<std::uint32_t> band_around(const std::vector<std::uint32_t>& region) const;

    /// The per-vertex displacement of the next level, and the next level's
    /// vertex positions alone (no triangles, no keys; index v for old vertex
    /// v, vertices + e for edge e's point): what records and shells read.
    /// With `needed` (indexed the same way), only those points are computed,
    /// and a vertex's displacement is then whole only where all its edges'
    /// points are needed. Values whose stencil is incomplete are marked
    /// invalid. Call after finish().
    /// Writes them into `next` (only its vertices and draw positions; it
    /// may be a reused scratch patch).
    void next_positions(const BaseTopology& topo, const SchemeRules& scheme, const Flags* needed,
                        Patch& next);
    /// What next_positions() needs for the records of the triangles flagged
    /// in `region`: their vertices (moved by Loop) and every edge point at them.
    Flags points_around(const Flags& region) const;

    /// next_positions() a few triangles at a time, for a patch whose next
    /// level's points are asked for by several tiles in turn (the level
    /// below a parent tile, shared by its child tiles): start_positions()
    /// once, on `next` sized to verts.size() + edges.size(); then each
    /// add_points_around() computes the points_around() the triangles listed
    /// in `region` that `done` (one flag per point) does not flag yet, and
    /// flags them. The same bits as one next_positions() of all of them.
    void start_positions(const SchemeRules& scheme, Patch& next);
    void add_points_around(const BaseTopology& topo, const SchemeRules& scheme,
                           const std::vector<std::uint32_t>& region, Patch& next, Flags& done);

    /// The per-vertex displacement of the next level, then the next level's
    /// patch (every triangle split 1-to-4), with only the points of its
    /// triangles in band(in_region) computed (the rest of the border is cut
    /// next); `kept` receives that band, for keep_only() once the caller is
    /// done with the untrimmed indices. Call after finish().
    template <class Pred>
    Patch subdivide_band(const BaseTopology& topo, const SchemeRules& scheme, Pred in_region,
                         Flags& kept) {
        Patch next = subdivide_topology(topo, parents_of_band(in_region));
        kept = next.band(in_region);
        Flags needed(next.verts.size(), false);
        for (std::size_t t = 0; t < next.tris.size(); ++t)
            if (kept[t])
                for (std::uint32_t v : next.tris[t].v) needed[v] = true;
        compute_positions(topo, scheme, next, &needed);
        return next;
    }
    /// Keeps the triangles flagged in `keep`, drops the rest.
    void keep_only(const Flags& keep) { trim_to(keep); }
    /// The triangles whose children can lie in the next level's
    /// band(in_region) (subdivide_band splits only them): those with a
    /// corner at a triangle with a child in the region. The band's vertices
    /// are the region's children's corners and their ring neighbours; each
    /// lies at such a corner or on an edge from one, and so does every
    /// triangle at one of them. About half of a band two rings wide.
    template <class Pred>
    Flags parents_of_band(Pred in_region) const;

    void fill_vertex_ring(std::uint32_t v, VertexRing& ring) const;
    /// v's ordered ring as indices (ring_order.h; after finish(), where v has_ring).
    RingIndices ring_indices(std::uint32_t v) const {
        const Ring& r = rings[v];
        return {ring_nbrs.data() + r.offset, r.count, r.closed, r.regular, derived[v].curve_count, derived[v].curve};
    }
    /// Whether v's ring is whole, manifold, of valence 6 and in one sector:
    /// an endpoint of a RegularEdge (after finish()).
    bool regular_six(std::uint32_t v) const {
        return derived[v].has_ring && detail::regular_six(ring_indices(v), derived[v].single_sector);
    }

    /// Where leaves draw vertex v (valid where verts[v].has_draw).
    const Vec3& drawn_at(std::uint32_t v) const { return draw.empty() ? verts[v].position : draw[v]; }

    /// Computes v's corner normals (corner_normal, has_normal) if it has a
    /// whole ring and they are not computed yet: finish() leaves them to
    /// the first reader, as most of a patch's border never needs them.
    void ensure_normal(const BaseTopology& topo, const SchemeRules& scheme, std::uint32_t v) {
        // Inline: most calls find the normals there already.
        if (!derived[v].has_normal && derived[v].has_ring) compute_normal(topo, scheme, v);
    }

    /// Gives v the corner normals normal_of(slot), for each corner slot 3t + c
    /// at v, instead of computing them (if it has a whole ring and none yet):
    /// for values known to equal what ensure_normal would compute.
    template <class NormalOf>
    void adopt_normal(std::uint32_t v, NormalOf normal_of) {
        VertexDerived& dv = derived[v];
        if (dv.has_normal || !dv.has_ring) return;
        for (std::uint32_t k = incident_offsets[v]; k < incident_offsets[v + 1]; ++k)
            corner_normal[incident_slots[k]] = normal_of(incident_slots[k]);
        dv.has_normal = true;
    }

    /// Frees rings and edges alone: this thread keeps their blocks for the
    /// next patch it finishes (a patch about to be destroyed gives them back).
    void give_back_derived();
    std::size_t owned_bytes() const;

private:
    /// Names the edges (edge_names) by their vertex pairs: for base patches.
    void name_edges(const BaseTopology& topo);
    void build_edges();
    void compute_normal(const BaseTopology& topo, const SchemeRules& scheme, std::uint32_t v);
    /// The next level's triangles (every one of `split` split 1-to-4, in
    /// order) and its vertices' keys: points for every edge, keyed where a
    /// split triangle has the edge.
    Patch subdivide_topology(const BaseTopology& topo, const Flags& split) const;
    void compute_positions(const BaseTopology& topo, const SchemeRules& scheme, Patch& next,
                           const Flags* needed);
    /// Next-level point `point` (old vertex v, or vertices + e for edge e),
    /// where its stencil is whole (after start_positions).
    void compute_point(const BaseTopology& topo, const SchemeRules& scheme, Patch& next,
                       std::uint32_t point);
    void finish_vertex(const BaseTopology& topo, const SchemeRules& scheme, std::uint32_t v);
    Vec3 edge_point(const SchemeRules& scheme, const PatchEdge& e) const;
    void fill_curve_end(std::uint32_t v, std::uint32_t other, bool& has_far, Vec3& far,
                        Vec3& normal) const;
    void trim_to(const Flags& keep);
};

/// order_ring of vertex v's incident pairs where they form one manifold fan
/// (after finish()'s edges), found through the edges instead of by searching
/// the pairs: from the first pair, or the one whose first edge is a
/// boundary, each next triangle is the other one on the edge the last one
/// ends at. The same neighbours in the same order, closed or open, as
/// order_ring gives that fan (each step joins the pairs by their vertices
/// too). False where it cannot tell: more than one boundary, an edge with
/// three triangles, a neighbour turned the other way, a neighbour met twice;
/// then order_ring decides. finish() orders Loop's and Butterfly's rings so,
/// where order_ring's searches were a tenth of Loop's close-up.
bool ring_by_edges(const Patch& p, std::uint32_t v, OrderedRing<std::uint32_t>& out);

/// The level-0 patch around the `count` base triangles at `region` (not
/// finished): them, and every base triangle with a vertex at most one ring
/// from theirs, so their corners and neighbours have whole rings.
/// Stamps that let base_patch deduplicate a large region's vertices and
/// faces in linear time; reused across calls (sized to the mesh once).
struct BasePatchScratch {
    std::vector<std::uint32_t> vertex_stamp;
    std::vector<std::uint32_t> face_stamp;
    std::vector<std::uint32_t> local_index;
    std::uint32_t generation = 0;
};
Patch base_patch(const BaseTopology& topo, const std::uint32_t* region, std::size_t count,
                 BasePatchScratch* scratch = nullptr);

template <class Pred>
Flags Patch::band(Pred in_region) const {
    // Distance 0: vertices of region triangles; 1: their ring neighbours.
    std::vector<std::uint8_t> dist(verts.size(), 2);
    for (const PatchTriangle& t : tris)
        if (in_region(t.id))
            for (std::uint32_t v : t.v) dist[v] = 0;
    for (const PatchTriangle& t : tris) {
        if (dist[t.v[0]] == 0 || dist[t.v[1]] == 0 || dist[t.v[2]] == 0)
            for (std::uint32_t v : t.v) dist[v] = std::min<std::uint8_t>(dist[v], 1);
    }
    Flags keep(tris.size());
    for (std::size_t t = 0; t < tris.size(); ++t) {
        const auto& v = tris[t].v;
        keep[t] = dist[v[0]] <= 1 || dist[v[1]] <= 1 || dist[v[2]] <= 1;
    }
    return keep;
}

template <class Pred>
Flags Patch::parents_of_band(Pred in_region) const {
    thread_local Flags near;
    near.assign(verts.size(), 0);
    for (const PatchTriangle& t : tris) {
        bool region = false;
        for (int c = 0; c < 4 && !region; ++c) region = in_region(child_of(t.id, c));
        if (region)
            for (std::uint32_t v : t.v) near[v] = 1;
    }
    Flags split(tris.size());
    for (std::size_t t = 0; t < tris.size(); ++t) {
        const auto& v = tris[t].v;
        split[t] = near[v[0]] | near[v[1]] | near[v[2]];
    }
    return split;
}

}  // namespace subdivtrace::detail
