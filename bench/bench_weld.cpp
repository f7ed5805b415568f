// The cost of welding coincident vertices on load (mesh.h, WeldOptions), as a
// share of reading: a ~1 M-triangle sphere of 6 patches whose seam vertices
// are written once per patch (like the Utah teapot's), read from binary PLY,
// OBJ and binary STL (a triangle soup: 3 vertices per facet to weld) with
// welding off, exact and with a tolerance. The files are written once into
// $TMPDIR (or /tmp) and kept for later runs. Peak memory: run one benchmark
// per process under /usr/bin/time -v (docs/mesh_input.md gives the figures):
//   bench_weld --benchmark_filter='read/ply/exact'
#include <array>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <benchmark/benchmark.h>
#include <glm/geometric.hpp>

#include "subdivtrace/mesh_io.h"

namespace {

using namespace subdivtrace;

constexpr int k_n = 289;  // 6 * 2 * 289^2 = 1,002,252 triangles

/// Six patches of k_n x k_n quads (two triangles each) on the unit sphere,
/// each with its own (k_n + 1)^2 vertices.
Mesh patch_split_sphere() {
    static const std::array<int, 3> axes[6] = {{0, 1, 2}, {0, 2, 1}, {1, 2, 0},
                                               {1, 0, 2}, {2, 0, 1}, {2, 1, 0}};
    Mesh m;
    for (int f = 0; f < 6; ++f) {
        const auto [axis, u, v] = axes[f];
        const auto base = static_cast<std::uint32_t>(m.positions.size());
        for (int j = 0; j <= k_n; ++j)
            for (int i = 0; i <= k_n; ++i) {
                Vec3 c(0.0);
                c[axis] = f % 2 == 0 ? 1.0 : -1.0;
                c[u] = 2.0 * i / k_n - 1.0;
                c[v] = 2.0 * j / k_n - 1.0;
                m.positions.push_back(glm::normalize(c));
            }
        auto at = [&](int i, int j) {
            return base + static_cast<std::uint32_t>(j * (k_n + 1) + i);
        };
        for (int j = 0; j < k_n; ++j)
            for (int i = 0; i < k_n; ++i) {
                m.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
                m.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
            }
    }
    return m;
}

std::string input_file(const std::string& ext) {
    const char* tmp = std::getenv("TMPDIR");
    const std::string path =
        std::string(tmp ? tmp : "/tmp") + "/subdivtrace_bench_weld_1M." + ext;
    if (!std::filesystem::exists(path)) write_mesh(path, patch_split_sphere());
    return path;
}

void read(benchmark::State& state, const std::string& ext, WeldOptions weld) {
    const std::string path = input_file(ext);
    std::size_t triangles = 0, vertices = 0;
    WeldReport report;
    for (auto _ : state) {
        const Mesh m = read_mesh(path, nullptr, weld, &report);
        triangles = m.triangles.size();
        vertices = m.positions.size();
        benchmark::DoNotOptimize(m.positions.data());
    }
    state.counters["triangles"] = static_cast<double>(triangles);
    state.counters["vertices"] = static_cast<double>(vertices);
    state.counters["welded"] = static_cast<double>(report.welded_vertices);
}

const WeldOptions k_off{false, 0.0};
const WeldOptions k_exact{true, 0.0};
const WeldOptions k_tolerance{true, 1e-7};

}  // namespace

BENCHMARK_CAPTURE(read, ply/off, std::string("ply"), k_off)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(read, ply/exact, std::string("ply"), k_exact)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(read, ply/tolerance, std::string("ply"), k_tolerance)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(read, obj/off, std::string("obj"), k_off)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(read, obj/exact, std::string("obj"), k_exact)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(read, stl/off, std::string("stl"), k_off)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(read, stl/exact, std::string("stl"), k_exact)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
