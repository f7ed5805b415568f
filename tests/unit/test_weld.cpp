// Welding coincident vertices where a Mesh is built (mesh.h, WeldOptions): a
// sphere written like the Utah teapot (patches with their own copies of the
// seam vertices) must become the sphere with shared vertices, render the same
// in every scheme, keep its per-corner UVs, and stay closed for every ray.
#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <map>

#include <glm/geometric.hpp>

#include "subdivtrace/mesh_report.h"
#include "render/render_loop.h"
#include "subdivtrace/tracer.h"
#include "test_meshes.h"

using namespace subdivtrace;
using namespace subdivtrace::tools;  // the standalone renderer (Camera, render)

namespace {

constexpr int k_n = 4;  // quads per patch side: 6 * 2 * 16 = 192 triangles

Mesh build(const MeshArrays& arrays, const WeldOptions& weld, WeldReport* report = nullptr,
           std::vector<std::string>* warnings = nullptr) {
    return mesh_from_arrays(arrays, "sphere", warnings, weld, report);
}

WeldOptions no_weld() {
    WeldOptions w;
    w.enabled = false;
    return w;
}

Camera seam_camera() {
    // Looks at a cube corner of the patch layout, where three seams meet.
    Camera cam;
    cam.look_from = Vec3(2.1, 1.9, 2.3);
    cam.look_at = Vec3(0.0);
    cam.width = 80;
    cam.height = 60;
    return cam;
}

Image render_mesh(const Mesh& mesh, SchemeKind scheme, RenderStats& rs) {
    const Camera cam = seam_camera();
    SurfaceOptions o;
    o.scheme = scheme;
    o.max_level = 5;
    o.view.camera = cam.look_from;
    o.view.pixel_angle = cam.pixel_angle();
    const AdaptiveSurface surface(mesh, o);
    RenderOptions ro;
    ro.threads = 2;
    return render([&](const Ray& r, Hit& h) { return surface.intersect(r, h); }, cam, ro,
                  surface.bounds(), rs);
}

std::size_t differing_pixels(const Image& a, const Image& b) {
    std::size_t n = 0;
    for (std::size_t p = 0; p < a.rgb.size(); p += 3)
        n += a.rgb[p] != b.rgb[p] || a.rgb[p + 1] != b.rgb[p + 1] || a.rgb[p + 2] != b.rgb[p + 2];
    return n;
}

}  // namespace

TEST_CASE("weld: a patch-split sphere becomes the sphere with shared vertices", "[weld]") {
    const MeshArrays split = testmesh::patch_split_sphere(k_n, false);
    const MeshArrays shared = testmesh::patch_split_sphere(k_n, true);
    // Counts from the layout alone: 6 (n+1)^2 written, 6 n^2 + 2 distinct.
    REQUIRE(split.positions.size() == 6 * (k_n + 1) * (k_n + 1));
    REQUIRE(shared.positions.size() == 6 * k_n * k_n + 2);

    WeldReport report;
    std::vector<std::string> warnings;
    const Mesh welded = build(split, WeldOptions{}, &report, &warnings);
    const Mesh reference = build(shared, no_weld());
    CHECK(report.welded_vertices == split.positions.size() - shared.positions.size());
    CHECK(report.collapsed_triangles == 0);
    CHECK(warnings.empty());
    // Same vertices in the same order, same triangles: welding numbers vertices
    // by first appearance, as the lattice-built reference does.
    CHECK(welded.positions == reference.positions);
    CHECK(welded.triangles == reference.triangles);

    const MeshReport r = analyze_mesh(welded);
    CHECK(r.components == 1);
    CHECK(r.boundary_edges == 0);
    CHECK(r.closed);
    // Without welding: six separate patches, each with a boundary of 4n edges.
    const MeshReport torn = analyze_mesh(build(split, no_weld()));
    CHECK(torn.components == 6);
    CHECK(torn.boundary_edges == 6 * 4 * k_n);
    CHECK(torn.vertices == split.positions.size());
}

