#pragma once
// Room for the points of one fan (the triangles around a vertex): on the
// stack up to k_inline of them, which holds every ring of a regular or
// near-regular mesh, and on the heap beyond. A build takes a fan per vertex
// at each level, and the thread-local vectors the fans had used cost a
// thread-local lookup and a size check each time.

#include <cstddef>
#include <vector>

#include "subdivtrace/mesh.h"
#include "subdivtrace/scheme.h"

namespace subdivtrace::detail {

class FanScratch {
public:
    /// Room for n points (what it held before is not kept).
    Vec3* room(std::size_t n) {
        if (n <= k_inline) return inline_;
        heap_.resize(n);
        return heap_.data();
    }

private:
    static constexpr std::size_t k_inline = 16;
    Vec3 inline_[k_inline];  // left uninitialised: every caller writes before it reads
    std::vector<Vec3> heap_;
};

/// The Gouraud normal of a fan of `count` triangles (centre, from[k], to[k]):
/// their angle-weighted normals summed in order, normalised (zero where they
/// cancel). A record's shading and edge-midpoint normals both sum here,
/// in the order their caller gathers the fan.
inline Vec3 fan_normal(const Vec3& centre, const Vec3* from, const Vec3* to, std::size_t count) {
    FanScratch room;
    Vec3* weight = room.room(count);
    angle_weighted_fan(centre, from, to, count, weight);
    Vec3 sum(0.0);
    for (std::size_t k = 0; k < count; ++k) sum += weight[k];
    return finish_normal(sum);
}

}  // namespace subdivtrace::detail
