// Uniform subdivision, per scheme and level, on a ~5k-triangle closed mesh (and
// at level 4 on the scanned bunny of data/): the baseline the adaptive tracer
// is compared against, and OpenMesh's LoopT and
// ModifiedButterflyT on the same mesh (in process, no I/O, the mesh copied into
// OpenMesh outside the timed region) as the peer. Counters: output triangles
// per second, the bytes of the output arrays, the process's peak resident
// memory (VmHWM) after the run, and the page faults per subdivision
// (faults/it). Each iteration's arrays are fresh memory as glibc gives freed
// blocks back, and a fault costs about 10 us on the virtual machines we
// measure on: run with MALLOC_TOP_PAD_=536870912
// MALLOC_TRIM_THRESHOLD_=1073741824 to keep freed memory and time the
// arithmetic alone (docs/benchmarks.md, "Page faults in uniform
// subdivision").
// OpenMesh's VectorT leaves default-constructed coordinates uninitialised on
// purpose; GCC 12 then warns inside <vector>. It must precede every include.
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <cmath>
#include <cstdint>
#include <fstream>
#include <map>
#include <random>
#include <string>
#include <utility>

#include <sys/resource.h>

#include <benchmark/benchmark.h>
#include <glm/geometric.hpp>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include "subdivtrace/mesh_io.h"
#include "subdivtrace/uniform.h"
#include "unit/openmesh_subdivide.h"

