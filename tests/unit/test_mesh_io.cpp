// Mesh input, validation, output and analysis: readers against hand-written
// files with known content, OpenMesh's readers/writers as independent truth on
// good files, and every bad input of DESIGN.md section 9 giving a MeshError
// that names the file and the reason.
// OpenMesh's PropertyT<VectorT<double, 3>>::push_back() copies a value-initialised
// VectorT whose constructor leaves it uninitialised; GCC 12 warns inside
// OpenMesh's headers. Not our code, so not our warning.
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

#include <unistd.h>

#include <glm/geometric.hpp>

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>

#include "subdivtrace/mesh.h"
#include "subdivtrace/mesh_io.h"
#include "subdivtrace/mesh_report.h"
#include "subdivtrace/uniform.h"
#include "unit/test_meshes.h"

namespace fs = std::filesystem;
using namespace subdivtrace;

namespace {

/// A fresh directory under the system temp dir, removed at scope exit.
struct TempDir {
    fs::path dir;
    TempDir() {
        static int counter = 0;
        dir = fs::temp_directory_path() / ("subdivtrace_mesh_io_" + std::to_string(::getpid()) +
                                           "_" + std::to_string(counter++));
        fs::remove_all(dir);
        fs::create_directories(dir);
    }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(dir, ec);
    }
    std::string write(const std::string& name, const std::string& bytes) const {
        const fs::path p = dir / name;
        std::ofstream out(p, std::ios::binary);
        out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
        return p.string();
    }
    std::string path(const std::string& name) const { return (dir / name).string(); }
};

const std::string k_cube_obj =
    "# cube\n"
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
    "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";

const std::vector<Vec3> k_cube_positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                            {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};

/// Little-endian bytes of a value.
template <class T>
void put(std::string& s, T v, bool big_endian = false) {
    unsigned char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    if (big_endian)
        for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(b[i], b[sizeof(T) - 1 - i]);
    s.append(reinterpret_cast<const char*>(b), sizeof(T));
}

/// Binary STL of `mesh` (float coordinates, zero normals).
std::string binary_stl(const Mesh& mesh) {
    std::string s(80, ' ');
    put<std::uint32_t>(s, static_cast<std::uint32_t>(mesh.triangles.size()));
    for (const Triangle& t : mesh.triangles) {
        for (int i = 0; i < 3; ++i) put<float>(s, 0.0f);
        for (std::uint32_t v : t)
            for (int i = 0; i < 3; ++i) put<float>(s, static_cast<float>(mesh.positions[v][i]));
        put<std::uint16_t>(s, 0);
    }
    return s;
}

std::string ascii_stl(const Mesh& mesh) {
    std::string s = "solid test\n";
    char buf[128];
    for (const Triangle& t : mesh.triangles) {
        s += "  facet normal 0 0 0\n    outer loop\n";
        for (std::uint32_t v : t) {
            std::snprintf(buf, sizeof buf, "      vertex %.17g %.17g %.17g\n",
                          static_cast<float>(mesh.positions[v].x),
                          static_cast<float>(mesh.positions[v].y),
                          static_cast<float>(mesh.positions[v].z));
            s += buf;
        }
        s += "    endloop\n  endfacet\n";
    }
    return s + "endsolid test\n";
}

/// PLY of `mesh` with per-vertex normals taken from `normals`.
std::string ply(const Mesh& mesh, const std::vector<Vec3>& normals, const std::string& format) {
    std::string s = "ply\nformat " + format + " 1.0\ncomment test\nelement vertex " +
                    std::to_string(mesh.positions.size()) +
                    "\nproperty float x\nproperty float y\nproperty float z\n"
                    "property float nx\nproperty float ny\nproperty float nz\n"
                    "element face " +
                    std::to_string(mesh.triangles.size()) +
                    "\nproperty list uchar int vertex_indices\nend_header\n";
    const bool ascii = format == "ascii";
    const bool big = format == "binary_big_endian";
    char buf[256];
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
        const Vec3& p = mesh.positions[v];
        const Vec3& n = normals[v];
        if (ascii) {
            std::snprintf(buf, sizeof buf, "%.17g %.17g %.17g %.17g %.17g %.17g\n",
                          static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z),
                          static_cast<float>(n.x), static_cast<float>(n.y),
                          static_cast<float>(n.z));
            s += buf;
        } else {
            for (int i = 0; i < 3; ++i) put<float>(s, static_cast<float>(p[i]), big);
            for (int i = 0; i < 3; ++i) put<float>(s, static_cast<float>(n[i]), big);
        }
    }
    for (const Triangle& t : mesh.triangles) {
        if (ascii) {
            s += "3 " + std::to_string(t[0]) + " " + std::to_string(t[1]) + " " +
                 std::to_string(t[2]) + "\n";
        } else {
            put<std::uint8_t>(s, 3);
            for (std::uint32_t v : t) put<std::int32_t>(s, static_cast<std::int32_t>(v), big);
        }
    }
    return s;
}

/// Exact equality of geometry, topology and attributes.
void require_same(const Mesh& a, const Mesh& b) {
    REQUIRE(a.positions.size() == b.positions.size());
    REQUIRE(a.triangles.size() == b.triangles.size());
    for (std::size_t i = 0; i < a.positions.size(); ++i) REQUIRE(a.positions[i] == b.positions[i]);
    for (std::size_t i = 0; i < a.triangles.size(); ++i) REQUIRE(a.triangles[i] == b.triangles[i]);
    REQUIRE(a.corner_normals.size() == b.corner_normals.size());
    for (std::size_t i = 0; i < a.corner_normals.size(); ++i)
        REQUIRE(a.corner_normals[i] == b.corner_normals[i]);
    REQUIRE(a.corner_uvs.size() == b.corner_uvs.size());
    for (std::size_t i = 0; i < a.corner_uvs.size(); ++i)
        REQUIRE(a.corner_uvs[i] == b.corner_uvs[i]);
}

