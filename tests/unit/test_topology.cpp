// The base topology's flat arrays against brute force: faces around a vertex,
// faces on an edge (found through the lower vertex's faces, no edge table),
// the grid points naming an edge point, closedness.
#include <catch2/catch.hpp>

#include <algorithm>
#include <random>

#include "base_topology.h"
#include "test_meshes.h"

using namespace subdivtrace;
using subdivtrace::detail::BaseTopology;
using subdivtrace::detail::GridPoint;
using subdivtrace::detail::VertexKey;

namespace {

/// Random triangles over few vertices: many edges end up with 1, 3 or more
/// faces (non-manifold), some with exactly 2, and some vertices with none.
Mesh random_soup(std::mt19937& rng, std::uint32_t vertices, std::uint32_t faces) {
    Mesh m;
    std::uniform_real_distribution<double> coord(-1.0, 1.0);
    for (std::uint32_t v = 0; v < vertices; ++v)
        m.positions.push_back(Vec3(coord(rng), coord(rng), coord(rng)));
    std::uniform_int_distribution<std::uint32_t> pick(0, vertices - 1);
    while (m.triangles.size() < faces) {
        const Triangle t{pick(rng), pick(rng), pick(rng)};
        if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) continue;
        m.triangles.push_back(t);
    }
    return m;
}

std::vector<std::uint32_t> brute_faces_of_edge(const Mesh& m, std::uint32_t u, std::uint32_t w) {
    std::vector<std::uint32_t> out;
    for (std::uint32_t f = 0; f < m.triangles.size(); ++f) {
        const Triangle& t = m.triangles[f];
        const bool has_u = t[0] == u || t[1] == u || t[2] == u;
        const bool has_w = t[0] == w || t[1] == w || t[2] == w;
        if (has_u && has_w) out.push_back(f);
    }
    return out;
}

bool brute_closed(const Mesh& m) {
    for (const Triangle& t : m.triangles)
        for (int c = 0; c < 3; ++c)
            if (brute_faces_of_edge(m, t[c], t[(c + 1) % 3]).size() != 2) return false;
    return true;
}

void check_against_brute_force(const Mesh& m) {
    const BaseTopology topo(m);
    CHECK(topo.closed() == brute_closed(m));
    for (std::uint32_t v = 0; v < m.positions.size(); ++v) {
        std::vector<std::uint32_t> expected;
        for (std::uint32_t f = 0; f < m.triangles.size(); ++f) {
            const Triangle& t = m.triangles[f];
            if (t[0] == v || t[1] == v || t[2] == v) expected.push_back(f);
        }
        const auto got = topo.faces_of_vertex(v);
        REQUIRE(std::vector<std::uint32_t>(got.begin(), got.end()) == expected);
    }
    // The mesh's own edges, as every new edge point asks (faces_on_edge
    // counts only where an edge may have other than two).
    for (const Triangle& t : m.triangles)
        for (int c = 0; c < 3; ++c) {
            const std::uint32_t u = t[c], w = t[(c + 1) % 3];
            REQUIRE(topo.faces_on_edge(u, w) == brute_faces_of_edge(m, u, w).size());
            REQUIRE(topo.faces_on_edge(w, u) == brute_faces_of_edge(m, u, w).size());
        }
    // Every vertex pair, edges or not, both orders.
    std::vector<GridPoint> reps;
    for (std::uint32_t u = 0; u < m.positions.size(); ++u) {
        for (std::uint32_t w = 0; w < m.positions.size(); ++w) {
            if (u == w) continue;
            const auto expected = brute_faces_of_edge(m, u, w);
            REQUIRE(topo.edge_face_count(u, w) == expected.size());
            if (u > w) continue;
            // The level-2 point a quarter of the way from u to w (weight 1 on w).
            VertexKey key;
            key.kind = VertexKey::edge_point;
            key.level = 2;
            key.a = u;
            key.b = w;
            key.c = 1;
            topo.representations(key, 2, reps);
            REQUIRE(reps.size() == expected.size());
            for (std::size_t k = 0; k < reps.size(); ++k) {
                REQUIRE(reps[k].face == expected[k]);
                // The grid point names the key back from its own face.
                CHECK(topo.canonical(reps[k].face, 2, reps[k].i, reps[k].j) == key);
            }
        }
    }
}

}  // namespace

TEST_CASE("base topology: faces of vertices and edges agree with brute force",
          "[topology]") {
    std::mt19937 rng(20261130);
    for (int round = 0; round < 20; ++round) {
        const std::uint32_t vertices = 4 + round;
        const Mesh m = random_soup(rng, vertices, 3 * vertices);
        INFO("round " << round);
        check_against_brute_force(m);
    }
    // Named meshes: closed, open, and the non-manifold fan of the stiff cases.
    check_against_brute_force(testmesh::icosahedron());
    check_against_brute_force(testmesh::open_grid(4));
    check_against_brute_force(testmesh::octasphere_half(2, true));  // open, every edge one or two faces
    check_against_brute_force(testmesh::faceted_cube());             // closed, with creases
    const BaseTopology ico(testmesh::icosahedron());
    CHECK(ico.closed());
    const Mesh grid = testmesh::open_grid(4);
    CHECK_FALSE(BaseTopology(grid).closed());
}

TEST_CASE("base topology holds 4 bytes per vertex and 12 per triangle", "[topology][memory]") {
    const Mesh m = testmesh::icosphere(3);  // 642 vertices, 1280 triangles
    const BaseTopology topo(m);
    CHECK(topo.owned_bytes() == 4 * (m.positions.size() + 1) + 12 * m.triangles.size());
}