namespace {

using namespace subdivtrace;

/// The icosahedron split 1-to-4 four times (5120 faces) and projected to the unit
/// sphere, then jittered (seeded) so no two edges are alike.
Mesh bumpy_sphere() {
    const double phi = (1.0 + std::sqrt(5.0)) / 2.0;
    Mesh m;
    m.positions = {{-1, phi, 0}, {1, phi, 0}, {-1, -phi, 0}, {1, -phi, 0},
                   {0, -1, phi}, {0, 1, phi}, {0, -1, -phi}, {0, 1, -phi},
                   {phi, 0, -1}, {phi, 0, 1}, {-phi, 0, -1}, {-phi, 0, 1}};
    for (Vec3& p : m.positions) p = glm::normalize(p);
    m.triangles = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                   {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                   {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                   {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
    for (int level = 0; level < 4; ++level) {
        std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;
        auto midpoint = [&](std::uint32_t u, std::uint32_t w) {
            const auto key = std::make_pair(std::min(u, w), std::max(u, w));
            const auto [it, inserted] =
                mid.emplace(key, static_cast<std::uint32_t>(m.positions.size()));
            if (inserted) m.positions.push_back(glm::normalize(m.positions[u] + m.positions[w]));
            return it->second;
        };
        std::vector<Triangle> next;
        for (const Triangle& t : m.triangles) {
            const std::uint32_t ab = midpoint(t[0], t[1]), bc = midpoint(t[1], t[2]),
                                ca = midpoint(t[2], t[0]);
            next.push_back({t[0], ab, ca});
            next.push_back({ab, t[1], bc});
            next.push_back({ca, bc, t[2]});
            next.push_back({ab, bc, ca});
        }
        m.triangles.swap(next);
    }
    std::mt19937 rng(42);
    std::uniform_real_distribution<double> jitter(-0.004, 0.004);
    for (Vec3& p : m.positions) p += Vec3(jitter(rng), jitter(rng), jitter(rng));
    return m;
}

/// Mesh 0: the bumpy sphere; mesh 1: the scanned bunny (2,996 triangles,
/// irregular valences, closed), read once.
const Mesh& base_mesh(long which = 0) {
    static const Mesh sphere = bumpy_sphere();
    static const Mesh bunny = read_mesh(SUBDIVTRACE_DATA_DIR "/bunny_lowpoly.obj");
    return which == 1 ? bunny : sphere;
}

/// Peak resident set size of this process in MB (VmHWM), or -1 if unknown.
double peak_rss_mb() {
    std::ifstream status("/proc/self/status");
    std::string line;
    while (std::getline(status, line)) {
        if (line.rfind("VmHWM:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
    }
    return -1.0;
}

/// Minor page faults of this process so far.
double minor_faults() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return static_cast<double>(usage.ru_minflt);
}

void BM_uniform(benchmark::State& state) {
    const auto scheme = static_cast<SchemeKind>(state.range(0));
    const int levels = static_cast<int>(state.range(1));
    const Mesh& mesh = base_mesh(state.range(2));
    state.SetLabel(std::string(scheme_name(scheme)) + (state.range(2) == 1 ? " bunny" : ""));
    std::size_t triangles = 0;
    double output_bytes = 0.0;
    double faults = 0.0;
    for (auto _ : state) {
        const double faults_before = minor_faults();
        SubdividedMesh sub = subdivide_uniform(mesh, scheme, levels);
        faults += minor_faults() - faults_before;
        benchmark::DoNotOptimize(sub.positions.data());
        triangles = sub.triangles.size();
        output_bytes = static_cast<double>(
            sub.positions.size() * sizeof(Vec3) + sub.normal_bytes() +
            sub.triangles.size() * sizeof(Triangle) +
            sub.base_face.size() * sizeof(std::uint32_t));
    }
    state.counters["in_tris"] = static_cast<double>(mesh.triangles.size());
    state.counters["out_tris"] = static_cast<double>(triangles);
    state.counters["tris/s"] = benchmark::Counter(
        static_cast<double>(triangles) * static_cast<double>(state.iterations()),
        benchmark::Counter::kIsRate);
    state.counters["out_MB"] = output_bytes / (1024.0 * 1024.0);
    state.counters["peak_MB"] = peak_rss_mb();
    state.counters["faults/it"] = faults / static_cast<double>(state.iterations());
}

void uniform_args(benchmark::internal::Benchmark* b) {
    for (SchemeKind kind : {SchemeKind::normal, SchemeKind::loop, SchemeKind::butterfly}) {
        for (int levels = 1; levels <= 4; ++levels) b->Args({static_cast<long>(kind), levels, 0});
        b->Args({static_cast<long>(kind), 4, 1});
    }
    b->ArgNames({"scheme", "level", "mesh"});
    b->Unit(benchmark::kMillisecond);
}

struct DoubleTraits : OpenMesh::DefaultTraits {
    using Point = OpenMesh::Vec3d;
    using Normal = OpenMesh::Vec3d;
};
using OmMesh = OpenMesh::TriMesh_ArrayKernelT<DoubleTraits>;

OmMesh to_openmesh(const Mesh& mesh) {
    OmMesh om;
    std::vector<OmMesh::VertexHandle> handles;
    for (const Vec3& p : mesh.positions) handles.push_back(om.add_vertex({p.x, p.y, p.z}));
    for (const Triangle& t : mesh.triangles) om.add_face(handles[t[0]], handles[t[1]], handles[t[2]]);
    return om;
}

/// OpenMesh's subdivider of the same scheme (Loop or modified Butterfly).
void BM_openmesh(benchmark::State& state) {
    const auto scheme = static_cast<SchemeKind>(state.range(0));
    const int levels = static_cast<int>(state.range(1));
    state.SetLabel(std::string("openmesh ") + scheme_name(scheme) +
                   (state.range(2) == 1 ? " bunny" : ""));
    std::size_t triangles = 0;
    double faults = 0.0;
    for (auto _ : state) {
        state.PauseTiming();
        OmMesh om = to_openmesh(base_mesh(state.range(2)));
        state.ResumeTiming();
        const double faults_before = minor_faults();
        testmesh::openmesh_subdivide(om, scheme, levels);
        faults += minor_faults() - faults_before;
        triangles = om.n_faces();
        benchmark::DoNotOptimize(triangles);
    }
    state.counters["out_tris"] = static_cast<double>(triangles);
    state.counters["tris/s"] = benchmark::Counter(
        static_cast<double>(triangles) * static_cast<double>(state.iterations()),
        benchmark::Counter::kIsRate);
    state.counters["faults/it"] = faults / static_cast<double>(state.iterations());
}

void openmesh_args(benchmark::internal::Benchmark* b) {
    for (SchemeKind kind : {SchemeKind::loop, SchemeKind::butterfly}) {
        for (int levels = 1; levels <= 4; ++levels) b->Args({static_cast<long>(kind), levels, 0});
        b->Args({static_cast<long>(kind), 4, 1});
    }
    b->ArgNames({"scheme", "level", "mesh"});
    b->Unit(benchmark::kMillisecond);
}

}  // namespace

BENCHMARK(BM_uniform)->Apply(uniform_args);
BENCHMARK(BM_openmesh)->Apply(openmesh_args);

BENCHMARK_MAIN();
