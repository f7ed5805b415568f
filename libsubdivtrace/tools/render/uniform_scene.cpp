#include "render/uniform_scene.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>

// The library's own BVH and triangle test (private headers of libsubdivtrace),
// so the baseline is built with the same care as the adaptive tracer.
#include "bvh.h"
#include "ray_triangle.h"

namespace subdivtrace::tools {

struct UniformScene::Impl {
    SubdividedMesh mesh;
    detail::Bvh bvh;
    Bounds3 bounds;
};

UniformScene::UniformScene(SubdividedMesh mesh) : impl_(std::make_unique<Impl>()) {
    impl_->mesh = std::move(mesh);
    const SubdividedMesh& m = impl_->mesh;
    std::vector<Vec3> lo(m.triangles.size()), hi(m.triangles.size());
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
        const Triangle& tri = m.triangles[t];
        lo[t] = glm::min(glm::min(m.positions[tri[0]], m.positions[tri[1]]), m.positions[tri[2]]);
        hi[t] = glm::max(glm::max(m.positions[tri[0]], m.positions[tri[1]]), m.positions[tri[2]]);
        impl_->bounds.lo = t == 0 ? lo[t] : glm::min(impl_->bounds.lo, lo[t]);
        impl_->bounds.hi = t == 0 ? hi[t] : glm::max(impl_->bounds.hi, hi[t]);
    }
    impl_->bvh.build(std::move(lo), std::move(hi), 4);
}

UniformScene::~UniformScene() = default;

bool UniformScene::intersect(const Ray& ray, Hit& hit) const {
    const SubdividedMesh& m = impl_->mesh;
    const RayBoxQuery q = make_ray_box_query(ray.origin, ray.direction, ray.t_min, ray.t_max);
    const detail::WatertightRay wr = detail::make_watertight_ray(ray.origin, ray.direction);
    double t_max = ray.t_max;
    bool found = false;
    impl_->bvh.traverse(q, t_max, [&](std::uint32_t t) {
        const Triangle& tri = m.triangles[t];
        detail::TriangleHit th;
        if (!detail::intersect_watertight(wr, m.positions[tri[0]], m.positions[tri[1]],
                                          m.positions[tri[2]], ray.t_min, t_max, th))
            return;
        t_max = th.t;
        found = true;
        hit.t = th.t;
        hit.point = th.b0 * m.positions[tri[0]] + th.b1 * m.positions[tri[1]] +
                    th.b2 * m.positions[tri[2]];
        hit.geometric_normal = finish_normal(glm::cross(m.positions[tri[1]] - m.positions[tri[0]],
                                                        m.positions[tri[2]] - m.positions[tri[0]]));
        hit.normal = finish_normal(th.b0 * m.corner_normal(t, 0) + th.b1 * m.corner_normal(t, 1) +
                                   th.b2 * m.corner_normal(t, 2));
        if (hit.normal == Vec3(0.0)) hit.normal = hit.geometric_normal;
        if (!m.corner_uvs.empty()) {
            hit.uv = th.b0 * m.corner_uvs[3 * t] + th.b1 * m.corner_uvs[3 * t + 1] +
                     th.b2 * m.corner_uvs[3 * t + 2];
        }
        hit.level = m.levels;
        hit.base_face = m.base_face[t];
        const Vec3 ap = glm::abs(hit.point);
        hit.error_bound = gamma_bound(7) * (ap.x + ap.y + ap.z);
    });
    return found;
}

Bounds3 UniformScene::bounds() const { return impl_->bounds; }

std::size_t UniformScene::memory_bytes() const {
    const SubdividedMesh& m = impl_->mesh;
    return m.positions.capacity() * sizeof(Vec3) + m.triangles.capacity() * sizeof(Triangle) +
           m.normal_bytes() + m.corner_uvs.capacity() * sizeof(Vec2) +
           m.base_face.capacity() * sizeof(std::uint32_t) + impl_->bvh.memory_bytes();
}

std::size_t UniformScene::triangle_count() const { return impl_->mesh.triangles.size(); }

}  // namespace subdivtrace::tools
