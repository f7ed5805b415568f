#include "embree_scene.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

namespace subdivtrace::compare {

namespace {

/// pbrt's gamma(n) in single precision: Embree intersects in float.
constexpr double float_gamma(int n) {
    const double eps = 0.5 * std::numeric_limits<float>::epsilon();
    return n * eps / (1.0 - n * eps);
}

void throw_on_error(RTCDevice device, const char* what) {
    const RTCError e = rtcGetDeviceError(device);
    if (e != RTC_ERROR_NONE) throw std::runtime_error(std::string("Embree: ") + what + " failed (error " +
                                                      std::to_string(static_cast<int>(e)) + ")");
}

bool monitor(void* user, ssize_t bytes, bool /*post*/) {
    auto* m = static_cast<EmbreeMemory*>(user);
    const long long now = m->bytes += bytes;
    long long peak = m->peak.load();
    while (now > peak && !m->peak.compare_exchange_weak(peak, now)) {
    }
    return true;
}

Vec3 to_vec3(const float* p) { return Vec3(p[0], p[1], p[2]); }

}  // namespace

EdgeLevels edge_levels(const Mesh& mesh, const tools::Camera& camera, double pixels_per_segment) {
    EdgeLevels out;
    out.per_half_edge.resize(mesh.triangles.size() * 3);
    const double footprint_per_distance = camera.pixel_angle() * pixels_per_segment;
    double sum = 0.0;
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        for (int c = 0; c < 3; ++c) {
            // Embree's level of edge c runs from corner c to corner c + 1; the
            // value depends only on the (unordered) endpoints, so both sides agree.
            const Vec3& a = mesh.positions[mesh.triangles[t][c]];
            const Vec3& b = mesh.positions[mesh.triangles[t][(c + 1) % 3]];
            const double distance = glm::length((a + b) * 0.5 - camera.look_from);
            const double segments = glm::length(b - a) / (footprint_per_distance * distance);
            const float level =
                std::clamp(static_cast<float>(std::ceil(segments)), 1.0f, k_max_edge_level);
            out.per_half_edge[3 * t + c] = level;
            sum += level;
            out.max = std::max(out.max, static_cast<double>(level));
        }
    }
    out.mean = out.per_half_edge.empty() ? 0.0 : sum / out.per_half_edge.size();
    return out;
}

EmbreeScene::EmbreeScene(int threads) {
    const std::string config = threads > 0 ? "threads=" + std::to_string(threads) : "";
    device_ = rtcNewDevice(config.c_str());
    if (!device_) throw std::runtime_error("Embree: rtcNewDevice failed");
    rtcSetDeviceMemoryMonitorFunction(device_, monitor, &memory_);
    scene_ = rtcNewScene(device_);
    throw_on_error(device_, "rtcNewScene");
}

EmbreeScene::~EmbreeScene() {
    if (geometry_) rtcReleaseGeometry(geometry_);
    if (scene_) rtcReleaseScene(scene_);
    if (device_) rtcReleaseDevice(device_);
}

void EmbreeScene::add_uniform(const SubdividedMesh& mesh) {
    geometry_ = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* positions = static_cast<float*>(rtcSetNewGeometryBuffer(
        geometry_, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float),
        mesh.positions.size()));
    auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
        geometry_, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned),
        mesh.triangles.size()));
    throw_on_error(device_, "allocating the triangle buffers");
    // Embree interpolates per-vertex normals: a vertex takes its first
    // corner's (the compared meshes have no creases, so its corners agree).
    normals_.resize(mesh.positions.size() * 3);
    for (std::size_t v = 0; v < mesh.positions.size(); ++v)
        for (int k = 0; k < 3; ++k) positions[3 * v + k] = static_cast<float>(mesh.positions[v][k]);
    for (std::size_t v = 0; v < mesh.vertex_normals.size(); ++v)
        for (int k = 0; k < 3; ++k) normals_[3 * v + k] = static_cast<float>(mesh.vertex_normals[v][k]);
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
        for (int k = 0; k < 3; ++k) indices[3 * t + k] = mesh.triangles[t][k];
    index_buffer_ = indices;
    base_face_ = mesh.base_face;
    uniform_level_ = mesh.levels;
    rtcCommitGeometry(geometry_);
    rtcAttachGeometry(scene_, geometry_);
    throw_on_error(device_, "building the triangle geometry");
}