/// Reading `path` throws a MeshError naming the file and containing `reason`.
void require_error(const std::string& path, const std::string& reason) {
    INFO("file " << path << ", expected reason '" << reason << "'");
    try {
        read_mesh(path);
        FAIL("no MeshError");
    } catch (const MeshError& e) {
        const std::string msg = e.what();
        INFO("message: " << msg);
        CHECK(msg.rfind(path + ": ", 0) == 0);
        CHECK(msg.find(reason) != std::string::npos);
    }
}

double float_round(double x) { return static_cast<double>(static_cast<float>(x)); }

/// The bytes of the file at `path`.
std::string file_bytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

using OMesh = OpenMesh::PolyMesh_ArrayKernelT<testmesh::DTraits>;

}  // namespace

// ---------------------------------------------------------------------------
// Readers on good input

TEST_CASE("mesh_io: OBJ cube of quads reads as 12 triangles with known coordinates", "[mesh_io]") {
    TempDir tmp;
    std::vector<std::string> warnings;
    const Mesh m = read_mesh(tmp.write("cube.obj", k_cube_obj), &warnings);
    REQUIRE(m.positions == k_cube_positions);
    REQUIRE(m.triangles.size() == 12);
    // Fan triangulation of "f 1 4 3 2": (0 3 2), (0 2 1).
    CHECK(m.triangles[0] == Triangle{0, 3, 2});
    CHECK(m.triangles[1] == Triangle{0, 2, 1});
    CHECK_FALSE(m.has_normals());
    CHECK_FALSE(m.has_uvs());
    REQUIRE(warnings.size() == 1);
    CHECK(warnings[0].find("fan-triangulated 6 polygon") != std::string::npos);
    const MeshReport r = analyze_mesh(m);
    CHECK(r.closed);
    CHECK(r.vertices == 8);
    CHECK(r.edges == 18);
}

TEST_CASE("mesh_io: a quad becomes two triangles, with a warning", "[mesh_io]") {
    TempDir tmp;
    for (const char* name : {"quad.obj", "quad.off"}) {
        const bool obj = std::string(name) == "quad.obj";
        const std::string text = obj ? "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n"
                                     : "OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n";
        std::vector<std::string> warnings;
        const Mesh m = read_mesh(tmp.write(name, text), &warnings);
        REQUIRE(m.triangles.size() == 2);
        CHECK(m.triangles[0] == Triangle{0, 1, 2});
        CHECK(m.triangles[1] == Triangle{0, 2, 3});
        REQUIRE(warnings.size() == 1);
        CHECK(warnings[0].find(name) != std::string::npos);
        CHECK(warnings[0].find("triangulated") != std::string::npos);
    }
}

TEST_CASE("mesh_io: OBJ negative indices resolve like positive ones", "[mesh_io]") {
    TempDir tmp;
    const Mesh pos = read_mesh(tmp.write("pos.obj", k_cube_obj));
    // Same cube, each face written right after its own vertices are defined
    // would be unusual; instead reference everything relatively from the end.
    std::string neg = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n";
    const int faces[6][4] = {{1, 4, 3, 2}, {5, 6, 7, 8}, {1, 2, 6, 5},
                             {2, 3, 7, 6}, {3, 4, 8, 7}, {4, 1, 5, 8}};
    for (const auto& f : faces) {
        neg += "f";
        for (int i : f) neg += " " + std::to_string(i - 9);  // 8 vertices: 1 -> -8
        neg += "\n";
    }
    require_same(pos, read_mesh(tmp.write("neg.obj", neg)));

    // Relative to the count *so far*: vertices interleaved with faces.
    const std::string inter = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\nv 0 0 1\nf -4 -1 -3\n";
    const Mesh m = read_mesh(tmp.write("inter.obj", inter));
    REQUIRE(m.triangles.size() == 2);
    CHECK(m.triangles[0] == Triangle{0, 1, 2});
    CHECK(m.triangles[1] == Triangle{0, 3, 1});
}

TEST_CASE("mesh_io: OBJ v/vt/vn corners become corner uvs and normals", "[mesh_io]") {
    TempDir tmp;
    const std::string text =
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
        "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
        "vn 0 0 1\nvn 0 0.6 0.8\n"
        "f 1/1/1 2/2/1 3/3/2\n"
        "f 1/1/1 3/3/2 4/4/1\n";
    const Mesh m = read_mesh(tmp.write("attr.obj", text));
    REQUIRE(m.triangles.size() == 2);
    REQUIRE(m.corner_uvs.size() == 6);
    REQUIRE(m.corner_normals.size() == 6);
    CHECK(m.corner_uvs[1] == Vec2(1, 0));
    CHECK(m.corner_uvs[5] == Vec2(0, 1));
    CHECK(m.corner_normals[2] == Vec3(0, 0.6, 0.8));
    CHECK(m.corner_normals[3] == Vec3(0, 0, 1));

    // v//vn: normals without uvs; comments, CRLF, groups and smoothing lines.
    const std::string text2 =
        "# comment\r\no thing\r\ng group\r\nv 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\n"
        "vn 0 0 1\r\ns 1\r\nusemtl red\r\nf 1//1 2//1 3//1 # trailing comment\r\n";
    const Mesh m2 = read_mesh(tmp.write("vn.obj", text2));
    REQUIRE(m2.triangles.size() == 1);
    CHECK_FALSE(m2.has_uvs());
    REQUIRE(m2.corner_normals.size() == 3);
    CHECK(m2.corner_normals[0] == Vec3(0, 0, 1));

    // Some faces without normals: normals dropped, with a warning.
    std::vector<std::string> warnings;
    const Mesh m3 = read_mesh(tmp.write("mixed.obj",
                                        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvn 0 0 1\n"
                                        "f 1//1 2//1 3//1\nf 2 4 3\n"),
                              &warnings);
    CHECK_FALSE(m3.has_normals());
    REQUIRE(warnings.size() == 1);
    CHECK(warnings[0].find("normals ignored") != std::string::npos);

    // The same with the normals first met after corners without them (the
    // reader keeps normal references only from the first one on): the
    // corners before count as missing, and one bad reference after them is
    // still found.
    warnings.clear();
    const Mesh m4 = read_mesh(tmp.write("late.obj",
                                        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvn 0 0 1\n"
                                        "f 2 4 3\nf 1//1 2//1 3//1\n"),
                              &warnings);
    CHECK_FALSE(m4.has_normals());
    REQUIRE(warnings.size() == 1);
    CHECK(warnings[0].find("3 face corner(s) have no normal") != std::string::npos);
    CHECK_THROWS_WITH(read_mesh(tmp.write("late_bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\n"
                                                          "f 1 2 3\nf 1//1 2//1 3//2\n")),
                      Catch::Contains("line 6: normal index 2 out of range"));
}

