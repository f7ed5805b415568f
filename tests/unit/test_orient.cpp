// Consistent winding when a Mesh is built (mesh_from_arrays, orient.h):
// neighbours must run their shared edges in opposite directions, whatever
// order the input's faces had, because the vertex normals every scheme
// shades with are sums over the triangles around a vertex.
#include <catch2/catch.hpp>

#include <map>
#include <random>
#include <utility>

#include <glm/geometric.hpp>

#include "subdivtrace/mesh.h"
#include "subdivtrace/uniform.h"
#include "test_meshes.h"

using namespace subdivtrace;

namespace {

MeshArrays arrays_of(const Mesh& mesh) {
    MeshArrays a;
    a.positions = mesh.positions;
    for (const Triangle& t : mesh.triangles) a.face_indices.push_back({t[0], t[1], t[2]});
    return a;
}

/// Directed edges counted by brute force: each must occur at most once when
/// the winding is consistent (an edge run twice the same way is a disagreement).
std::size_t edges_run_twice_the_same_way(const Mesh& mesh) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
    for (const Triangle& t : mesh.triangles)
        for (int c = 0; c < 3; ++c) ++directed[{t[c], t[(c + 1) % 3]}];
    std::size_t twice = 0;
    for (const auto& [edge, count] : directed) twice += count > 1 ? 1 : 0;
    return twice;
}

/// POV-Ray's scenes/objects/mesh2.pov "Mesh_B": a cube with a pyramid on each
/// face, 24 triangles, whose faces do not agree on a winding.
MeshArrays stellated_cube_as_in_povray() {
    MeshArrays a;
    a.positions = {Vec3(-1, -1, -1), Vec3(1, -1, -1), Vec3(-1, 1, -1), Vec3(1, 1, -1),
                   Vec3(-1, -1, 1),  Vec3(1, -1, 1),  Vec3(-1, 1, 1),  Vec3(1, 1, 1),
                   Vec3(-1.5, 0, 0), Vec3(1.5, 0, 0), Vec3(0, -1.5, 0), Vec3(0, 1.5, 0),
                   Vec3(0, 0, -1.5), Vec3(0, 0, 1.5)};
    a.face_indices = {{8, 0, 2},  {8, 0, 4},  {8, 6, 2},  {8, 6, 4},  {9, 1, 3},  {9, 1, 5},
                      {9, 7, 3},  {9, 7, 5},  {10, 0, 1}, {10, 0, 4}, {10, 5, 1}, {10, 5, 4},
                      {11, 2, 3}, {11, 2, 6}, {11, 7, 3}, {11, 7, 6}, {12, 0, 1}, {12, 0, 2},
                      {12, 3, 1}, {12, 3, 2}, {13, 4, 5}, {13, 4, 6}, {13, 7, 5}, {13, 7, 6}};
    return a;
}

}  // namespace

TEST_CASE("a consistently wound mesh is built untouched", "[mesh][orient]") {
    for (const Mesh& m : {testmesh::icosphere(2), testmesh::torus(8, 6, 1.0, 0.3),
                          testmesh::open_grid(6), testmesh::irregular_closed(7)}) {
        std::vector<std::string> warnings;
        WeldReport report;
        const Mesh built = mesh_from_arrays(arrays_of(m), "test", &warnings, {}, &report);
        CHECK(built.triangles == m.triangles);
        CHECK(report.reversed_triangles.empty());
        CHECK(warnings.empty());
    }
}