void EmbreeScene::add_subdivision(const Mesh& mesh, const EdgeLevels& levels) {
    subdivision_ = true;
    geometry_ = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_SUBDIVISION);
    const std::size_t faces = mesh.triangles.size();
    auto* face_sizes = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
        geometry_, RTC_BUFFER_TYPE_FACE, 0, RTC_FORMAT_UINT, sizeof(unsigned), faces));
    auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
        geometry_, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT, sizeof(unsigned), 3 * faces));
    auto* positions = static_cast<float*>(rtcSetNewGeometryBuffer(
        geometry_, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float),
        mesh.positions.size()));
    auto* level = static_cast<float*>(rtcSetNewGeometryBuffer(
        geometry_, RTC_BUFFER_TYPE_LEVEL, 0, RTC_FORMAT_FLOAT, sizeof(float), 3 * faces));
    throw_on_error(device_, "allocating the subdivision buffers");
    for (std::size_t t = 0; t < faces; ++t) {
        face_sizes[t] = 3;
        for (int k = 0; k < 3; ++k) {
            indices[3 * t + k] = mesh.triangles[t][k];
            level[3 * t + k] = levels.per_half_edge[3 * t + k];
        }
    }
    for (std::size_t v = 0; v < mesh.positions.size(); ++v)
        for (int k = 0; k < 3; ++k) positions[3 * v + k] = static_cast<float>(mesh.positions[v][k]);
    // Open boundaries stay smooth curves (our schemes' boundary rule is a curve too).
    rtcSetGeometrySubdivisionMode(geometry_, 0, RTC_SUBDIVISION_MODE_SMOOTH_BOUNDARY);
    rtcCommitGeometry(geometry_);
    rtcAttachGeometry(scene_, geometry_);
    throw_on_error(device_, "building the subdivision geometry");
}

void EmbreeScene::commit() {
    rtcCommitScene(scene_);
    throw_on_error(device_, "rtcCommitScene");
}

bool EmbreeScene::intersect(const Ray& ray, Hit& hit) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit rh;
    rh.ray.org_x = static_cast<float>(ray.origin.x);
    rh.ray.org_y = static_cast<float>(ray.origin.y);
    rh.ray.org_z = static_cast<float>(ray.origin.z);
    rh.ray.dir_x = static_cast<float>(ray.direction.x);
    rh.ray.dir_y = static_cast<float>(ray.direction.y);
    rh.ray.dir_z = static_cast<float>(ray.direction.z);
    rh.ray.tnear = static_cast<float>(ray.t_min);
    rh.ray.tfar = ray.t_max >= std::numeric_limits<float>::max()
                      ? std::numeric_limits<float>::infinity()
                      : static_cast<float>(ray.t_max);
    rh.ray.time = 0.0f;
    rh.ray.mask = ~0u;
    rh.ray.id = 0;
    rh.ray.flags = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene_, &context, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;

    hit.t = rh.ray.tfar;
    hit.point = ray.origin + hit.t * ray.direction;
    hit.geometric_normal = finish_normal(Vec3(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z));
    if (subdivision_) fill_subdivision_hit(rh.hit.primID, rh.hit.u, rh.hit.v, hit);
    else fill_uniform_hit(rh.hit.primID, rh.hit.u, rh.hit.v, hit);
    if (hit.normal == Vec3(0.0)) hit.normal = hit.geometric_normal;
    // Single-precision hit: the point is off by a few float ulps of its
    // coordinates and of the distance travelled.
    const Vec3 ap = glm::abs(hit.point);
    hit.error_bound = float_gamma(16) * (ap.x + ap.y + ap.z + hit.t * glm::length(ray.direction));
    return true;
}

void EmbreeScene::fill_uniform_hit(unsigned prim, float u, float v, Hit& hit) const {
    // Embree's barycentrics: p = (1 - u - v) p0 + u p1 + v p2.
    const unsigned* tri = index_buffer_ + 3 * prim;
    hit.normal = finish_normal((1.0 - u - v) * to_vec3(&normals_[3 * tri[0]]) +
                               double(u) * to_vec3(&normals_[3 * tri[1]]) +
                               double(v) * to_vec3(&normals_[3 * tri[2]]));
    hit.level = uniform_level_;
    hit.base_face = base_face_[prim];
}

void EmbreeScene::fill_subdivision_hit(unsigned prim, float u, float v, Hit& hit) const {
    // The limit surface's normal from its derivatives at (u, v).
    float p[3], dpdu[3], dpdv[3];
    rtcInterpolate1(geometry_, prim, u, v, RTC_BUFFER_TYPE_VERTEX, 0, p, dpdu, dpdv, 3);
    hit.normal = finish_normal(glm::cross(to_vec3(dpdu), to_vec3(dpdv)));
    hit.level = 0;
    hit.base_face = prim;
}

Bounds3 EmbreeScene::bounds() const {
    RTCBounds b;
    rtcGetSceneBounds(scene_, &b);
    Bounds3 out;
    out.lo = Vec3(b.lower_x, b.lower_y, b.lower_z);
    out.hi = Vec3(b.upper_x, b.upper_y, b.upper_z);
    return out;
}

std::size_t EmbreeScene::bytes() const {
    return static_cast<std::size_t>(std::max(0LL, memory_.bytes.load())) +
           normals_.capacity() * sizeof(float) + base_face_.capacity() * sizeof(std::uint32_t);
}

std::size_t EmbreeScene::peak_bytes() const {
    return static_cast<std::size_t>(std::max(0LL, memory_.peak.load())) +
           normals_.capacity() * sizeof(float) + base_face_.capacity() * sizeof(std::uint32_t);
}

}  // namespace subdivtrace::compare