TEST_CASE("weld: the welded sphere renders pixel-identically to the shared one, every scheme",
          "[weld][tracer]") {
    const MeshArrays split = testmesh::patch_split_sphere(k_n, false);
    const Mesh welded = build(split, WeldOptions{});
    const Mesh shared = build(testmesh::patch_split_sphere(k_n, true), no_weld());
    const Mesh torn = build(split, no_weld());
    for (SchemeKind scheme : {SchemeKind::normal, SchemeKind::loop, SchemeKind::butterfly}) {
        RenderStats rs_welded, rs_shared, rs_torn;
        const Image a = render_mesh(welded, scheme, rs_welded);
        const Image b = render_mesh(shared, scheme, rs_shared);
        const Image c = render_mesh(torn, scheme, rs_torn);
        const std::size_t torn_diff = differing_pixels(c, b);
        WARN(scheme_name(scheme) << ": " << rs_welded.hit_pixels << " of 4800 pixels hit, "
                                 << differing_pixels(a, b) << " differ welded vs shared, "
                                 << torn_diff << " differ unwelded vs shared");
        CHECK(rs_welded.hit_pixels == rs_shared.hit_pixels);
        CHECK(rs_welded.hit_pixels > 1500);
        CHECK(differing_pixels(a, b) == 0);
        // The seams do show without welding (else this test could not fail).
        CHECK(torn_diff > 20);
    }
}

TEST_CASE("weld: UV seams keep every corner's UV exactly", "[weld]") {
    const MeshArrays split = testmesh::patch_split_sphere(k_n, false);
    const Mesh welded = build(split, WeldOptions{});
    REQUIRE(welded.triangles.size() == split.face_indices.size());
    REQUIRE(welded.corner_uvs.size() == 3 * split.face_indices.size());
    std::size_t seam_corners = 0;
    for (std::size_t f = 0; f < split.face_indices.size(); ++f)
        for (int c = 0; c < 3; ++c) {
            const std::int64_t v = split.face_indices[f][c];
            CHECK(welded.corner_uvs[3 * f + c] == split.uvs[static_cast<std::size_t>(v)]);
            CHECK(welded.positions[welded.triangles[f][c]] ==
                  split.positions[static_cast<std::size_t>(v)]);
            seam_corners += welded.triangles[f][c] != static_cast<std::uint32_t>(v);
        }
    CHECK(seam_corners > 0);  // some corners did move to a welded vertex

    // At max_level 0 the welded and unwelded spheres draw the same triangles:
    // every camera ray finds the same point and the same UV.
    const Mesh torn = build(split, no_weld());
    const Camera cam = seam_camera();
    SurfaceOptions o;
    o.max_level = 0;
    o.view.camera = cam.look_from;
    o.view.pixel_angle = cam.pixel_angle();
    const AdaptiveSurface s_welded(welded, o), s_torn(torn, o);
    std::size_t hits = 0, uv_mismatch = 0;
    for (int y = 0; y < cam.height; ++y)
        for (int x = 0; x < cam.width; ++x) {
            Hit hw, ht;
            const bool a = s_welded.intersect(cam.ray(x, y), hw);
            const bool b = s_torn.intersect(cam.ray(x, y), ht);
            REQUIRE(a == b);
            if (!a) continue;
            ++hits;
            uv_mismatch += hw.uv != ht.uv || hw.t != ht.t;
        }
    CHECK(hits > 1500);
    CHECK(uv_mismatch == 0);
}

