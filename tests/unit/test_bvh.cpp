// The top-level BVH's single-precision nodes against the double-precision
// boxes they stand for: a ray the double test sends into an item's box must
// reach that item through the tree, near the origin and 1e6 away from it.
#include <catch2/catch.hpp>

#include <random>
#include <set>

#include "bvh.h"

using namespace subdivtrace;

TEST_CASE("BVH: float nodes hold their items' boxes and the traversal finds every box a ray hits",
          "[bvh]") {
    std::mt19937 rng(7);
    for (const double offset : {0.0, 1e6}) {
        // Boxes with 1e-3 detail, at the origin and 1e6 away from it.
        std::uniform_real_distribution<double> centre(-1.0, 1.0), size(0.0, 1e-3);
        std::vector<Vec3> lo, hi;
        for (int k = 0; k < 2000; ++k) {
            const Vec3 c(offset + centre(rng), offset + centre(rng), offset + centre(rng));
            const Vec3 e(size(rng), size(rng), size(rng));
            lo.push_back(c - e);
            hi.push_back(c + e);
        }
        detail::Bvh bvh;
        bvh.build(lo, hi, 2);
        CHECK(bvh.memory_bytes() <= bvh.node_count() * 32 + lo.size() * 4);
        // Rays aimed at box corners: the traversal must report each box the
        // double-precision test accepts.
        std::uniform_int_distribution<int> pick(0, static_cast<int>(lo.size()) - 1);
        int checked = 0;
        for (int r = 0; r < 500; ++r) {
            const int target = pick(rng);
            const Vec3 origin(offset + 3.0, offset + 2.0 * centre(rng), offset + 2.0 * centre(rng));
            const Vec3 dir = lo[target] - origin;
            RayBoxQuery q;
            q.origin = origin;
            q.dir = dir;
            q.inv_dir = Vec3(1.0) / dir;
            q.t_min = 0.0;
            q.t_max = 1e300;
            std::set<std::uint32_t> expected, found;
            for (std::uint32_t k = 0; k < lo.size(); ++k) {
                double t = 0.0;
                if (ray_hits_box(q, lo[k], hi[k], t)) expected.insert(k);
            }
            const double t_max = 1e300;
            bvh.traverse(q, t_max, [&](std::uint32_t item) { found.insert(item); });
            for (std::uint32_t k : expected) REQUIRE(found.count(k) == 1);
            checked += static_cast<int>(expected.size());
        }
        CHECK(checked >= 500);  // every ray hits at least its target
    }
}
