#pragma once
// The baseline the adaptive surface is timed against: a uniform level-K mesh
// in a binned-SAH BVH, intersected with the same watertight test and giving
// the same Hit fields.

#include <cstddef>
#include <memory>

#include "subdivtrace/tracer.h"
#include "subdivtrace/uniform.h"

namespace subdivtrace::tools {

/// A uniform mesh with a BVH, intersected like the adaptive surface.
class UniformScene {
public:
    explicit UniformScene(SubdividedMesh mesh);
    ~UniformScene();
    UniformScene(const UniformScene&) = delete;
    UniformScene& operator=(const UniformScene&) = delete;

    /// Nearest hit in (ray.t_min, ray.t_max); thread-safe.
    bool intersect(const Ray& ray, Hit& hit) const;
    Bounds3 bounds() const;
    /// Bytes of the mesh arrays and the BVH.
    std::size_t memory_bytes() const;
    std::size_t triangle_count() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace subdivtrace::tools