TEST_CASE("triangles turned against their neighbours are turned back", "[mesh][orient]") {
    // Turn a random minority of a closed and an open mesh's triangles, with
    // their normals and uvs: building must restore the original exactly.
    std::mt19937 rng(11);
    for (Mesh m : {testmesh::icosphere_with_normals(2), testmesh::open_grid(7)}) {
        m.corner_uvs.clear();
        for (std::size_t i = 0; i < 3 * m.triangles.size(); ++i)
            m.corner_uvs.push_back(Vec2(double(i), -double(i)));
        MeshArrays a = arrays_of(m);
        a.uvs = m.corner_uvs;
        a.normals = m.corner_normals;
        std::vector<std::uint32_t> turned;
        for (std::size_t t = 0; t < m.triangles.size(); ++t) {
            std::array<std::int64_t, 3> corners{std::int64_t(3 * t), std::int64_t(3 * t + 1),
                                                std::int64_t(3 * t + 2)};
            if (rng() % 3 == 0) {
                std::swap(a.face_indices[t][1], a.face_indices[t][2]);
                std::swap(corners[1], corners[2]);
                turned.push_back(static_cast<std::uint32_t>(t));
            }
            a.uv_indices.push_back(corners);
            if (!a.normals.empty()) a.normal_indices.push_back(corners);
        }
        REQUIRE(!turned.empty());
        REQUIRE(2 * turned.size() < m.triangles.size());

        std::vector<std::string> warnings;
        WeldReport report;
        const Mesh built = mesh_from_arrays(a, "test", &warnings, {}, &report);
        CHECK(built.triangles == m.triangles);
        CHECK(built.corner_uvs == m.corner_uvs);
        CHECK(built.corner_normals == m.corner_normals);
        CHECK(report.reversed_triangles == turned);
        REQUIRE(warnings.size() == 1);
        CHECK(warnings[0].find("turned " + std::to_string(turned.size()) + " of") !=
              std::string::npos);
    }
}

TEST_CASE("POV-Ray's mesh2 demo cube gets one winding and outward-symmetric normals",
          "[mesh][orient]") {
    // Before orientation the apex normals summed to zero (half the apex's
    // triangles point in, half out) and the normal scheme's points went wild.
    std::vector<std::string> warnings;
    WeldReport report;
    const Mesh m = mesh_from_arrays(stellated_cube_as_in_povray(), "mesh2", &warnings, {}, &report);
    CHECK(edges_run_twice_the_same_way(m) == 0);
    CHECK(!report.reversed_triangles.empty());
    CHECK(2 * report.reversed_triangles.size() <= m.triangles.size());

    // By symmetry each apex's normal lies along its axis (either sign, the
    // same for all six: one winding), and each cube corner's along its diagonal.
    const SubdividedMesh level0 = subdivide_uniform(m, SchemeKind::normal, 0);
    double sign = 0.0;
    for (std::size_t t = 0; t < m.triangles.size(); ++t)
        for (int c = 0; c < 3; ++c) {
            const Vec3 p = m.positions[m.triangles[t][c]];
            const Vec3 n = level0.corner_normal(t, c);
            REQUIRE(glm::length(n) == Approx(1.0).margin(1e-12));
            const Vec3 axis = glm::normalize(p);
            const double along = glm::dot(n, axis);
            CHECK(std::abs(along) == Approx(1.0).margin(1e-12));
            if (sign == 0.0) sign = along > 0 ? 1.0 : -1.0;
            CHECK(along * sign > 0.0);
        }
}

TEST_CASE("a Moebius strip is wound as far as it can be, with a warning", "[mesh][orient]") {
    // A strip of n quads whose ends are joined with a half twist: no winding
    // agrees everywhere, exactly one edge must disagree.
    const int n = 12;
    MeshArrays a;
    for (int i = 0; i < n; ++i) {
        const double u = 2.0 * 3.14159265358979 * i / n, w = 0.5 * u;
        for (const double s : {-0.3, 0.3})
            a.positions.push_back(Vec3((1.0 + s * std::cos(w)) * std::cos(u),
                                       (1.0 + s * std::cos(w)) * std::sin(u), s * std::sin(w)));
    }
    for (int i = 0; i < n; ++i) {
        const std::int64_t a0 = 2 * i, a1 = 2 * i + 1;
        // The last quad joins the first column upside down (the half twist).
        const std::int64_t b0 = i + 1 < n ? 2 * (i + 1) : 1, b1 = i + 1 < n ? 2 * (i + 1) + 1 : 0;
        a.face_indices.push_back({a0, b0, b1});
        a.face_indices.push_back({a0, b1, a1});
    }
    std::vector<std::string> warnings;
    const Mesh m = mesh_from_arrays(a, "strip", &warnings);
    CHECK(edges_run_twice_the_same_way(m) == 1);
    bool warned = false;
    for (const std::string& w : warnings)
        warned = warned || w.find("1 edge(s) join triangles whose windings cannot agree") !=
                               std::string::npos;
    CHECK(warned);
}
