#include "loop_patch.h"

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

/// Where vertex `from` lies in ring r (of six), and the direction `step`
/// (+1 or -1) in which `towards` follows it `offset` places on; false unless
/// exactly one direction fits.
bool locate(const RingIndices& r, std::uint32_t from, std::uint32_t towards, int offset, int& at, int& step) {
    at = -1;
    for (int k = 0; k < 6; ++k)
        if (r.nbrs[k] == from) at = k;
    if (at < 0) return false;
    const bool forward = r.nbrs[(at + offset) % 6] == towards;
    const bool backward = r.nbrs[(at + 6 - offset) % 6] == towards;
    if (forward == backward) return false;
    step = forward ? 1 : 5;  // 5: one step back, modulo 6
    return true;
}

}  // namespace

const std::array<std::array<std::uint8_t, 3>, 15> k_loop_bezier_index = {{
    {4, 0, 0}, {3, 0, 1}, {2, 0, 2}, {1, 0, 3}, {0, 0, 4}, {3, 1, 0}, {2, 1, 1}, {1, 1, 2},
    {0, 1, 3}, {2, 2, 0}, {1, 2, 1}, {0, 2, 2}, {1, 3, 0}, {0, 3, 1}, {0, 4, 0},
}};

LoopBezierNet loop_bezier_net(const LoopPatchPoints& points) {
    LoopBezierNet net;
    for (int q = 0; q < 15; ++q) {
        Vec3 sum(0.0);
        for (int k = 0; k < 12; ++k)
            if (k_weights[q][k] != 0) sum += static_cast<double>(k_weights[q][k]) * points[k];
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

}  // namespace subdivtrace::detail