TEST_CASE("mesh_io: extensions are case-insensitive, unknown ones are refused", "[mesh_io]") {
    TempDir tmp;
    CHECK(read_mesh(tmp.write("CUBE.OBJ", k_cube_obj)).triangles.size() == 12);
    require_error(tmp.write("cube.xyz", k_cube_obj), "unsupported");
    require_error(tmp.write("cube", k_cube_obj), "unsupported");
}

TEST_CASE("mesh_io: OFF: comments, colours and NOFF normals", "[mesh_io]") {
    TempDir tmp;
    const std::string text =
        "OFF # a comment\n# another\n4 2 0\n"
        "0 0 0\n1 0 0\n1 1 0\n0 1 0\n"
        "3 0 1 2 255 0 0\n3 0 2 3\n";
    const Mesh m = read_mesh(tmp.write("a.off", text));
    REQUIRE(m.positions.size() == 4);
    REQUIRE(m.triangles.size() == 2);
    CHECK(m.triangles[1] == Triangle{0, 2, 3});
    CHECK(m.positions[2] == Vec3(1, 1, 0));

    const std::string noff = "NOFF\n3 1 0\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0.6 0 0.8\n3 0 1 2\n";
    const Mesh n = read_mesh(tmp.write("n.off", noff));
    REQUIRE(n.corner_normals.size() == 3);
    CHECK(n.corner_normals[2] == Vec3(0.6, 0, 0.8));

    const Mesh one_line =
        read_mesh(tmp.write("b.off", "OFF 3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"));
    CHECK(one_line.triangles.size() == 1);
}

TEST_CASE("mesh_io: PLY ascii, binary little and big endian read equal", "[mesh_io]") {
    TempDir tmp;
    const Mesh ico = testmesh::icosahedron();
    std::vector<Vec3> normals;
    for (const Vec3& p : ico.positions) normals.push_back(p);  // unit sphere: normal = position
    const Mesh a = read_mesh(tmp.write("a.ply", ply(ico, normals, "ascii")));
    const Mesh le = read_mesh(tmp.write("le.ply", ply(ico, normals, "binary_little_endian")));
    const Mesh be = read_mesh(tmp.write("be.ply", ply(ico, normals, "binary_big_endian")));
    require_same(a, le);
    require_same(a, be);
    REQUIRE(a.triangles == ico.triangles);
    for (std::size_t i = 0; i < ico.positions.size(); ++i)
        for (int k = 0; k < 3; ++k) CHECK(a.positions[i][k] == float_round(ico.positions[i][k]));
    // Per-vertex normals become corner normals.
    REQUIRE(a.corner_normals.size() == 3 * ico.triangles.size());
    CHECK(a.corner_normals[4].x == float_round(ico.positions[ico.triangles[1][1]].x));
}

