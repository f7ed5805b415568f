// The top-level BVH's single-precision nodes against the double-precision
// boxes they stand for: a ray the double test sends into an item's box must
// reach that item through the tree, near the origin and 1e6 away from it.
#include <catch2/catch.hpp>

#include <random>
#include <set>
#include <tuple>

#include "bvh.h"

using namespace subdivtrace;

TEST_CASE("BVH: float nodes hold their items' boxes and the traversal finds every box a ray hits",
          "[bvh]") {
    // 2000 boxes, and 100,000 (a tree that large builds its two halves on two threads).
    std::mt19937 rng(7);
    for (const auto& [offset, count, rays] : {std::tuple{0.0, 2000, 500}, std::tuple{1e6, 2000, 500},
                                             std::tuple{0.0, 100000, 100}}) {
        INFO(count << " boxes at offset " << offset);
        // Boxes with 1e-3 detail, at the origin and 1e6 away from it.
        std::uniform_real_distribution<double> centre(-1.0, 1.0), size(0.0, 1e-3);
        std::vector<Vec3> lo, hi;
        for (int k = 0; k < count; ++k) {
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
        for (int r = 0; r < rays; ++r) {
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
        CHECK(checked >= rays);  // every ray hits at least its target

        // Every item in exactly one leaf; every node's box holds its children's.
        std::vector<int> seen(lo.size(), 0);
        for (std::size_t i = 0; i < bvh.node_count(); ++i) {
            const detail::BvhNode& node = bvh.node(i);
            if (node.count > 0) {
                for (std::uint32_t k = 0; k < node.count; ++k) {
                    const std::uint32_t item = bvh.item(node.first + k);
                    ++seen[item];
                    for (int a = 0; a < 3; ++a) {
                        REQUIRE(node.box_lo(bvh.origin())[a] <= lo[item][a]);
                        REQUIRE(node.box_hi(bvh.origin())[a] >= hi[item][a]);
                    }
                }
                continue;
            }
            REQUIRE(node.first + 1 < bvh.node_count());
            for (const std::size_t child : {std::size_t{node.first}, std::size_t{node.first} + 1})
                for (int a = 0; a < 3; ++a) {
                    REQUIRE(node.box_lo(bvh.origin())[a] <= bvh.node(child).box_lo(bvh.origin())[a]);
                    REQUIRE(node.box_hi(bvh.origin())[a] >= bvh.node(child).box_hi(bvh.origin())[a]);
                }
        }
        for (int s : seen) REQUIRE(s == 1);
    }
}
