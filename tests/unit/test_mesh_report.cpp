// analyze_mesh and crease_masks read one sorted edge table (edge_sides.h);
// here both are checked against a brute-force count over every pair of
// triangles, on random small soups that hold what users' files hold:
// boundaries, fins (three triangles on an edge), bowties, duplicates,
// unreferenced vertices and split normals.
#include <algorithm>
#include <map>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include <catch2/catch.hpp>

#include "creases.h"
#include "subdivtrace/mesh_report.h"

using namespace subdivtrace;

namespace {

using Edge = std::pair<std::uint32_t, std::uint32_t>;

Edge edge_of(const Triangle& t, int e) {
    const std::uint32_t u = t[e], w = t[(e + 1) % 3];
    return {std::min(u, w), std::max(u, w)};
}

bool has_corner(const Triangle& t, std::uint32_t v) { return t[0] == v || t[1] == v || t[2] == v; }

/// Triangles f and g at vertex v share an edge at v (a vertex w != v that both hold).
bool share_edge_at(const Triangle& f, const Triangle& g, std::uint32_t v) {
    for (std::uint32_t w : f)
        if (w != v && has_corner(g, w)) return true;
    return false;
}

/// Number of fans at v: triangles at v joined, transitively, through edges at v.
std::size_t fans_at(const Mesh& m, std::uint32_t v) {
    std::vector<std::size_t> at;
    for (std::size_t f = 0; f < m.triangles.size(); ++f)
        if (has_corner(m.triangles[f], v)) at.push_back(f);
    std::vector<int> fan(at.size(), -1);
    int fans = 0;
    for (std::size_t s = 0; s < at.size(); ++s) {
        if (fan[s] >= 0) continue;
        fan[s] = fans;
        for (bool grew = true; grew;) {  // flood until nothing joins
            grew = false;
            for (std::size_t a = 0; a < at.size(); ++a)
                for (std::size_t b = 0; b < at.size(); ++b)
                    if (fan[a] == fans && fan[b] < 0 &&
                        share_edge_at(m.triangles[at[a]], m.triangles[at[b]], v)) {
                        fan[b] = fans;
                        grew = true;
                    }
        }
        ++fans;
    }
    return static_cast<std::size_t>(fans);
}

Mesh random_soup(std::mt19937& rng) {
    std::uniform_int_distribution<std::uint32_t> vertex(0, 9), count(1, 18), coin(0, 3);
    std::normal_distribution<double> g;
    Mesh m;
    for (int v = 0; v < 11; ++v) m.positions.push_back(Vec3(g(rng), g(rng), g(rng)));  // 10: unreferenced
    const std::uint32_t n = count(rng);
    while (m.triangles.size() < n) {
        const Triangle t{vertex(rng), vertex(rng), vertex(rng)};
        if (t[0] != t[1] && t[1] != t[2] && t[0] != t[2]) m.triangles.push_back(t);
    }
    if (coin(rng) != 0) {
        // One normal per vertex, some corners split from it.
        std::vector<Vec3> per_vertex;
        for (std::size_t v = 0; v < m.positions.size(); ++v) per_vertex.push_back(Vec3(g(rng), g(rng), g(rng)));
        for (const Triangle& t : m.triangles)
            for (std::uint32_t v : t)
                m.corner_normals.push_back(coin(rng) == 0 ? Vec3(g(rng), g(rng), g(rng)) : per_vertex[v]);
    }
    return m;
}

}  // namespace

TEST_CASE("analyze_mesh and crease_masks equal a brute-force count on random soups", "[report][creases]") {
    std::mt19937 rng(20261204);
    for (int trial = 0; trial < 3000; ++trial) {
        const Mesh m = random_soup(rng);
        INFO("trial " << trial);
        // Edges by brute force: the triangles on each.
        std::map<Edge, std::vector<std::size_t>> faces_on;
        for (std::size_t f = 0; f < m.triangles.size(); ++f)
            for (int e = 0; e < 3; ++e) faces_on[edge_of(m.triangles[f], e)].push_back(f);
        std::size_t boundary = 0, nonmanifold = 0;
        std::vector<int> valence(m.positions.size(), 0);
        std::set<std::uint32_t> on_fin;
        for (const auto& [edge, faces] : faces_on) {
            ++valence[edge.first];
            ++valence[edge.second];
            boundary += faces.size() == 1;
            if (faces.size() > 2) {
                ++nonmanifold;
                on_fin.insert({edge.first, edge.second});
            }
        }
        std::size_t singular = 0, unreferenced = 0;
        std::vector<std::size_t> histogram;
        for (std::uint32_t v = 0; v < m.positions.size(); ++v) {
            if (valence[v] == 0) {
                ++unreferenced;
                continue;
            }
            if (histogram.size() <= static_cast<std::size_t>(valence[v])) histogram.resize(valence[v] + 1, 0);
            ++histogram[valence[v]];
            singular += on_fin.count(v) > 0 || fans_at(m, v) > 1;
        }
        const MeshReport r = analyze_mesh(m);
        CHECK(r.edges == faces_on.size());
        CHECK(r.boundary_edges == boundary);
        CHECK(r.nonmanifold_edges == nonmanifold);
        CHECK(r.unreferenced_vertices == unreferenced);
        CHECK(r.singular_vertices == singular);
        CHECK(r.valence_histogram == histogram);
        CHECK(r.closed == (boundary == 0 && nonmanifold == 0));

        // Creases: an edge of exactly two triangles whose normals at either
        // end differ between them.
        const std::vector<std::uint8_t> masks = detail::crease_masks(m);
        REQUIRE(masks.size() == m.triangles.size());
        std::size_t wrong = 0, creases = 0;
        for (std::size_t f = 0; f < m.triangles.size(); ++f)
            for (int e = 0; e < 3; ++e) {
                const std::vector<std::size_t>& faces = faces_on[edge_of(m.triangles[f], e)];
                bool crease = false;
                if (m.has_normals() && faces.size() == 2) {
                    const std::size_t other = faces[0] == f ? faces[1] : faces[0];
                    for (std::uint32_t v : {m.triangles[f][e], m.triangles[f][(e + 1) % 3]})
                        crease = crease || detail::normals_split(detail::given_normal_of(m, static_cast<std::uint32_t>(f), v),
                                                                 detail::given_normal_of(m, static_cast<std::uint32_t>(other), v));
                }
                creases += crease;
                wrong += crease != ((masks[f] >> e & 1u) != 0);
            }
        CHECK(wrong == 0);
        CHECK(r.crease_edges == creases / 2);
    }
}