TEST_CASE("mesh_io: PLY: other elements and properties are skipped", "[mesh_io]") {
    TempDir tmp;
    std::string s =
        "ply\nformat binary_little_endian 1.0\n"
        "element material 1\nproperty uchar r\nproperty list uchar float junk\n"
        "element vertex 3\nproperty double x\nproperty double y\nproperty double z\n"
        "property uchar red\n"
        "element face 1\nproperty uchar flags\nproperty list uchar uint vertex_indices\n"
        "property list uchar float texcoord\nend_header\n";
    put<std::uint8_t>(s, 7);
    put<std::uint8_t>(s, 2);
    put<float>(s, 1.0f);
    put<float>(s, 2.0f);
    const double p[3][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    for (const auto& v : p) {
        for (double x : v) put<double>(s, x);
        put<std::uint8_t>(s, 200);
    }
    put<std::uint8_t>(s, 0);
    put<std::uint8_t>(s, 3);
    for (std::uint32_t i : {0u, 1u, 2u}) put<std::uint32_t>(s, i);
    put<std::uint8_t>(s, 6);
    for (float x : {0.f, 0.f, 1.f, 0.f, 0.f, 1.f}) put<float>(s, x);
    const Mesh m = read_mesh(tmp.write("extra.ply", s));
    REQUIRE(m.triangles.size() == 1);
    CHECK(m.positions[1] == Vec3(1, 0, 0));
    REQUIRE(m.corner_uvs.size() == 3);
    CHECK(m.corner_uvs[2] == Vec2(0, 1));
}

TEST_CASE("mesh_io: STL ascii and binary read equal, vertices are merged", "[mesh_io]") {
    TempDir tmp;
    const Mesh cube = read_mesh(tmp.write("cube.obj", k_cube_obj));
    const Mesh b = read_mesh(tmp.write("b.stl", binary_stl(cube)));
    const Mesh a = read_mesh(tmp.write("a.stl", ascii_stl(cube)));
    require_same(a, b);
    CHECK(b.positions.size() == 8);
    CHECK(b.triangles.size() == 12);
    CHECK(analyze_mesh(b).closed);
    // Binary STL whose 80-byte header starts with "solid" is still binary.
    std::string tricky = binary_stl(cube);
    tricky.replace(0, 5, "solid");
    require_same(b, read_mesh(tmp.write("tricky.stl", tricky)));
    // Corner positions are the input's (merged by exact value).
    for (std::size_t t = 0; t < cube.triangles.size(); ++t)
        for (int k = 0; k < 3; ++k)
            CHECK(b.positions[b.triangles[t][k]] == cube.positions[cube.triangles[t][k]]);
}

TEST_CASE("mesh_io: our readers agree with OpenMesh's on good files", "[mesh_io]") {
    TempDir tmp;
    const std::string data = SUBDIVTRACE_TEST_DATA "/../../data/";
    for (const char* name : {"bunny_lowpoly.obj", "icosahedron.obj"}) {
        const Mesh ours = read_mesh(data + name);
        OMesh om;
        REQUIRE(OpenMesh::IO::read_mesh(om, data + name));
        REQUIRE(om.n_vertices() == ours.positions.size());
        REQUIRE(om.n_faces() == ours.triangles.size());
        for (auto f : om.faces()) {
            std::vector<std::uint32_t> ids;
            for (auto v : om.fv_range(f)) ids.push_back(static_cast<std::uint32_t>(v.idx()));
            REQUIRE(ids.size() == 3);
            const Triangle& t = ours.triangles[static_cast<std::size_t>(f.idx())];
            CHECK((ids[0] == t[0] && ids[1] == t[1] && ids[2] == t[2]));
        }
        // OpenMesh reads OBJ coordinates as float.
        for (auto v : om.vertices())
            for (int k = 0; k < 3; ++k)
                CHECK(float_round(ours.positions[static_cast<std::size_t>(v.idx())][k]) ==
                      float_round(om.point(v)[k]));
    }
    // Files OpenMesh writes read back as the same mesh here.
    const Mesh bunny = read_mesh(data + "bunny_lowpoly.obj");
    OMesh om;
    REQUIRE(OpenMesh::IO::read_mesh(om, data + "bunny_lowpoly.obj"));
    for (const char* name : {"om.off", "om.ply", "om.stl"}) {
        OpenMesh::IO::Options opt;
        if (std::string(name) != "om.off") opt += OpenMesh::IO::Options::Binary;
        REQUIRE(OpenMesh::IO::write_mesh(om, tmp.path(name), opt));
        const Mesh back = read_mesh(tmp.path(name));
        INFO(name);
        CHECK(back.triangles.size() == bunny.triangles.size());
        CHECK(back.positions.size() == bunny.positions.size());
        const MeshReport r = analyze_mesh(back);
        CHECK(r.closed);
        double err = 0.0;
        const double d = testmesh::bbox_diagonal(bunny.positions);
        const auto match = testmesh::match_positions(back.positions, bunny.positions, d / 50, &err);
        CHECK(std::count(match.begin(), match.end(), UINT32_MAX) == 0);
        CHECK(err <= 1e-5 * d);
    }
}

// ---------------------------------------------------------------------------
// Writers

TEST_CASE("mesh_io: write then read gives the same mesh", "[mesh_io]") {
    TempDir tmp;
    Mesh m = testmesh::irregular_closed(3);
    // Per-corner normals with a crease and UVs with a seam.
    for (std::size_t c = 0; c < 3 * m.triangles.size(); ++c) {
        const Vec3 p = m.positions[m.triangles[c / 3][c % 3]];
        m.corner_normals.push_back(glm::normalize(p + Vec3(c % 7 == 0 ? 0.1 : 0.0, 0, 0)));
        m.corner_uvs.push_back(Vec2(p.x * 0.3 + 1.0 / 3.0, p.y + (c % 5 == 0)));
    }
    // OBJ keeps everything exactly (%.17g round-trips doubles).
    require_same(m, read_mesh([&] {
                     write_mesh(tmp.path("m.obj"), m);
                     return tmp.path("m.obj");
                 }()));

    Mesh plain = m;
    plain.corner_normals.clear();
    plain.corner_uvs.clear();
    write_mesh(tmp.path("m.off"), plain);
    require_same(plain, read_mesh(tmp.path("m.off")));
    write_mesh(tmp.path("m.ply"), plain);
    require_same(plain, read_mesh(tmp.path("m.ply")));

    // PLY stores per-vertex normals: a smooth mesh keeps them exactly.
    Mesh smooth = plain;
    for (std::size_t c = 0; c < 3 * smooth.triangles.size(); ++c)
        smooth.corner_normals.push_back(
            glm::normalize(smooth.positions[smooth.triangles[c / 3][c % 3]]));
    write_mesh(tmp.path("s.ply"), smooth);
    require_same(smooth, read_mesh(tmp.path("s.ply")));

    // STL is single precision and merges by position.
    write_mesh(tmp.path("m.stl"), plain);
    const Mesh stl = read_mesh(tmp.path("m.stl"));
    REQUIRE(stl.triangles.size() == plain.triangles.size());
    REQUIRE(stl.positions.size() == plain.positions.size());
    for (std::size_t t = 0; t < plain.triangles.size(); ++t)
        for (int c = 0; c < 3; ++c)
            for (int k = 0; k < 3; ++k)
                CHECK(stl.positions[stl.triangles[t][c]][k] ==
                      float_round(plain.positions[plain.triangles[t][c]][k]));
}

TEST_CASE("mesh_io: a subdivided mesh writes as its Mesh copy does, byte for byte", "[mesh_io]") {
    // write_mesh(SubdividedMesh) and write_mesh2 read the normals in place (per vertex, and
    // the corners that differ); to_mesh expands them to one per corner. The
    // files must be the same: smooth, creased (split corners), with given
    // normals and with UVs, for every scheme and format.
    TempDir tmp;
    const Mesh with_uvs = mesh_from_arrays(testmesh::patch_split_sphere(3, true), "sphere");
    REQUIRE(with_uvs.has_uvs());
    const std::vector<std::pair<const char*, Mesh>> meshes = {
        {"icosphere", testmesh::icosphere(1)}, {"cube", testmesh::faceted_cube()},
        {"cylinder", testmesh::split_normal_cylinder(6, 1.0, 1.0)}, {"open", testmesh::open_grid(3)},
        {"uvs", with_uvs}};
    std::size_t compared = 0, with_split_corners = 0;
    for (const auto& [name, mesh] : meshes)
        for (const SchemeKind scheme : {SchemeKind::normal, SchemeKind::loop, SchemeKind::butterfly})
            for (int levels = 0; levels <= 2; ++levels) {
                const SubdividedMesh sub = subdivide_uniform(mesh, scheme, levels);
                with_split_corners += sub.split_corners.empty() ? 0 : 1;
                const Mesh copy = to_mesh(sub);
                for (const char* ext : {"obj", "ply", "off", "stl"}) {
                    const std::string a = tmp.path(std::string("copy.") + ext);
                    const std::string b = tmp.path(std::string("direct.") + ext);
                    write_mesh(a, copy);
                    write_mesh(b, sub);
                    INFO(name << " " << scheme_name(scheme) << " level " << levels << " " << ext);
                    CHECK(file_bytes(a) == file_bytes(b));
                    ++compared;
                }
                // mesh2: streamed from the subdivided mesh, the text mesh2_text builds.
                write_mesh2(tmp.path("direct.inc"), sub, "M");
                INFO(name << " " << scheme_name(scheme) << " level " << levels << " mesh2");
                CHECK(file_bytes(tmp.path("direct.inc")) == mesh2_text(copy, "M"));
                ++compared;
            }
    CHECK(compared == 5 * 3 * 3 * 5);
    CHECK(with_split_corners > 0);  // the creased meshes exercise the split corners

    // Values a subdivision can overflow to are refused, naming the file.
    SubdividedMesh bad = subdivide_uniform(testmesh::icosphere(0), SchemeKind::loop, 1);
    bad.positions[3].y = std::numeric_limits<double>::infinity();
    CHECK_THROWS_WITH(write_mesh(tmp.path("bad.ply"), bad), Catch::Contains("bad.ply: vertex 3 is not finite"));
    CHECK_FALSE(fs::exists(tmp.path("bad.ply")));
}

TEST_CASE("mesh_io: a failed write throws and leaves no partial output", "[mesh_io]") {
    TempDir tmp;
    const Mesh m = testmesh::icosahedron();
    const std::string missing_dir = tmp.path("no/such/dir/out.obj");
    try {
        write_mesh(missing_dir, m);
        FAIL("no MeshError");
    } catch (const MeshError& e) {
        CHECK(std::string(e.what()).find(missing_dir) != std::string::npos);
    }
    CHECK_THROWS_AS(write_mesh(tmp.path("out.xyz"), m), MeshError);

    // An invalid mesh is refused before the existing file is touched.
    write_mesh(tmp.path("keep.obj"), m);
    Mesh bad = m;
    bad.triangles[0][0] = 99;
    CHECK_THROWS_AS(write_mesh(tmp.path("keep.obj"), bad), MeshError);
    require_same(m, read_mesh(tmp.path("keep.obj")));
    // Only the good file is there: no temporaries left behind.
    std::size_t files = 0;
    for (const auto& entry : fs::directory_iterator(tmp.dir)) {
        (void)entry;
        ++files;
    }
    CHECK(files == 1);
}

TEST_CASE("mesh_io: mesh2 text: sections, deduplication, identifiers", "[mesh_io]") {
    Mesh m = testmesh::icosahedron();
    const std::string plain = mesh2_text(m, "Ico");
    CHECK(plain.find("#declare Ico = mesh2 {") != std::string::npos);
    CHECK(plain.find("vertex_vectors {\n    12,") != std::string::npos);
    CHECK(plain.find("face_indices {\n    20,") != std::string::npos);
    CHECK(plain.find("normal_vectors") == std::string::npos);
    CHECK(plain.find("uv_vectors") == std::string::npos);

    // Smooth normals: one per vertex after deduplication; one shared uv.
    for (std::size_t c = 0; c < 60; ++c) {
        m.corner_normals.push_back(m.positions[m.triangles[c / 3][c % 3]]);
        m.corner_uvs.push_back(Vec2(0.25, 0.5));
    }
    const std::string full = mesh2_text(m, "Ico");
    CHECK(full.find("normal_vectors {\n    12,") != std::string::npos);
    CHECK(full.find("uv_vectors {\n    1,\n    <0.25, 0.5>\n  }") != std::string::npos);
    CHECK(full.find("normal_indices {\n    20,") != std::string::npos);
    CHECK(full.find("uv_indices {\n    20,\n    <0, 0, 0>") != std::string::npos);
    // Full precision: the first coordinate round-trips.
    char expect[64];
    std::snprintf(expect, sizeof expect, "<%.17g, ", m.positions[0].x);
    CHECK(full.find(expect) != std::string::npos);
    // Section order as POV-Ray requires.
    CHECK(full.find("vertex_vectors") < full.find("normal_vectors"));
    CHECK(full.find("normal_vectors") < full.find("uv_vectors"));
    CHECK(full.find("uv_vectors") < full.find("face_indices"));
    CHECK(full.find("face_indices") < full.find("normal_indices"));
    CHECK(full.find("normal_indices") < full.find("uv_indices"));

    CHECK_THROWS_AS(mesh2_text(m, "1abc"), std::invalid_argument);
    CHECK(is_pov_identifier("Bunny_2"));
    CHECK_FALSE(is_pov_identifier("_x"));
    CHECK_FALSE(is_pov_identifier("a-b"));
    CHECK(pov_identifier("bunny_lowpoly") == "Bunny_lowpoly");
    CHECK(pov_identifier("my mesh-v2") == "My_mesh_v2");
    CHECK(pov_identifier("3d") == "Mesh_3d");
    CHECK(pov_identifier("") == "Mesh_");
    CHECK(is_pov_identifier(pov_identifier(std::string(100, '#'))));
}

// ---------------------------------------------------------------------------
// Bad input: each gives a MeshError "<path>: <reason>"

TEST_CASE("mesh_io: missing and empty files", "[mesh_io]") {
    TempDir tmp;
    require_error(tmp.path("missing.obj"), "cannot open");
    for (const char* name : {"e.obj", "e.off", "e.ply", "e.stl"})
        require_error(tmp.write(name, ""), "empty file");
    require_error(tmp.write("blank.obj", "\n\n  \n# only a comment\n"), "no faces");
}

TEST_CASE("mesh_io: a directory named like a mesh file says so", "[mesh_io]") {
    TempDir tmp;
    for (const char* name : {"x.obj", "x.off", "x.ply", "x.stl"}) {
        fs::create_directory(tmp.path(name));
        try {
            read_mesh(tmp.path(name));
            FAIL("no MeshError");
        } catch (const MeshError& e) {
            CHECK(std::string(e.what()) == tmp.path(name) + ": is a directory");
        }
    }
}

TEST_CASE("mesh_io: PLY header lines off the spec are skipped with a warning", "[mesh_io]") {
    TempDir tmp;
    const std::string body =
        "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
        "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
        "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    const Mesh plain = read_mesh(tmp.write("plain.ply", "ply\nformat ascii 1.0\n" + body));
    // What exporters write in the wild: a banner without "comment" (assimp),
    // obj_info (CloudCompare), a blank line, CRLF line ends and a leading space.
    const std::string odd =
        " ply\r\nformat ascii 1.0\r\ncomment Created by Blender\r\n"
        "Created by Open Asset Import Library - http://assimp.sf.net (v3.0.1270)\r\n"
        "obj_info Generated by CloudCompare!\r\n\r\nunknown_keyword 1 2 3\r\n" + body;
    std::vector<std::string> warnings;
    const std::string path = tmp.write("odd.ply", odd);
    const Mesh m = read_mesh(path, &warnings);
    CHECK(m.positions == plain.positions);
    CHECK(m.triangles == plain.triangles);
    REQUIRE(warnings.size() == 1);
    CHECK(warnings[0] == path + ": skipped 2 non-standard PLY header line(s) (first: line 4: "
                                "'Created')");
    // A line that may be a misspelt layout line leaves the data ambiguous.
    for (const char* bad : {"elements edge 3\n", "Property float w\n", "formats ascii\n"})
        require_error(tmp.write("bad.ply", std::string("ply\nformat ascii 1.0\n") + bad + body),
                      "misspelt element, property or format line");
}

TEST_CASE("mesh_io: truncated files", "[mesh_io]") {
    TempDir tmp;
    require_error(tmp.write("t.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n"),
                  "truncated");
    require_error(tmp.write("t2.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1"), "truncated");
    require_error(tmp.write("t.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2"), "at least 3");
    require_error(tmp.write("t2.obj", "v 0 0 0\nv 1 0 0\nv 0 1"), "truncated");
    require_error(tmp.write("t3.obj", "v 0 0 0\nv 1 0 0\nv 0 1\nf 1 2 3\n"), "too few values");

    const Mesh ico = testmesh::icosahedron();
    std::vector<Vec3> normals(ico.positions);
    for (const char* format : {"ascii", "binary_little_endian"}) {
        std::string full = ply(ico, normals, format);
        require_error(
            tmp.write(std::string("cut_") + format + ".ply", full.substr(0, full.size() - 10)),
            "truncated");
        const std::size_t header = full.find("end_header\n") + 11;
        require_error(tmp.write(std::string("header_") + format + ".ply", full.substr(0, header)),
                      "truncated");
        require_error(
            tmp.write(std::string("noend_") + format + ".ply", full.substr(0, header - 8)),
            "end_header");
    }
    const std::string bin = binary_stl(ico);
    require_error(tmp.write("cut_bin.stl", bin.substr(0, bin.size() - 7)), "truncated");
    const std::string asc = ascii_stl(ico);
    require_error(tmp.write("cut_asc.stl", asc.substr(0, asc.size() / 2)), "truncated");
    require_error(tmp.write("noend.stl", asc.substr(0, asc.find("endsolid"))), "endsolid");
    require_error(tmp.write("short.stl", "abc"), "too short");
}

TEST_CASE("mesh_io: out-of-range and invalid indices", "[mesh_io]") {
    TempDir tmp;
    require_error(tmp.write("r.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n"), "out of range");
    require_error(tmp.write("r0.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n"), "index 0");
    require_error(tmp.write("rneg.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n"), "out of range");
    require_error(tmp.write("rvt.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/2 3/1\n"),
                  "out of range");
    require_error(tmp.write("rvn.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1//1 2//1 3//1\n"),
                  "out of range");
    require_error(tmp.write("bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x\n"), "bad face corner");
    require_error(tmp.write("big.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99999999999999999999\n"),
                  "bad face corner");
    require_error(tmp.write("r.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n"), "out of range");
    require_error(tmp.write("rn.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n"),
                  "out of range");
    std::string s =
        "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
        "property float y\nproperty float z\nelement face 1\n"
        "property list uchar int vertex_indices\nend_header\n";
    for (int i = 0; i < 9; ++i) put<float>(s, float(i == 3 || i == 7));
    put<std::uint8_t>(s, 3);
    for (std::int32_t i : {0, 1, 5}) put<std::int32_t>(s, i);
    require_error(tmp.write("r.ply", s), "out of range");
}

TEST_CASE("mesh_io: NaN and Inf coordinates are rejected", "[mesh_io]") {
    TempDir tmp;
    require_error(tmp.write("nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n"), "non-finite");
    require_error(tmp.write("inf.obj", "v 0 0 0\nv 1 0 0\nv 0 -inf 0\nf 1 2 3\n"), "non-finite");
    require_error(tmp.write("huge.obj", "v 0 0 0\nv 1e999 0 0\nv 0 1 0\nf 1 2 3\n"), "non-finite");
    require_error(tmp.write("nan.off", "OFF\n3 1 0\n0 0 0\n1 NaN 0\n0 1 0\n3 0 1 2\n"),
                  "non-finite");
    require_error(
        tmp.write("nan_n.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 nan\nf 1//1 2//1 3//1\n"),
        "non-finite");
    const Mesh ico = testmesh::icosahedron();
    std::vector<Vec3> normals(ico.positions);
    Mesh bad = ico;
    bad.positions[5].y = std::numeric_limits<double>::quiet_NaN();
    require_error(tmp.write("nan.ply", ply(bad, normals, "binary_little_endian")), "not finite");
    require_error(tmp.write("nan_a.ply", ply(bad, normals, "ascii")), "not finite");
    bad.positions[5].y = std::numeric_limits<double>::infinity();
    require_error(tmp.write("inf.stl", binary_stl(bad)), "not finite");
    require_error(tmp.write("inf_a.stl", ascii_stl(bad)), "non-finite");
}

TEST_CASE("mesh_io: absurd header counts are refused by comparing with the file size",
          "[mesh_io]") {
    // By design no reader reserves from a claimed count before checking that
    // the bytes after the header can hold it; these files are a few bytes long
    // and claim billions of elements, so the messages name the byte count.
    TempDir tmp;
    require_error(tmp.write("h.off", "OFF\n3000000000 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"),
                  "bytes follow");
    require_error(tmp.write("h2.off", "OFF\n3 2000000000 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"),
                  "bytes follow");
    require_error(tmp.write("h3.off", "OFF\n99999999999 1 0\n0 0 0\n"), "more than 2^32");
    require_error(tmp.write("h4.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2000000000 0 1 2\n"),
                  "more than the file holds");
    const std::string head =
        "ply\nformat %s 1.0\nelement vertex 4000000000\nproperty float x\nproperty float y\n"
        "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
    for (const char* format : {"ascii", "binary_little_endian"}) {
        char buf[512];
        std::snprintf(buf, sizeof buf, head.c_str(), format);
        require_error(tmp.write(std::string("h_") + format + ".ply",
                                std::string(buf) + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"),
                      "bytes follow");
    }
    // A face list length that the rest of the file cannot hold.
    std::string s =
        "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
        "property float y\nproperty float z\nelement face 1\n"
        "property list int int vertex_indices\nend_header\n";
    for (int i = 0; i < 9; ++i) put<float>(s, float(i == 3 || i == 7));
    put<std::int32_t>(s, 2000000000);
    for (std::int32_t i : {0, 1, 2}) put<std::int32_t>(s, i);
    require_error(tmp.write("hl.ply", s), "more than the file holds");

    std::string stl(80, ' ');
    put<std::uint32_t>(stl, 4000000000u);
    stl += std::string(50, '\0');
    require_error(tmp.write("h.stl", stl), "claims 4000000000 triangles");
}

TEST_CASE("mesh_io: files without faces", "[mesh_io]") {
    TempDir tmp;
    require_error(tmp.write("z.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n"), "no faces");
    require_error(tmp.write("z.off", "OFF\n3 0 0\n0 0 0\n1 0 0\n0 1 0\n"), "no faces");
    require_error(tmp.write("z.ply",
                            "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
                            "property float y\nproperty float z\nelement face 0\n"
                            "property list uchar int vertex_indices\nend_header\n0 0 0\n"),
                  "no faces");
    std::string stl(80, ' ');
    put<std::uint32_t>(stl, 0);
    require_error(tmp.write("z.stl", stl), "no faces");
    require_error(tmp.write("za.stl", "solid x\nendsolid x\n"), "no faces");
    // Only triangles that repeat a vertex: nothing left.
    require_error(tmp.write("rep.obj", "v 0 0 0\nv 1 0 0\nf 1 2 2\nf 1 1 2\n"), "no faces left");
    require_error(tmp.write("notoff.off", "PLY\n"), "not an OFF file");
    require_error(tmp.write("notply.ply", "OFF\n"), "not a PLY file");
}

// ---------------------------------------------------------------------------
// mesh_from_arrays and validate_mesh

TEST_CASE("mesh_io: mesh_from_arrays validates and drops repeated-vertex triangles", "[mesh_io]") {
    MeshArrays a;
    a.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
    a.face_indices = {{0, 1, 2}, {1, 1, 3}, {1, 3, 2}};
    std::vector<std::string> warnings;
    const Mesh m = mesh_from_arrays(a, "mesh2", &warnings);
    REQUIRE(m.triangles.size() == 2);
    CHECK(m.triangles[1] == Triangle{1, 3, 2});
    REQUIRE(warnings.size() == 1);
    CHECK(warnings[0].find("mesh2: dropped 1 triangle") == 0);

    // Separate normal and uv indices.
    a.normals = {{0, 0, 1}, {0, 0, -1}};
    a.normal_indices = {{0, 0, 0}, {0, 0, 0}, {1, 1, 1}};
    a.uvs = {{0, 0}, {1, 0}, {0, 1}, {1, 1}};
    const Mesh n = mesh_from_arrays(a, "mesh2");
    REQUIRE(n.corner_normals.size() == 6);
    CHECK(n.corner_normals[3] == Vec3(0, 0, -1));
    REQUIRE(n.corner_uvs.size() == 6);  // uv indices = face indices
    CHECK(n.corner_uvs[4] == Vec2(1, 1));
    CHECK_NOTHROW(validate_mesh(n, "x"));

    auto expect_error = [](const MeshArrays& arrays, const std::string& word) {
        try {
            mesh_from_arrays(arrays, "mesh2");
            FAIL("no MeshError for " << word);
        } catch (const MeshError& e) {
            const std::string msg = e.what();
            INFO(msg);
            CHECK(msg.rfind("mesh2: ", 0) == 0);
            CHECK(msg.find(word) != std::string::npos);
        }
    };
    MeshArrays b = a;
    b.face_indices[0][2] = 4;
    expect_error(b, "out of range");
    b = a;
    b.face_indices[0][2] = -1;
    expect_error(b, "out of range");
    b = a;
    b.normal_indices[2][0] = 2;
    expect_error(b, "normal index");
    b = a;
    b.normal_indices.pop_back();
    expect_error(b, "normal_indices has 2");
    b = a;
    b.positions[3].z = std::numeric_limits<double>::infinity();
    expect_error(b, "not finite");
    b = a;
    b.uvs[0].x = std::nan("");
    expect_error(b, "not finite");
    b = a;
    b.face_indices.clear();
    expect_error(b, "no faces");
    b = a;
    b.normals.clear();
    expect_error(b, "normal_indices given without");

    Mesh bad = n;
    bad.corner_normals.pop_back();
    CHECK_THROWS_AS(validate_mesh(bad, "x"), MeshError);
    bad = n;
    bad.triangles[0] = {1, 2, 1};
    CHECK_THROWS_AS(validate_mesh(bad, "x"), MeshError);
    bad = n;
    bad.triangles.clear();
    CHECK_THROWS_AS(validate_mesh(bad, "x"), MeshError);
}

TEST_CASE("mesh_io: mesh_bounds covers the used vertices only", "[mesh_io]") {
    Mesh m = testmesh::icosahedron();
    m.positions.push_back(Vec3(100, 100, 100));  // unreferenced
    const Bounds3 b = mesh_bounds(m);
    CHECK(b.hi.x < 1.0);
    CHECK(b.lo.x > -1.0);
    CHECK(b.hi.x == Approx(0.8506508083520399));
}

// ---------------------------------------------------------------------------
// analyze_mesh

TEST_CASE("mesh_io: analyze_mesh counts what the schemes will see", "[mesh_io][report]") {
    const MeshReport ico = analyze_mesh(testmesh::icosahedron());
    CHECK(ico.closed);
    CHECK(ico.vertices == 12);
    CHECK(ico.faces == 20);
    CHECK(ico.edges == 30);
    CHECK(ico.components == 1);
    CHECK(ico.min_valence == 5);
    CHECK(ico.max_valence == 5);
    REQUIRE(ico.valence_histogram.size() == 6);
    CHECK(ico.valence_histogram[5] == 12);
    CHECK(ico.boundary_edges + ico.nonmanifold_edges + ico.degenerate_faces + ico.duplicate_faces +
              ico.unreferenced_vertices + ico.singular_vertices ==
          0);

    // Open grid: boundary edges = perimeter.
    const MeshReport grid = analyze_mesh(testmesh::open_grid(4));
    CHECK_FALSE(grid.closed);
    CHECK(grid.boundary_edges == 16);

    // A fin: three triangles on one edge, a duplicate, an unreferenced vertex.
    Mesh fin;
    fin.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {9, 9, 9}};
    fin.triangles = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}, {2, 1, 0}};
    const MeshReport f = analyze_mesh(fin);
    CHECK(f.nonmanifold_edges == 1);
    CHECK(f.duplicate_faces == 1);
    CHECK(f.unreferenced_vertices == 1);
    CHECK(f.singular_vertices == 2);
    CHECK(f.boundary_edges == 4);
    CHECK_FALSE(f.closed);

    // Bowtie: two triangles sharing only a vertex, two fans there.
    Mesh bowtie;
    bowtie.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {-1, 0, 0}, {-1, -1, 0}};
    bowtie.triangles = {{0, 1, 2}, {0, 3, 4}};
    const MeshReport bt = analyze_mesh(bowtie);
    CHECK(bt.singular_vertices == 1);
    CHECK(bt.components == 1);

    // Degenerate triangles, found exactly at a 1e6 offset.
    const MeshReport z = analyze_mesh(testmesh::zero_area_mesh());
    CHECK(z.degenerate_faces >= 1);
    const double o = 1e6;
    CHECK(is_degenerate_triangle({o, o, o}, {o + 1, o + 2, o + 3}, {o + 2, o + 4, o + 6}));
    CHECK(is_degenerate_triangle({0, 0, 0}, {1, 1, 1}, {1, 1, 1}));
    CHECK_FALSE(is_degenerate_triangle({o, o, o}, {o + 1, o + 2, o + 3},
                                       {o + 2, o + 4, o + 6 + std::ldexp(1.0, -30)}));
    CHECK_FALSE(is_degenerate_triangle({0, 0, 0}, {1e-200, 0, 0}, {0, 1e-200, 0}));
    CHECK(analyze_mesh(testmesh::sliver_mesh()).degenerate_faces == 0);
}

