// Mesh analysis for `subdivtrace info` (mesh_report.h).
#include "subdivtrace/mesh_report.h"

#include "creases.h"
#include "disjoint_sets.h"
#include "edge_sides.h"
#include "scheme_rules.h"
#include "vertex_faces.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace subdivtrace {

namespace {

// Exact arithmetic for the sign of a 2x2 orientation determinant (Shewchuk,
// "Adaptive Precision Floating-Point Arithmetic and Fast Robust Geometric
// Predicates", 1997): products split exactly with fma, summed as a
// nonoverlapping expansion.

void two_sum(double a, double b, double& s, double& e) {
    s = a + b;
    const double bv = s - a;
    const double av = s - bv;
    e = (a - av) + (b - bv);
}

/// Adds b to the expansion e (nonoverlapping, increasing magnitude), in place.
void grow_expansion(std::vector<double>& e, double b) {
    double q = b;
    std::size_t out = 0;
    for (std::size_t i = 0; i < e.size(); ++i) {
        double s, h;
        two_sum(q, e[i], s, h);
        q = s;
        if (h != 0.0) e[out++] = h;
    }
    e.resize(out);
    if (q != 0.0) e.push_back(q);
}

/// Sign of (b - a) x (c - a) in the plane of coordinates (i, j): exact.
int orient2d_sign(const Vec3& a, const Vec3& b, const Vec3& c, int i, int j) {
    // det = ax*by - ax*cy - bx*ay + bx*cy + cx*ay - cx*by
    const double terms[6][2] = {{a[i], b[j]}, {-a[i], c[j]}, {-b[i], a[j]},
                                {b[i], c[j]}, {c[i], a[j]},  {-c[i], b[j]}};
    double naive = 0.0, magnitude = 0.0;
    for (const auto& t : terms) {
        naive += t[0] * t[1];
        magnitude += std::abs(t[0] * t[1]);
    }
    // Forward error of six products and five sums is below 12 eps * magnitude.
    const double bound = 16.0 * std::numeric_limits<double>::epsilon() * magnitude;
    if (naive > bound) return 1;
    if (naive < -bound) return -1;
    std::vector<double> e;
    e.reserve(24);
    for (const auto& t : terms) {
        const double p = t[0] * t[1];
        const double err = std::fma(t[0], t[1], -p);
        grow_expansion(e, err);
        grow_expansion(e, p);
    }
    if (e.empty()) return 0;
    return e.back() > 0.0 ? 1 : -1;
}

}  // namespace

bool is_degenerate_triangle(const Vec3& a_in, const Vec3& b_in, const Vec3& c_in) {
    // Scale by a power of two (exact) so the largest coordinate is near 1: the
    // products below then neither overflow nor, for coordinates of similar
    // magnitude, underflow (scale 1e-200 or 1e200 meshes stay exact).
    double largest = 0.0;
    for (const Vec3* p : {&a_in, &b_in, &c_in})
        for (int i = 0; i < 3; ++i) largest = std::max(largest, std::abs((*p)[i]));
    if (largest == 0.0) return true;
    const int e = std::ilogb(largest);
    Vec3 a, b, c;
    for (int i = 0; i < 3; ++i) {
        a[i] = std::ldexp(a_in[i], -e);
        b[i] = std::ldexp(b_in[i], -e);
        c[i] = std::ldexp(c_in[i], -e);
    }
    // Collinear in 3-D iff collinear in all three axis projections.
    return orient2d_sign(a, b, c, 0, 1) == 0 && orient2d_sign(a, b, c, 1, 2) == 0 &&
           orient2d_sign(a, b, c, 2, 0) == 0;
}

