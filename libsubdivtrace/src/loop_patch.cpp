#include "loop_patch.h"

#include <initializer_list>
#include <utility>

#include "subdivtrace/scheme.h"

namespace subdivtrace::detail {

namespace {

/// Weights (/24) of the 12 control points (LoopPatchPoints' order) in each
/// Bezier point, derived exactly: two levels of Loop's regular rules applied
/// to each control point's indicator on the lattice, its limit values at the
/// 15 level-2 points of ABC (the domain points (b, c) / 4), then
/// interpolation by the quartic Bernstein basis. Each row sums to 24; the
/// corner rows are Loop's limit mask (1/2, and 1/12 per neighbour).
constexpr std::uint8_t k_weights[15][12] = {
    {12, 2, 2, 2, 2, 2, 2, 0, 0, 0, 0, 0},   // (4, 0, 0)
    {12, 3, 4, 1, 0, 1, 3, 0, 0, 0, 0, 0},   // (3, 0, 1)
    {8, 4, 8, 0, 0, 0, 4, 0, 0, 0, 0, 0},    // (2, 0, 2)
    {4, 3, 12, 0, 0, 0, 3, 0, 1, 0, 0, 1},   // (1, 0, 3)
    {2, 2, 12, 0, 0, 0, 2, 0, 2, 0, 2, 2},   // (0, 0, 4)
    {12, 4, 3, 0, 1, 3, 1, 0, 0, 0, 0, 0},   // (3, 1, 0)
    {10, 6, 6, 0, 0, 1, 1, 0, 0, 0, 0, 0},   // (2, 1, 1)
    {6, 6, 10, 0, 0, 0, 1, 0, 1, 0, 0, 0},   // (1, 1, 2)
    {3, 4, 12, 0, 0, 0, 1, 0, 3, 0, 1, 0},   // (0, 1, 3)
    {8, 8, 4, 0, 0, 4, 0, 0, 0, 0, 0, 0},    // (2, 2, 0)
    {6, 10, 6, 0, 0, 1, 0, 0, 1, 0, 0, 0},   // (1, 2, 1)
    {4, 8, 8, 0, 0, 0, 0, 0, 4, 0, 0, 0},    // (0, 2, 2)
    {4, 12, 3, 0, 0, 3, 0, 0, 1, 1, 0, 0},   // (1, 3, 0)
    {3, 12, 4, 0, 0, 1, 0, 1, 3, 0, 0, 0},   // (0, 3, 1)
    {2, 12, 2, 0, 0, 2, 0, 2, 2, 2, 0, 0},   // (0, 4, 0)
};

/// Where vertex `from` lies in ring r (of r.count, at least 3), and the
/// direction `step` (1, or r.count - 1: one step back modulo the count) in
/// which `towards` follows it `offset` places on; false unless exactly one
/// direction fits.
bool locate(const RingIndices& r, std::uint32_t from, std::uint32_t towards, int offset, int& at, int& step) {
    const int n = static_cast<int>(r.count);
    at = -1;
    for (int k = 0; k < n; ++k)
        if (r.nbrs[k] == from) at = k;
    if (at < 0) return false;
    const bool forward = r.nbrs[(at + offset) % n] == towards;
    const bool backward = r.nbrs[(at + n - offset) % n] == towards;
    if (forward == backward) return false;
    step = forward ? 1 : n - 1;
    return true;
}

/// The edge between patch vertices v and w, or -1 (found among v's triangles).
int edge_between(const Patch& p, std::uint32_t v, std::uint32_t w) {
    for (std::uint32_t k = p.incident_offsets[v]; k < p.incident_offsets[v + 1]; ++k) {
        const std::uint32_t slot = p.incident_slots[k];
        const std::uint32_t first = slot - slot % 3;
        for (std::uint32_t s : {slot, first + (slot % 3 + 2) % 3}) {
            const PatchEdge& e = p.edges[p.tri_edges[s]];
            if ((e.a == v && e.b == w) || (e.a == w && e.b == v)) return static_cast<int>(p.tri_edges[s]);
        }
    }
    return -1;
}

}  // namespace

const std::array<std::array<std::uint8_t, 3>, 15> k_loop_bezier_index = {{
    {4, 0, 0}, {3, 0, 1}, {2, 0, 2}, {1, 0, 3}, {0, 0, 4}, {3, 1, 0}, {2, 1, 1}, {1, 1, 2},
    {0, 1, 3}, {2, 2, 0}, {1, 2, 1}, {0, 2, 2}, {1, 3, 0}, {0, 3, 1}, {0, 4, 0},
}};

namespace {

/// k_weights without its zeros: each row's non-zero weights and their
/// points, in ascending order of the point (a net is summed in that order,
/// as from the full rows, but without a test per weight: nets are most of
/// the cost of Loop's shells).
struct SparseRow {
    int count = 0;
    std::uint8_t point[12] = {};
    double weight[12] = {};
};
constexpr std::array<SparseRow, 15> sparse_rows() {
    std::array<SparseRow, 15> rows{};
    for (int q = 0; q < 15; ++q)
        for (int k = 0; k < 12; ++k)
            if (k_weights[q][k] != 0) {
                SparseRow& r = rows[q];
                r.point[r.count] = static_cast<std::uint8_t>(k);
                r.weight[r.count] = k_weights[q][k];
                ++r.count;
            }
    return rows;
}
constexpr std::array<SparseRow, 15> k_sparse_rows = sparse_rows();

}  // namespace

LoopBezierNet loop_bezier_net(const LoopPatchPoints& points) {
    LoopBezierNet net;
    for (int q = 0; q < 15; ++q) {
        const SparseRow& row = k_sparse_rows[q];
        Vec3 sum(0.0);
        for (int i = 0; i < row.count; ++i) sum += row.weight[i] * points[row.point[i]];
        net[q] = sum / 24.0;
    }
    return net;
}

bool loop_patch_points(const Patch& p, std::uint32_t t, LoopPatchPoints& out) {
    const auto& v = p.tris[t].v;
    for (std::uint32_t c : v)
        if (!p.regular_six(c) || p.derived[c].curve_count != 0) return false;
    const RingIndices ra = p.ring_indices(v[0]), rb = p.ring_indices(v[1]), rc = p.ring_indices(v[2]);
    // Counter-clockwise on the lattice: A's ring from B is B, C, (-1, 1),
    // (-1, 0), (0, -1), (1, -1); B's from A is A, (1, -1), (2, -1), (2, 0),
    // (1, 1), C; C's from A is A, B, (1, 1), (0, 2), (-1, 2), (-1, 1). Each
    // ring's direction is found from the triangle's own corners, so a mesh
    // oriented either way (or not at all) maps alike.
    int ia, sa, ib, sb, ic, sc;
    if (!locate(ra, v[1], v[2], 1, ia, sa) || !locate(rb, v[0], v[2], 5, ib, sb) ||
        !locate(rc, v[0], v[1], 1, ic, sc))
        return false;
    const auto a = [&](int k) { return ra.nbrs[(ia + k * sa) % 6]; };
    const auto b = [&](int k) { return rb.nbrs[(ib + k * sb) % 6]; };
    const auto c = [&](int k) { return rc.nbrs[(ic + k * sc) % 6]; };
    // The three points two rings share must be the same vertices.
    if (a(5) != b(1) || a(2) != c(5) || b(4) != c(2)) return false;
    const std::uint32_t index[12] = {v[0], v[1], v[2], a(3), a(4), a(5), a(2), b(3), b(4), b(2), c(3), c(4)};
    for (int k = 0; k < 12; ++k) out[k] = p.verts[index[k]].position;
    return true;
}

void grow_by_corner_ring(const Patch& p, const Patch& next, std::uint32_t t, int c, Shell& shell) {
    // Across a crease nothing is read (its rules use the crease and one
    // side), so only the corner's sector that holds t counts.
    const std::uint32_t v = p.tris[t].v[c];
    const bool one_sector = p.derived[v].single_sector;
    const std::uint16_t sector = p.corner_sector[3 * t + c];
    shell.grow_both(next.verts[v].position);
    for (std::uint32_t k = p.incident_offsets[v]; k < p.incident_offsets[v + 1]; ++k) {
        const std::uint32_t slot = p.incident_slots[k];
        if (!one_sector && p.corner_sector[slot] != sector) continue;
        const std::uint32_t first = slot - slot % 3;
        for (std::uint32_t e : {slot, first + (slot % 3 + 2) % 3}) {
            const PatchEdge& edge = p.edges[p.tri_edges[e]];
            if (!edge.valid) stencil_cut("an edge point next to a corner");
            shell.grow_both(next.verts[edge.point].position);
        }
    }
}

bool loop_children_points(const Patch& p, const Patch& next, std::uint32_t t, LoopChildren& out) {
    // Names on the lattice of loop_patch.h, one level down (coordinates
    // doubled): t is A = (0, 0), B = (2, 0), C = (0, 2); D, E and F lie
    // across AB, BC and CA; mXY is the point of edge XY, X1 the new X.
    const auto& v = p.tris[t].v;
    std::uint32_t across[3];       // D, E, F
    std::uint32_t side[3][2];      // across edge (X, Y): edges X-third and Y-third
    for (int k = 0; k < 3; ++k) {
        const PatchEdge& e = p.edges[p.tri_edges[3 * t + k]];
        if (e.curve || e.slot_count != 2 || !e.valid) return false;
        const std::uint32_t other = e.slot[0] / 3 == t ? e.slot[1] : e.slot[0];
        if (other / 3 == t) return false;
        const PatchTriangle& u = p.tris[other / 3];
        const std::uint32_t c = other % 3, first = other - c;
        across[k] = u.v[(c + 2) % 3];
        const std::uint32_t x = v[k], y = v[(k + 1) % 3];
        int to_x = -1, to_y = -1;
        for (std::uint32_t s : {first + (c + 1) % 3, first + (c + 2) % 3}) {
            const PatchEdge& f = p.edges[p.tri_edges[s]];
            const std::uint32_t end = f.a == across[k] ? f.b : f.a;
            if (end == x) to_x = static_cast<int>(p.tri_edges[s]);
            if (end == y) to_y = static_cast<int>(p.tri_edges[s]);
        }
        if (to_x < 0 || to_y < 0) return false;
        side[k][0] = static_cast<std::uint32_t>(to_x);
        side[k][1] = static_cast<std::uint32_t>(to_y);
    }
    bool complete = true;
    const auto vertex_point = [&](std::uint32_t x) {
        complete = complete && next.verts[x].has_position;
        return next.verts[x].position;
    };
    const auto edge_point = [&](std::uint32_t e) {
        const std::uint32_t x = p.edges[e].point;
        complete = complete && p.edges[e].valid && next.verts[x].has_position;
        return next.verts[x].position;
    };
    LoopChildren& o = out;
    for (int k = 0; k < 3; ++k) o.across[k] = across[k];
    o.A1 = vertex_point(v[0]);
    o.B1 = vertex_point(v[1]);
    o.C1 = vertex_point(v[2]);
    o.mAB = edge_point(p.tri_edges[3 * t]);
    o.mBC = edge_point(p.tri_edges[3 * t + 1]);
    o.mCA = edge_point(p.tri_edges[3 * t + 2]);
    o.mAD = edge_point(side[0][0]);
    o.mBD = edge_point(side[0][1]);
    o.mBE = edge_point(side[1][0]);
    o.mCE = edge_point(side[1][1]);
    o.mCF = edge_point(side[2][0]);
    o.mAF = edge_point(side[2][1]);
    if (!complete) return false;

    // A corner's child is regular where the corner is; its two farther
    // lattice points are the corner's ring neighbours found as in
    // loop_patch_points (counter-clockwise: A's ring from B is B, C, F,
    // (-1, 0), (0, -1), D; B's from A is A, D, (2, -1), (2, 0), E, C; C's
    // from A is A, B, E, (0, 2), (-1, 2), F).
    Vec3 far[3][2];
    for (int c = 0; c < 3; ++c) {
        bool& regular = o.regular[c];
        regular = p.regular_six(v[c]) && p.derived[v[c]].curve_count == 0;
        if (!regular) continue;
        const std::uint32_t x = v[c];
        const RingIndices r = p.ring_indices(x);
        // Where the walk starts, where it heads (so many places on), and the
        // places of the two neighbours across t's edges (D, E or F).
        struct Walk {
            int from, towards, offset, first_k;
            std::uint32_t first, last;
        };
        const Walk walks[3] = {{1, 2, 1, 2, across[2], across[0]},
                               {0, 2, 5, 1, across[0], across[1]},
                               {0, 1, 1, 2, across[1], across[2]}};
        const Walk& w = walks[c];
        int at = 0, step = 0;
        const bool found = locate(r, v[w.from], v[w.towards], w.offset, at, step);
        const auto nbr = [&](int k) { return r.nbrs[(at + k * step) % 6]; };
        if (!found || nbr(w.first_k) != w.first || nbr(w.first_k + 3) != w.last) {
            regular = false;
            continue;
        }
        // The two ring neighbours between them, in lattice order.
        const int e0 = edge_between(p, x, nbr(w.first_k + 1)), e1 = edge_between(p, x, nbr(w.first_k + 2));
        if (e0 < 0 || e1 < 0) {
            regular = false;
            continue;
        }
        far[c][0] = edge_point(static_cast<std::uint32_t>(e0));
        far[c][1] = edge_point(static_cast<std::uint32_t>(e1));
        if (!complete) return false;
    }
    // far[0]: A's (-1, 0), (0, -1); far[1]: B's (2, -1), (2, 0); far[2]:
    // C's (0, 2), (-1, 2). Each child in LoopPatchPoints' order from its
    // corner P0 (the middle child is the lattice's triangle turned half a
    // turn: its points are the template's mirrored through mBC).
    o.points[3] = {o.mBC, o.mCA, o.mAB, o.mBE, o.mCE, o.C1, o.B1, o.mAF, o.A1, o.mCF, o.mAD, o.mBD};
    o.points[0] = {o.A1, o.mAB, o.mCA, far[0][0], far[0][1], o.mAD, o.mAF, o.B1, o.mBC, o.mBD, o.C1, o.mCF};
    o.points[1] = {o.mAB, o.B1, o.mBC, o.A1, o.mAD, o.mBD, o.mCA, far[1][1], o.mBE, far[1][0], o.mCE, o.C1};
    o.points[2] = {o.mCA, o.mBC, o.C1, o.mAF, o.A1, o.mAB, o.mCF, o.mBE, o.mCE, o.B1, far[2][0], far[2][1]};
    return true;
}

void LoopCornerFrame::grow(Shell& shell) const {
    for (const Vec3& x : {P, M, XB, YC, XD2, YF2}) shell.grow_both(x);
    for (const Vec3& x : ring) shell.grow_both(x);  // X, Y, XD1 and YF1 among them
}

bool loop_corner_frame(const Patch& p, const Patch& next, std::uint32_t t, int c, const LoopChildren& ch,
                       LoopCornerFrame& out) {
    // The frame's points one level down, turned so that corner c is P.
    const Vec3* const named[3][10] = {
        {&ch.A1, &ch.mAB, &ch.mCA, &ch.mBC, &ch.B1, &ch.C1, &ch.mAD, &ch.mBD, &ch.mAF, &ch.mCF},
        {&ch.B1, &ch.mBC, &ch.mAB, &ch.mCA, &ch.C1, &ch.A1, &ch.mBE, &ch.mCE, &ch.mBD, &ch.mAD},
        {&ch.C1, &ch.mCA, &ch.mBC, &ch.mAB, &ch.A1, &ch.B1, &ch.mCF, &ch.mAF, &ch.mCE, &ch.mBE}};
    Vec3* const frame[10] = {&out.P, &out.X, &out.Y, &out.M, &out.XB, &out.YC, &out.XD1, &out.XD2, &out.YF1, &out.YF2};
    for (int k = 0; k < 10; ++k) *frame[k] = *named[c][k];

    // P's ring one level down, counter-clockwise from X: the points of its
    // edges. Only a smooth interior corner: on a boundary or crease the
    // rules refine_corner_frame applies are not Loop's there.
    const std::uint32_t v = p.tris[t].v[c];
    const VertexDerived& d = p.derived[v];
    if (!d.has_ring || !d.single_sector || d.curve_count != 0) return false;
    const RingIndices r = p.ring_indices(v);
    const std::uint32_t n = r.count;
    if (!r.closed || n < 3) return false;
    int at = 0, step = 0;
    if (!locate(r, p.tris[t].v[(c + 1) % 3], p.tris[t].v[(c + 2) % 3], 1, at, step)) return false;
    const auto start = static_cast<std::uint32_t>(at), stride = static_cast<std::uint32_t>(step);
    const auto nbr = [&](std::uint32_t k) { return r.nbrs[(start + k * stride) % n]; };
    // The vertices across t's edges at P must close its ring as the lattice says.
    if (nbr(2) != ch.across[(c + 2) % 3] || nbr(n - 1) != ch.across[c]) return false;
    out.ring.resize(n);
    for (std::uint32_t k = 0; k < n; ++k) {
        const int e = edge_between(p, v, nbr(k));
        if (e < 0) return false;
        const PatchEdge& edge = p.edges[static_cast<std::uint32_t>(e)];
        if (!edge.valid || !next.verts[edge.point].has_position) return false;
        out.ring[k] = next.verts[edge.point].position;
    }
    return true;
}

void refine_corner_frame(const LoopCornerFrame& f, std::array<LoopPatchPoints, 3>& nets, LoopCornerFrame& below) {
    const auto edge_point = [](const Vec3& a, const Vec3& b, const Vec3& left, const Vec3& right) {
        EdgeStencil s;
        s.a = a;
        s.b = b;
        s.interior = true;
        s.c = left;
        s.d = right;
        return loop_edge_point(s);
    };
    const auto vertex_point = [](const Vec3& centre, const Vec3* nbrs, std::size_t count) {
        thread_local VertexRing ring;
        ring.center = centre;
        ring.nbrs.assign(nbrs, nbrs + count);
        ring.closed = true;
        ring.regular = true;
        ring.curve_count = 0;
        return loop_vertex_point(ring);
    };
    const std::size_t n = f.ring.size();
    // One level down the lattice's spacing halves: P2 = (0, 0), q[k] on P's
    // edge to ring point k (q[0] = (1, 0), q[1] = (0, 1)), X2 = (2, 0),
    // Y2 = (0, 2), and the points of the frame's other edges.
    const Vec3 P2 = vertex_point(f.P, f.ring.data(), n);
    const Vec3 x_ring[6] = {f.P, f.XD1, f.XD2, f.XB, f.M, f.Y};
    const Vec3 y_ring[6] = {f.P, f.X, f.M, f.YC, f.YF2, f.YF1};
    const Vec3 X2 = vertex_point(f.X, x_ring, 6);
    const Vec3 Y2 = vertex_point(f.Y, y_ring, 6);
    below.ring.resize(n);
    std::vector<Vec3>& q = below.ring;
    for (std::size_t k = 0; k < n; ++k)
        q[k] = edge_point(f.P, f.ring[k], f.ring[(k + n - 1) % n], f.ring[(k + 1) % n]);
    const Vec3 nXY = edge_point(f.X, f.Y, f.P, f.M);       // (1, 1)
    const Vec3 nXD1 = edge_point(f.X, f.XD1, f.P, f.XD2);  // (2, -1)
    const Vec3 nXD2 = edge_point(f.X, f.XD2, f.XD1, f.XB); // (3, -1)
    const Vec3 nXB = edge_point(f.X, f.XB, f.XD2, f.M);    // (3, 0)
    const Vec3 nXM = edge_point(f.X, f.M, f.XB, f.Y);      // (2, 1)
    const Vec3 nYM = edge_point(f.Y, f.M, f.X, f.YC);      // (1, 2)
    const Vec3 nYC = edge_point(f.Y, f.YC, f.M, f.YF2);    // (0, 3)
    const Vec3 nYF2 = edge_point(f.Y, f.YF2, f.YC, f.YF1); // (-1, 3)
    const Vec3 nYF1 = edge_point(f.Y, f.YF1, f.YF2, f.P);  // (-1, 2)
    const Vec3 &q0 = q[0], &q1 = q[1], &q2 = q[2], &qlast = q[n - 1];

    // As LoopChildren's middle and corner children, with (P, X, Y) for (A, B, C).
    nets[0] = {nXY, q1, q0, nXM, nYM, Y2, X2, q2, P2, nYF1, qlast, nXD1};
    nets[1] = {q0, X2, nXY, P2, qlast, nXD1, q1, nXB, nXM, nXD2, nYM, Y2};
    nets[2] = {q1, nXY, Y2, q2, P2, q0, nYF1, nXM, nYM, X2, nYC, nYF2};
    // The child at P, (P2, q0, q1), and its neighbourhood: the frame again.
    below.P = P2;
    below.X = q0;
    below.Y = q1;
    below.M = nXY;
    below.XB = X2;
    below.YC = Y2;
    below.XD1 = qlast;
    below.XD2 = nXD1;
    below.YF1 = q2;
    below.YF2 = nYF1;
}

bool grow_by_children(const Patch& p, const Patch& next, std::uint32_t t, Shell& shell) {
    LoopChildren ch;
    if (!loop_children_points(p, next, t, ch)) return false;
    const auto grow_by_net = [&](const LoopPatchPoints& points) {
        for (const Vec3& b : loop_bezier_net(points)) shell.grow_both(b);
    };
    grow_by_net(ch.points[3]);  // the middle child is always regular
    for (int c = 0; c < 3; ++c) {
        if (ch.regular[c]) {
            grow_by_net(ch.points[c]);
            continue;
        }
        thread_local LoopCornerFrame frame, below;
        if (loop_corner_frame(p, next, t, c, ch, frame)) {
            std::array<LoopPatchPoints, 3> nets;
            for (int level = 0; level < k_loop_corner_levels; ++level) {
                refine_corner_frame(frame, nets, below);
                for (const LoopPatchPoints& net : nets) grow_by_net(net);
                std::swap(frame, below);
            }
            frame.grow(shell);
            continue;
        }
        // Its corners' rings: the corner's, and those of the two edge
        // points at it (the new corners, t's edge points, and the points of
        // the edges across the two edges of t at this corner).
        grow_by_corner_ring(p, next, t, c, shell);
        for (const Vec3& q : {ch.A1, ch.B1, ch.C1, ch.mAB, ch.mBC, ch.mCA}) shell.grow_both(q);
        for (const Vec3& q : c == 0   ? std::array<Vec3, 4>{ch.mAD, ch.mBD, ch.mAF, ch.mCF}
                             : c == 1 ? std::array<Vec3, 4>{ch.mAD, ch.mBD, ch.mBE, ch.mCE}
                                      : std::array<Vec3, 4>{ch.mBE, ch.mCE, ch.mAF, ch.mCF})
            shell.grow_both(q);
    }
    return true;
}

}  // namespace subdivtrace::detail