TEST_CASE("mesh_io: a PLY list count beyond any integer is refused, not converted",
          "[mesh_io][fuzz]") {
    // Found by fuzzing: a float list count of 3e29 was cast to int64 (undefined).
    TempDir tmp;
    for (const char* count : {"3e29", "1e300", "inf", "4294967296"}) {
        const std::string text = std::string("ply\nformat ascii 1.0\nelement vertex 3\n") +
                                 "property float x\nproperty float y\nproperty float z\n"
                                 "element face 1\nproperty list float int vertex_indices\n"
                                 "end_header\n0 0 0\n1 0 0\n0 1 0\n" + count + " 0 1 2\n";
        INFO(count);
        require_error(tmp.write("huge_list.ply", text), "items, more than the file holds");
    }
}

TEST_CASE("mesh_io: the fuzz seeds and pinned fuzz regressions read or fail cleanly",
          "[mesh_io][fuzz]") {
    // tests/fuzz/{corpus,regressions}/read_<format>/*: each input must give a
    // valid Mesh or a MeshError naming it, welded or not (what the harnesses assert).
    const fs::path fuzz = fs::path(SUBDIVTRACE_TEST_DATA) / ".." / "fuzz";
    TempDir tmp;
    std::size_t inputs = 0;
    for (const char* kind : {"corpus", "regressions"})
        for (const char* format : {"obj", "off", "ply", "stl"}) {
            const fs::path dir = fuzz / kind / (std::string("read_") + format);
            if (!fs::is_directory(dir)) continue;
            for (const auto& entry : fs::directory_iterator(dir)) {
                // Copied under the format's extension, which read_mesh dispatches on.
                const std::string path = tmp.path("input." + std::string(format));
                fs::copy_file(entry.path(), path, fs::copy_options::overwrite_existing);
                INFO(entry.path().string());
                ++inputs;
                for (const bool weld : {true, false}) {
                    try {
                        const Mesh m = read_mesh(path, nullptr, WeldOptions{weld, 0.0});
                        CHECK_NOTHROW(validate_mesh(m, path));
                    } catch (const MeshError& e) {
                        CHECK(std::string(e.what()).rfind(path + ": ", 0) == 0);
                    }
                }
            }
        }
    CHECK(inputs >= 10);
}
