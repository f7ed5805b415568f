// The `subdivtrace` CLI as a user runs it: exit codes (0 ok, 1 bad input naming
// the file, 2 usage error), and outputs read back with read_mesh.
#include <catch2/catch.hpp>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include <sys/wait.h>
#include <unistd.h>

#include "subdivtrace/mesh_io.h"
#include "test_meshes.h"

namespace fs = std::filesystem;
using namespace subdivtrace;

namespace {

struct Result {
    int code = -1;
    std::string out;
    std::string err;
};

std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

/// Single-quotes an argument for /bin/sh.
std::string shell_quote(const std::string& s) {
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

struct Sandbox {
    fs::path dir;
    Sandbox() {
        static int counter = 0;
        dir = fs::temp_directory_path() /
              ("subdivtrace_cli_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
        fs::remove_all(dir);
        fs::create_directories(dir);
    }
    ~Sandbox() {
        std::error_code ec;
        fs::remove_all(dir, ec);
    }
    std::string path(const std::string& name) const { return (dir / name).string(); }
    std::string write(const std::string& name, const std::string& text) const {
        std::ofstream(dir / name, std::ios::binary) << text;
        return path(name);
    }

    /// Runs the CLI with `args`, capturing stdout, stderr and the exit code.
    Result run(const std::vector<std::string>& args) const {
        std::string cmd = shell_quote(SUBDIVTRACE_CLI);
        for (const std::string& a : args) cmd += " " + shell_quote(a);
        cmd += " >" + shell_quote(path("stdout.txt")) + " 2>" + shell_quote(path("stderr.txt"));
        const int status = std::system(cmd.c_str());
        Result r;
        r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
        r.out = slurp(dir / "stdout.txt");
        r.err = slurp(dir / "stderr.txt");
        return r;
    }
};

const std::string k_data = SUBDIVTRACE_TEST_DATA;
const std::string k_cube = k_data + "/cube.obj";  // 8 vertices, 12 triangles
const std::string k_quads = k_data + "/../../data/quad_blob.obj";

}  // namespace

TEST_CASE("cli: info prints the counts of a good mesh", "[cli]") {
    Sandbox box;
    const Result r = box.run({"info", k_cube});
    INFO(r.err);
    REQUIRE(r.code == 0);
    CHECK(r.out.find("vertices:              8\n") != std::string::npos);
    CHECK(r.out.find("triangles:             12\n") != std::string::npos);
    CHECK(r.out.find("closed:                yes\n") != std::string::npos);
    CHECK(r.err.empty());

    // Polygons: warnings on stderr, prefixed.
    const Result q = box.run({"info", k_quads});
    REQUIRE(q.code == 0);
    CHECK(q.err.rfind("warning: ", 0) == 0);
    CHECK(q.err.find("triangulated") != std::string::npos);
}

TEST_CASE("cli: bad input exits 1 naming the file", "[cli]") {
    Sandbox box;
    const std::string missing = box.path("missing.obj");
    const std::string huge = box.write("huge.off", "OFF\n3000000000 1 0\n0 0 0\n");
    const std::string empty = box.write("empty.stl", "");
    const std::string nan = box.write("nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n");
    for (const std::string& file : {missing, huge, empty, nan}) {
        for (const char* command : {"info", "subdivide", "export-mesh2"}) {
            std::vector<std::string> args = {command, file};
            if (std::string(command) != "info") {
                args.push_back("-o");
                args.push_back(box.path("out.obj"));
            }
            const Result r = box.run(args);
            INFO(command << " " << file << ": " << r.err);
            CHECK(r.code == 1);
            CHECK(r.err.find(file + ": ") != std::string::npos);
            CHECK_FALSE(fs::exists(box.path("out.obj")));
        }
    }
    // An output that cannot be written is bad input too, and leaves nothing.
    const std::string unwritable = box.path("no/such/dir/out.obj");
    const Result w = box.run({"subdivide", k_cube, "-o", unwritable});
    CHECK(w.code == 1);
    CHECK(w.err.find(unwritable) != std::string::npos);
    const Result x = box.run({"subdivide", k_cube, "-o", box.path("out.xyz")});
    CHECK(x.code == 1);
    CHECK(x.err.find("out.xyz") != std::string::npos);
}

TEST_CASE("cli: a directory named like a mesh is bad input, said so", "[cli]") {
    Sandbox box;
    fs::create_directory(box.path("x.obj"));
    for (const char* command : {"info", "stats"}) {
        const Result r = box.run({command, box.path("x.obj")});
        INFO(r.err);
        CHECK(r.code == 1);
        CHECK(r.err.find(box.path("x.obj") + ": is a directory") != std::string::npos);
    }
}

TEST_CASE("cli: a mesh of scale 1e-11 renders with the default camera", "[cli]") {
    Sandbox box;
    // The framing scales with the mesh, so every scale covers the pixels the
    // unit sphere covers (up to rays that graze the silhouette).
    long unit_hits = -1;
    for (double scale : {1.0, 1e-11, 1e-15, 1e11}) {
        const std::string file = box.path("scaled.obj");
        write_mesh(file, testmesh::offset_mesh(testmesh::icosphere(1), Vec3(0.0), scale));
        const Result r = box.run({"stats", file, "--width", "32", "--height", "24"});
        INFO("scale " << scale << ": " << r.err);
        REQUIRE(r.code == 0);
        const std::size_t at = r.out.find("\"hit_pixels\": ");
        REQUIRE(at != std::string::npos);
        const long hits = std::strtol(r.out.c_str() + at + 14, nullptr, 10);
        if (unit_hits < 0) unit_hits = hits;
        CHECK(hits > 80);
        CHECK(std::abs(hits - unit_hits) <= 2);
    }
}

TEST_CASE("cli: usage errors exit 2", "[cli]") {
    Sandbox box;
    const std::string out = box.path("out.obj");
    const std::vector<std::vector<std::string>> bad = {
        {"info"},
        {"info", k_cube, "--bogus"},
        {"info", k_cube, "-o", out},  // info has no output
        {"info", k_cube, k_cube},
        {"subdivide", k_cube},  // no -o
        {"subdivide", k_cube, "-o"},
        {"subdivide", k_cube, "-o", out, "--levels"},
        {"subdivide", k_cube, "-o", out, "--levels", "11"},
        {"subdivide", k_cube, "-o", out, "--levels", "-1"},
        {"subdivide", k_cube, "-o", out, "--levels", "two"},
        {"subdivide", k_cube, "-o", out, "--levels", "1.5"},
        {"subdivide", k_cube, "-o", out, "--scheme", "catmull"},
        {"subdivide", k_cube, "-o", out, "--name", "X"},  // only export-mesh2 has --name
        {"export-mesh2", k_cube, "-o", out, "--name", "9lives"},
        {"export-mesh2", k_cube, "-o", out, "--name", "a-b"},
        {"frobnicate", k_cube},
    };
    for (const auto& args : bad) {
        const Result r = box.run(args);
        std::string joined;
        for (const auto& a : args) joined += a + " ";
        INFO(joined << "-> " << r.err);
        CHECK(r.code == 2);
        CHECK_FALSE(r.err.empty());
        CHECK_FALSE(fs::exists(out));
    }
    for (const char* command : {"info", "subdivide", "export-mesh2"}) {
        const Result r = box.run({command, "--help"});
        CHECK(r.code == 0);
        CHECK(r.out.find("usage: subdivtrace") != std::string::npos);
    }
}

TEST_CASE("cli: info reports welded vertices, --no-weld and --weld EPS on every command",
          "[cli][weld]") {
    Sandbox box;
    // A sphere of 6 patches, each with its own copy of the seam vertices.
    WeldOptions keep;
    keep.enabled = false;
    const Mesh split =
        mesh_from_arrays(testmesh::patch_split_sphere(3, false), "sphere", nullptr, keep);
    REQUIRE(split.positions.size() == 96);  // 6 patches of 4 x 4; 56 distinct
    for (const char* ext : {"obj", "ply", "stl"}) {
        const std::string file = box.path(std::string("sphere.") + ext);
        write_mesh(file, split);
        const Result w = box.run({"info", file});
        INFO(file << ": " << w.err);
        REQUIRE(w.code == 0);
        // STL stores three vertices per facet: 3 * 108 - 56 of them are welded.
        const std::string welded = ext == std::string("stl") ? "268" : "40";
        CHECK(w.out.find("welded vertices:       " + welded + "\n") != std::string::npos);
        CHECK(w.out.find("vertices:              56\n") != std::string::npos);
        CHECK(w.out.find("components:            1\n") != std::string::npos);
        CHECK(w.out.find("boundary edges:        0\n") != std::string::npos);
        const Result n = box.run({"info", file, "--no-weld"});
        REQUIRE(n.code == 0);
        CHECK(n.out.find("welded vertices:       none (--no-weld)\n") != std::string::npos);
        CHECK(n.out.find(ext == std::string("stl") ? "components:            108\n"
                                                   : "components:            6\n") !=
              std::string::npos);
        const Result t = box.run({"info", file, "--weld=1e-6"});
        CHECK(t.code == 0);
        CHECK(t.out.find("components:            1\n") != std::string::npos);
    }
    const std::string obj = box.path("sphere.obj");
    const std::string out = box.path("out.obj");
    CHECK(box.run({"subdivide", obj, "-o", out, "--no-weld"}).code == 0);
    CHECK(read_mesh(out, nullptr, keep).positions.size() == 6 * 7 * 7);  // 6 patches of (2n + 1)^2
    CHECK(box.run({"subdivide", obj, "-o", out, "--weld", "0"}).code == 0);
    CHECK(read_mesh(out, nullptr, keep).positions.size() == 56 + 162);  // + one per edge
    CHECK(box.run({"export-mesh2", obj, "-o", box.path("s.inc"), "--no-weld"}).code == 0);
    CHECK(box.run({"stats", obj, "--no-weld", "--width", "8", "--height", "6"}).code == 0);
    CHECK(box.run({"stats", obj, "--weld", "1e-9", "--width", "8", "--height", "6"}).code == 0);
    for (const char* bad : {"-1", "abc", "0.5", "nan", ""}) {
        for (const char* command : {"info", "subdivide", "render", "stats"}) {
            const Result r = box.run({command, obj, "--weld", bad, "-o", out});
            INFO(command << " --weld '" << bad << "': " << r.err);
            CHECK(r.code == 2);
            CHECK(r.err.find("--weld") != std::string::npos);
        }
    }
    CHECK(box.run({"info", obj, "--weld"}).code == 2);
}

TEST_CASE("cli: subdivide --levels 2 of 12 triangles gives 192, every scheme", "[cli]") {
    Sandbox box;
    for (const char* scheme : {"normal", "loop", "butterfly"}) {
        for (const char* ext : {"obj", "ply", "off", "stl"}) {
            const std::string out = box.path(std::string("cube_") + scheme + "." + ext);
            const Result r =
                box.run({"subdivide", k_cube, "-o", out, "--scheme", scheme, "--levels", "2"});
            INFO(scheme << " " << ext << ": " << r.err);
            REQUIRE(r.code == 0);
            CHECK(r.err.find("12 triangles -> 192 triangles") != std::string::npos);
            const Mesh m = read_mesh(out);
            CHECK(m.triangles.size() == 192);
            CHECK(m.positions.size() == 98);  // V - E + F = 2: 8 + 18 + 72
        }
    }
    // Default: normal scheme, one level; --opt=value works too.
    const Result r = box.run({"subdivide", k_cube, "--output=" + box.path("d.obj")});
    REQUIRE(r.code == 0);
    CHECK(read_mesh(box.path("d.obj")).triangles.size() == 48);
    CHECK(r.err.find("(normal, 1 level)") != std::string::npos);
}

TEST_CASE("cli: export-mesh2 writes a mesh2 include", "[cli]") {
    Sandbox box;
    const std::string out = box.path("cube.inc");
    const Result r = box.run({"export-mesh2", k_cube, "-o", out});
    INFO(r.err);
    REQUIRE(r.code == 0);
    const std::string text = slurp(out);
    CHECK(text.find("#declare Cube = mesh2 {") != std::string::npos);
    CHECK(text.find("vertex_vectors {\n    8,") != std::string::npos);
    CHECK(text.find("face_indices {\n    12,") != std::string::npos);

    const Result n = box.run({"export-mesh2", k_cube, "-o", out, "--levels", "1", "--scheme",
                              "loop", "--name", "Smooth_cube"});
    REQUIRE(n.code == 0);
    const std::string sub = slurp(out);
    CHECK(sub.find("#declare Smooth_cube = mesh2 {") != std::string::npos);
    CHECK(sub.find("face_indices {\n    48,") != std::string::npos);
    CHECK(sub.find("normal_indices {\n    48,") != std::string::npos);
}

TEST_CASE("cli: stock POV-Ray renders the exported mesh2", "[cli][povray]") {
    if (std::system("command -v povray >/dev/null 2>&1") != 0) {
        WARN("povray not installed: skipped");
        return;
    }
    Sandbox box;
    const std::string inc = box.path("mesh.inc");
    REQUIRE(box.run({"export-mesh2", k_cube, "-o", inc, "--levels", "1", "--name", "M"}).code == 0);
    const std::string scene = box.write(
        "scene.pov", "#version 3.7;\nglobal_settings { assumed_gamma 1.0 }\n#include \"" + inc +
                         "\"\ncamera { location <2, 3, -4> look_at <0.5, 0.5, 0.5> }\n"
                         "light_source { <5, 10, -10> color rgb 1 }\n"
                         "object { M pigment { color rgb 1 } }\n");
    const std::string cmd = "cd " + shell_quote(box.dir.string()) + " && povray +I" +
                            shell_quote(scene) + " +O" + shell_quote(box.path("out.png")) +
                            " +W32 +H24 -D -V -GA >povray.log 2>&1";
    const int status = std::system(cmd.c_str());
    INFO(slurp(box.dir / "povray.log"));
    CHECK(WIFEXITED(status));
    CHECK(WEXITSTATUS(status) == 0);
    CHECK(fs::exists(box.path("out.png")));
}

namespace {

/// The pixels of `render --color-by level` per level, read back from its legend
/// ("  level  3: green  (rgb ...)  1214 pixels  48.3%").
std::map<int, long> legend_levels(const std::string& out) {
    std::map<int, long> pixels;
    std::istringstream in(out);
    std::string line;
    while (std::getline(in, line)) {
        int level = -1;
        long n = -1;
        char name[64];
        if (std::sscanf(line.c_str(), " level %d: %63[^(](rgb %*f %*f %*f) %ld pixels", &level,
                        name, &n) == 3)
            pixels[level] = n;
    }
    return pixels;
}

double mean_level(const std::map<int, long>& pixels) {
    double sum = 0.0, count = 0.0;
    for (const auto& [level, n] : pixels) sum += double(level) * n, count += n;
    return count > 0 ? sum / count : -1.0;
}

/// Pixels of a binary PPM (P6, 8-bit) that differ from its top-left pixel.
long pixels_unlike_corner(const std::string& ppm) {
    std::istringstream in(ppm);
    std::string magic;
    int w = 0, h = 0, maxval = 0;
    in >> magic >> w >> h >> maxval;
    in.get();
    REQUIRE(magic == "P6");
    REQUIRE(maxval == 255);
    std::string data(std::size_t(w) * h * 3, '\0');
    in.read(&data[0], static_cast<std::streamsize>(data.size()));
    REQUIRE(in.gcount() == static_cast<std::streamsize>(data.size()));
    long differ = 0;
    for (std::size_t p = 3; p < data.size(); p += 3)
        if (data.compare(p, 3, data, 0, 3) != 0) ++differ;
    return differ;
}

}  // namespace

TEST_CASE("cli: render --color-by level shows a far view using lower levels than a close-up",
          "[cli][render]") {
    Sandbox box;
    const std::string bunny = k_data + "/../../data/bunny_lowpoly.obj";  // ~2.5 units across
    auto render = [&](const std::string& from, const std::string& out,
                      std::vector<std::string> extra = {}) {
        std::vector<std::string> args = {"render", bunny, "-o", box.path(out), "--width", "96",
                                         "--height", "72", "--look-from", from, "--look-at",
                                         "0,0,0", "--no-shadows", "--quiet", "--threads", "2"};
        args.insert(args.end(), extra.begin(), extra.end());
        const Result r = box.run(args);
        INFO(r.err);
        REQUIRE(r.code == 0);
        return r.out;
    };
    // The paper's size rule: levels follow the distance alone.
    const std::string far = render("0,0,10", "far.ppm", {"--color-by", "level", "--refine", "size"});
    const std::string close = render("0,0,2", "close.ppm", {"--color-by", "level", "--refine", "size"});
    INFO("far:\n" << far << "close:\n" << close);
    const auto far_levels = legend_levels(far);
    const auto close_levels = legend_levels(close);
    REQUIRE_FALSE(far_levels.empty());
    REQUIRE_FALSE(close_levels.empty());
    // Five times closer: edges look five times longer, about log2(5) = 2.3 more levels.
    CHECK(mean_level(close_levels) > mean_level(far_levels) + 1.5);
    CHECK(close_levels.rbegin()->first > far_levels.rbegin()->first);

    // The legend counts exactly the pixels the image colours (the rest is background).
    long far_total = 0;
    for (const auto& [level, n] : far_levels) far_total += n;
    CHECK(far.find("over " + std::to_string(far_total) + " pixels") != std::string::npos);
    CHECK(pixels_unlike_corner(slurp(box.path("far.ppm"))) == far_total);

    // Without --color-by the render prints nothing on stdout.
    CHECK(render("0,0,10", "plain.ppm").empty());
    // The uniform baseline is one level everywhere.
    const auto uniform = legend_levels(
        render("0,0,10", "u2.ppm", {"--uniform", "2", "--color-by", "level"}));
    CHECK(uniform.size() == 1);
    CHECK(uniform.begin()->first == 2);
}

TEST_CASE("cli: render --color-by face counts the base faces seen", "[cli][render]") {
    Sandbox box;
    const Result r = box.run({"render", k_cube, "-o", box.path("cube.png"), "--width", "64",
                              "--height", "48", "--color-by", "face", "--quiet"});
    INFO(r.err);
    REQUIRE(r.code == 0);
    int faces = -1;
    const auto at = r.out.find("):");
    REQUIRE(at != std::string::npos);
    REQUIRE(std::sscanf(r.out.c_str() + at, "): %d faces seen", &faces) == 1);
    // The default camera sees three sides of the cube: 6 of its 12 triangles
    // (more may peek in at the silhouette of the smooth surface).
    CHECK(faces >= 6);
    CHECK(faces <= 12);
    CHECK(r.out.find("  face ") != std::string::npos);

    const Result bad = box.run({"render", k_cube, "-o", box.path("x.png"), "--color-by", "normal"});
    CHECK(bad.code == 2);
    CHECK(bad.err.find("--color-by must be level, face or error") != std::string::npos);
    CHECK_FALSE(fs::exists(box.path("x.png")));
}

TEST_CASE("cli: --refine error builds fewer nodes than size, and stats carry the bound",
          "[cli][render]") {
    Sandbox box;
    const std::string bunny = k_data + "/../../data/bunny_lowpoly.obj";
    auto stats = [&](const std::string& rule) {
        const Result r = box.run({"stats", bunny, "--width", "96", "--height", "72", "--look-from",
                                  "0,0,2", "--look-at", "0,0,0", "--refine", rule, "--threads", "2"});
        INFO(r.err);
        REQUIRE(r.code == 0);
        return r.out;
    };
    auto number = [](const std::string& json, const std::string& key) {
        const auto at = json.find("\"" + key + "\": ");
        REQUIRE(at != std::string::npos);
        return std::strtod(json.c_str() + at + key.size() + 4, nullptr);
    };
    const std::string error = stats("error"), size = stats("size");
    INFO("error:\n" << error << "size:\n" << size);
    CHECK(error.find("\"refine\": \"error\"") != std::string::npos);
    CHECK(size.find("\"refine\": \"size\"") != std::string::npos);
    CHECK(number(error, "nodes_built") < number(size, "nodes_built"));
    // The bound is a distance in pixels: positive where the surface is
    // curved, and the mean never above the largest.
    CHECK(number(error, "error_bound_px_max") > 0.0);
    CHECK(number(error, "error_bound_px_mean") <= number(error, "error_bound_px_max"));
    CHECK(number(error, "hits_at_max_level") == 0.0);
    // Tiles built are the cache's misses and the tiles built with them (a
    // base triangle's chunk, at most k_face_chunk_size per miss); their time is
    // a positive part of the work, and each node built costs it, spread evenly.
    CHECK(number(error, "tiles_built") >= number(error, "cache_misses"));
    CHECK(number(error, "tiles_built") <= 16 * number(error, "cache_misses"));
    CHECK(number(error, "tile_build_seconds") > 0.0);
    CHECK(number(error, "ns_per_node_built") ==
          Approx(number(error, "tile_build_seconds") * 1e9 / number(error, "nodes_built"))
              .epsilon(1e-6));
    CHECK(number(error, "cache_peak_bytes_per_node_built") > 0.0);
    const Result bad = box.run({"stats", bunny, "--refine", "fast"});
    CHECK(bad.code == 2);
    CHECK(bad.err.find("--refine must be error or size") != std::string::npos);
}

TEST_CASE("cli: render --color-by error bins every pixel by its certified bound", "[cli][render]") {
    Sandbox box;
    const std::string bunny = k_data + "/../../data/bunny_lowpoly.obj";
    const Result r = box.run({"render", bunny, "-o", box.path("err.ppm"), "--width", "80",
                              "--height", "60", "--color-by", "error", "--quiet", "--no-shadows"});
    INFO(r.err << r.out);
    REQUIRE(r.code == 0);
    CHECK(r.out.find("certified bound") != std::string::npos);
    // Each legend line ends in "N pixels P%": together they are the pixels the image colours.
    long total = 0;
    std::istringstream lines(r.out);
    for (std::string line; std::getline(lines, line);) {
        const auto rgb = line.find("(rgb ");
        if (rgb == std::string::npos) continue;
        total += std::strtol(line.c_str() + line.find(')', rgb) + 1, nullptr, 10);
    }
    CHECK(total > 0);
    CHECK(pixels_unlike_corner(slurp(box.path("err.ppm"))) == total);
}

TEST_CASE("cli: info counts creases, and Loop/Butterfly warn that given normals do not shape them",
          "[cli][creases]") {
    Sandbox box;
    const std::string cube = k_data + "/faceted_cube.obj";
    const Result info = box.run({"info", cube});
    REQUIRE(info.code == 0);
    CHECK(info.out.find("crease edges:          12\n") != std::string::npos);
    for (const char* scheme : {"loop", "butterfly"}) {
        const Result r = box.run({"subdivide", cube, "-o", box.path("out.obj"), "--levels", "1", "--scheme", scheme});
        INFO(r.err);
        REQUIRE(r.code == 0);
        CHECK(r.err.find("warning: " + cube + ": the " + scheme + " scheme computes its own normals") == 0);
        CHECK(r.err.find("12 crease edges") != std::string::npos);
    }
    const Result normal = box.run({"subdivide", cube, "-o", box.path("out.obj"), "--levels", "1"});
    REQUIRE(normal.code == 0);
    CHECK(normal.err.find("warning") == std::string::npos);
}
