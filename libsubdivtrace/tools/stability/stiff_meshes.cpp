#include "stability/stiff_meshes.h"

#include <cmath>
#include <vector>

namespace subdivtrace::tools {

namespace {

constexpr double k_pi = 3.14159265358979323846;

/// Splits edge (a, b) at point x, a new vertex, in both faces that have it
/// or, with `only_a_to_b`, only in the face running a -> b; returns its index.
std::uint32_t split_edge(Mesh& m, std::uint32_t a, std::uint32_t b, const Vec3& x,
                         bool only_a_to_b = false) {
    const auto xi = static_cast<std::uint32_t>(m.positions.size());
    m.positions.push_back(x);
    std::vector<Triangle> out;
    for (const Triangle& t : m.triangles) {
        bool split = false;
        for (int i = 0; i < 3 && !split; ++i) {
            const std::uint32_t u = t[i], w = t[(i + 1) % 3], o = t[(i + 2) % 3];
            if ((u == a && w == b) || (!only_a_to_b && u == b && w == a)) {
                out.push_back({u, xi, o});
                out.push_back({xi, w, o});
                split = true;
            }
        }
        if (!split) out.push_back(t);
    }
    m.triangles.swap(out);
    return xi;
}

}  // namespace

Mesh icosahedron() {
    const double phi = (1.0 + std::sqrt(5.0)) / 2.0;
    const double s = 1.0 / std::sqrt(1.0 + phi * phi);
    const double a = s, b = phi * s;
    Mesh m;
    m.positions = {{-a, b, 0},  {a, b, 0},  {-a, -b, 0}, {a, -b, 0},
                   {0, -a, b},  {0, a, b},  {0, -a, -b}, {0, a, -b},
                   {b, 0, -a},  {b, 0, a},  {-b, 0, -a}, {-b, 0, a}};
    m.triangles = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                   {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                   {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                   {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
    return m;
}

Mesh sliver_mesh() {
    Mesh m = icosahedron();
    const Vec3& a = m.positions[0];
    const Vec3& b = m.positions[11];
    split_edge(m, 0, 11, a + 1.0e-6 * (b - a));
    return m;
}

Mesh zero_area_mesh() {
    Mesh m = icosahedron();
    // Vertices 4 (0, -a, b) and 5 (0, a, b) differ in y only, so their midpoint
    // is exact and (4, 5, mid) has exactly zero area.
    const Vec3 mid = (m.positions[4] + m.positions[5]) * 0.5;
    // The face running 4 -> 5 -> o becomes (4, x, o) and (x, 5, o); the
    // T-junction is closed by (4, 5, x), whose edges pair with 4 -> x, x -> 5 and
    // the other face's 5 -> 4.
    const std::uint32_t xi = split_edge(m, 4, 5, mid, true);
    m.triangles.push_back({4, 5, xi});
    return m;
}

Mesh high_valence_fan(int n) {
    Mesh m;
    for (int i = 0; i < n; ++i) {
        const double u = 2.0 * k_pi * i / n;
        m.positions.push_back({std::cos(u), std::sin(u), 0.0});
    }
    const auto top = static_cast<std::uint32_t>(n), bottom = top + 1;
    m.positions.push_back({0.0, 0.0, 1.0});
    m.positions.push_back({0.0, 0.0, -1.0});
    for (int i = 0; i < n; ++i) {
        const auto a = static_cast<std::uint32_t>(i), b = static_cast<std::uint32_t>((i + 1) % n);
        m.triangles.push_back({a, b, top});
        m.triangles.push_back({b, a, bottom});
    }
    return m;
}

Mesh folded() {
    Mesh m = high_valence_fan(8);
    m.positions[8].z = 1.0e-4;
    m.positions[9].z = -1.0e-4;
    return m;
}

void add_box(Mesh& m, const Vec3& lo, const Vec3& hi) {
    const auto base = static_cast<std::uint32_t>(m.positions.size());
    for (int i = 0; i < 8; ++i)
        m.positions.push_back({i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z});
    const std::uint32_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                       {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& q : quads) {
        m.triangles.push_back({base + q[0], base + q[1], base + q[2]});
        m.triangles.push_back({base + q[0], base + q[2], base + q[3]});
    }
}

Mesh offset_mesh(Mesh mesh, const Vec3& offset, double scale) {
    for (Vec3& p : mesh.positions) p = p * scale + offset;
    return mesh;
}

}  // namespace subdivtrace::tools
