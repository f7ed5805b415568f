#pragma once
// Embree 3 (Debian's libembree-dev) as the peer a standalone user would pick:
// the same mesh either pre-tessellated by our uniform subdivision into
// Embree's triangle BVH, or handed to Embree's own Catmull-Clark subdivision
// geometry with per-edge tessellation levels from the camera. Hits come back
// as subdivtrace Hits, so the tools' render loop shades them like ours.

#include <atomic>
#include <cstddef>
#include <memory>
#include <vector>

#include <embree3/rtcore.h>

#include "render/camera.h"
#include "subdivtrace/tracer.h"
#include "subdivtrace/uniform.h"

namespace subdivtrace::compare {

/// Bytes Embree allocated through its device (its memory-monitor callback).
struct EmbreeMemory {
    std::atomic<long long> bytes{0};
    std::atomic<long long> peak{0};
};

/// Edge tessellation levels of the subdivision geometry.
struct EdgeLevels {
    std::vector<float> per_half_edge;  ///< one per face corner, as RTC_BUFFER_TYPE_LEVEL
    double mean = 0.0;
    double max = 0.0;
};

/// Segments per base edge so that each spans at most `pixels_per_segment`
/// pixels seen from `camera` (its length over the footprint at its midpoint,
/// as the adaptive tracer's tolerance measures it), clamped to 1..k_max_edge_level.
/// Both half edges of an edge get the same level (no cracks).
EdgeLevels edge_levels(const Mesh& mesh, const tools::Camera& camera, double pixels_per_segment);

/// Embree's own limit on one edge's tessellation level.
constexpr float k_max_edge_level = 4096.0f;

class EmbreeScene {
public:
    /// `threads` = 0: Embree's default (all cores) for its build.
    explicit EmbreeScene(int threads);
    ~EmbreeScene();
    EmbreeScene(const EmbreeScene&) = delete;
    EmbreeScene& operator=(const EmbreeScene&) = delete;

    /// The uniform level-K mesh as Embree triangles (float positions and
    /// normals; the double-precision mesh is not kept).
    void add_uniform(const SubdividedMesh& mesh);
    /// The base mesh as RTC_GEOMETRY_TYPE_SUBDIVISION (Catmull-Clark), with
    /// the given edge levels.
    void add_subdivision(const Mesh& mesh, const EdgeLevels& levels);
    /// Builds the BVH (and, for subdivision geometry, the tessellation).
    void commit();

    /// Nearest hit in (ray.t_min, ray.t_max); thread-safe after commit().
    bool intersect(const Ray& ray, Hit& hit) const;
    Bounds3 bounds() const;
    /// Bytes Embree holds now / at most, plus the arrays this class keeps.
    std::size_t bytes() const;
    std::size_t peak_bytes() const;

private:
    void fill_uniform_hit(unsigned prim, float u, float v, Hit& hit) const;
    void fill_subdivision_hit(unsigned prim, float u, float v, Hit& hit) const;

    EmbreeMemory memory_;
    RTCDevice device_ = nullptr;
    RTCScene scene_ = nullptr;
    RTCGeometry geometry_ = nullptr;
    bool subdivision_ = false;
    int uniform_level_ = 0;
    // Uniform mesh: what a hit needs besides Embree's buffers.
    std::vector<float> normals_;  ///< 3 per vertex
    const unsigned* index_buffer_ = nullptr;  ///< Embree's, 3 per triangle
    std::vector<std::uint32_t> base_face_;
};

}  // namespace subdivtrace::compare