TEST_CASE("weld: near-coincident vertices only with a tolerance, collapsed faces dropped",
          "[weld]") {
    // Move every seam copy after the first by 1e-9 or 2e-9 per axis: exact
    // welding keeps the patches apart, a relative tolerance of 1e-7 joins them.
    MeshArrays split = testmesh::patch_split_sphere(k_n, false);
    const Mesh exact_before = build(split, WeldOptions{});
    std::map<std::array<double, 3>, int> copies;  // k-th copy moves by k * 1e-9
    for (Vec3& p : split.positions) {
        const int k = copies[{p.x, p.y, p.z}]++;
        if (k > 0) p += Vec3(1e-9, -1e-9, 1e-9) * double(k);
    }
    WeldReport exact, near;
    const Mesh apart = build(split, WeldOptions{}, &exact);
    CHECK(exact.welded_vertices == 0);
    CHECK(analyze_mesh(apart).components == 6);
    WeldOptions tol;
    tol.relative_tolerance = 1e-7;  // of the diagonal 2 sqrt(3): 3.5e-7 > 2e-9 sqrt(3)
    const Mesh joined = build(split, tol, &near);
    CHECK(near.welded_vertices ==
          split.positions.size() - testmesh::patch_split_sphere(k_n, true).positions.size());
    CHECK(analyze_mesh(joined).closed);
    CHECK(joined.positions == exact_before.positions);  // first occurrences kept, exactly

    // A triangle whose corners fall within the tolerance collapses: dropped, counted.
    MeshArrays a;
    a.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1e-12, 0, 0),
                   Vec3(0, 0, 1e-12)};
    a.face_indices = {{0, 1, 2}, {0, 3, 4}, {3, 2, 1}};
    std::vector<std::string> warnings;
    WeldReport r;
    const Mesh m = mesh_from_arrays(a, "tiny", &warnings, tol, &r);
    CHECK(m.triangles.size() == 2);
    CHECK(r.collapsed_triangles == 1);
    CHECK(r.welded_vertices == 2);
    REQUIRE(warnings.size() == 1);
    CHECK_THAT(warnings[0], Catch::Contains("tiny: dropped 1 triangle(s) that collapsed when "
                                            "welding coincident vertices (first: face 1)"));
    // Exact welding leaves them apart (distinct positions).
    CHECK(mesh_from_arrays(a, "tiny").triangles.size() == 3);
}

TEST_CASE("weld: exact welding joins -0 and +0, never neighbours, chains do not collapse",
          "[weld]") {
    MeshArrays a;
    a.positions = {Vec3(0.0, 1, 0), Vec3(1, 0, 0), Vec3(0, 0, 1),
                   Vec3(-0.0, 1, 0), Vec3(0, 0, std::nextafter(1.0, 2.0))};
    a.face_indices = {{0, 1, 2}, {3, 4, 1}};
    WeldReport r;
    const Mesh m = mesh_from_arrays(a, "zeros", nullptr, WeldOptions{}, &r);
    CHECK(r.welded_vertices == 1);  // -0 joins +0; the next double up does not
    REQUIRE(m.triangles.size() == 2);
    CHECK(m.triangles[1][0] == 0);
    CHECK(m.triangles[1][1] == 3);

    // Points 0.6 tolerance apart in a row: each joins the first representative
    // within reach, so the chain splits into pairs instead of one vertex.
    MeshArrays chain;
    for (int i = 0; i < 6; ++i) chain.positions.push_back(Vec3(0.6 * i, 0, 0));
    chain.positions.push_back(Vec3(0, 5, 0));
    chain.face_indices = {{0, 2, 6}, {1, 4, 6}, {3, 5, 6}};
    // Diagonal of (0,0,0)..(3,5,0) = sqrt(34); tolerance 1.0 absolute.
    WeldOptions w;
    w.relative_tolerance = 1.0 / std::sqrt(34.0);
    WeldReport rc;
    const Mesh c = mesh_from_arrays(chain, "chain", nullptr, w, &rc);
    CHECK(rc.welded_vertices == 3);  // 0-1, 2-3, 4-5 (0.6 <= 1 < 1.2)
    CHECK(c.positions.size() == 4);

    WeldOptions bad;
    bad.relative_tolerance = -1.0;
    CHECK_THROWS_WITH(mesh_from_arrays(chain, "chain", nullptr, bad),
                      Catch::Contains("chain: weld tolerance must be finite and >= 0"));
}
