#pragma once
// All hits (CSG, inside()): each surface crossing once, told apart by the
// structure the ray met, never by distance (docs/tracer.md section 3).

#include <array>
#include <cstddef>
#include <vector>

#include "ray_triangle.h"
#include "subdivtrace/tracer.h"

namespace subdivtrace::detail {

/// What one hit met: the drawn triangle's inside, one of its edges or one of
/// its corners, named by its drawn positions (bit-identical wherever leaves
/// share them), and the signed share of a full turn around the ray that this
/// triangle covers there.
struct CrossingPart {
    std::array<Vec3, 3> feature;  ///< sorted corners; unused ones zero
    int corners;                  ///< 3 inside, 2 edge, 1 corner
    double turns;                 ///< +-1 inside, +-1/2 edge, +-angle/(2 pi) corner
    std::size_t hit;              ///< index into the hits
};

/// The feature of drawn triangle `t` the ray met (th: the watertight test's
/// result) and the share of a turn around the ray the triangle covers there.
/// Zero weights are exact (the watertight test computes a shared edge's
/// function identically from both sides), so every leaf that meets the same
/// edge or corner names the same feature.
CrossingPart crossing_part(const WatertightRay& ray, const std::array<Vec3, 3>& t,
                           const TriangleHit& th, std::size_t hit);

/// Replaces `hits` by one hit per crossing, sorted by t: each feature reports
/// the steps of the surface's running winding number around the ray there
/// (its triangles' turns added to those before it, rounded).
void merge_crossings(std::vector<CrossingPart>& parts, std::vector<Hit>& hits);

}  // namespace subdivtrace::detail