MeshReport analyze_mesh(const Mesh& mesh) {
    MeshReport r;
    const std::size_t nv = mesh.positions.size();
    r.vertices = nv;
    r.faces = mesh.triangles.size();
    r.has_normals = mesh.has_normals();
    // Edges and the triangles on them.
    const detail::HugeArray<detail::EdgeSide> sides = detail::sorted_edge_sides(mesh.triangles, nv);
    for (std::uint8_t m : detail::crease_masks(mesh, sides)) r.crease_edges += (m & 1u) + (m >> 1 & 1u) + (m >> 2 & 1u);
    r.crease_edges /= 2;  // counted from both triangles
    r.has_uvs = mesh.has_uvs();
    r.bounds = mesh_bounds(mesh);

    std::vector<int> valence(nv, 0);
    std::vector<unsigned char> on_nonmanifold(nv, 0);
    detail::for_each_edge(sides, [&](const detail::EdgeSide* first, const detail::EdgeSide* last) {
        ++r.edges;
        ++valence[first->lo];
        ++valence[first->hi];
        const std::ptrdiff_t faces = last - first;
        if (faces == 1) ++r.boundary_edges;
        if (faces > 2) {
            ++r.nonmanifold_edges;
            on_nonmanifold[first->lo] = on_nonmanifold[first->hi] = 1;
        }
    });
    // A vertex some triangle holds has an edge there: used iff valence > 0.
    const auto used = [&](std::size_t v) { return valence[v] > 0; };
    r.closed = r.edges > 0 && r.boundary_edges == 0 && r.nonmanifold_edges == 0;

    // Valences of the used vertices.
    bool first = true;
    for (std::size_t v = 0; v < nv; ++v) {
        if (!used(v)) {
            ++r.unreferenced_vertices;
            continue;
        }
        const int k = valence[v];
        if (r.valence_histogram.size() <= static_cast<std::size_t>(k))
            r.valence_histogram.resize(static_cast<std::size_t>(k) + 1, 0);
        ++r.valence_histogram[static_cast<std::size_t>(k)];
        r.min_valence = first ? k : std::min(r.min_valence, k);
        r.max_valence = first ? k : std::max(r.max_valence, k);
        first = false;
    }

    // Degenerate and duplicate triangles.
    for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
        const Triangle& t = mesh.triangles[f];
        if (is_degenerate_triangle(mesh.positions[t[0]], mesh.positions[t[1]],
                                   mesh.positions[t[2]]))
            ++r.degenerate_faces;
    }
    {
        std::vector<std::array<std::uint32_t, 3>> sorted(mesh.triangles.size());
        for (std::size_t f = 0; f < sorted.size(); ++f) {
            sorted[f] = mesh.triangles[f];
            std::sort(sorted[f].begin(), sorted[f].end());
        }
        std::sort(sorted.begin(), sorted.end());
        for (std::size_t f = 1; f < sorted.size(); ++f)
            if (sorted[f] == sorted[f - 1]) ++r.duplicate_faces;
    }

    // Connected components through shared vertices.
    detail::DisjointSets components(nv);
    for (const Triangle& t : mesh.triangles) {
        components.unite(t[0], t[1]);
        components.unite(t[0], t[2]);
    }
    for (std::size_t v = 0; v < nv; ++v)
        if (used(v) && components.find(static_cast<std::uint32_t>(v)) == v) ++r.components;

    // Singular vertices: on a non-manifold edge, or whose triangles form more
    // than one fan: the sectors of label_sectors with no crease.
    const detail::VertexFaces faces_of(mesh.triangles, nv);
    std::vector<detail::FanCorner> corners;
    std::vector<std::uint32_t> labels;
    for (std::uint32_t v = 0; v < nv; ++v) {
        if (!used(v)) continue;
        if (on_nonmanifold[v]) {
            ++r.singular_vertices;
            continue;
        }
        corners.clear();
        for (std::uint32_t f : faces_of.faces_of(v)) {
            const Triangle& t = mesh.triangles[f];
            const int c = detail::corner_of(t, v);
            detail::FanCorner corner;
            corner.prev = t[(c + 2) % 3];
            corner.next = t[(c + 1) % 3];
            corners.push_back(corner);
        }
        if (detail::label_sectors(corners, labels) > 1) ++r.singular_vertices;
    }
    return r;
}

std::string given_normals_warning(const Mesh& mesh, SchemeKind scheme, const std::string& source) {
    if (!mesh.has_normals() || detail::rules_of(scheme).takes_given_normals) return "";
    std::size_t creases = 0;
    for (std::uint8_t m : detail::crease_masks(mesh)) creases += (m & 1u) + (m >> 1 & 1u) + (m >> 2 & 1u);
    std::string w = source + ": the " + scheme_name(scheme) +
                    " scheme computes its own normals, so the mesh's normals do not change the surface";
    if (creases > 0)
        w += " (except that where they are split they mark " + std::to_string(creases / 2) +
             " crease edges)";
    return w + "; the normal scheme uses them";
}

}  // namespace subdivtrace
