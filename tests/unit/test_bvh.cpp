// The top-level BVH's single-precision nodes against the double-precision
// boxes they stand for: a ray the double test sends into an item's box must
// reach that item through the tree, near the origin and 1e6 away from it.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cstring>
#include <random>
#include <set>
#include <tuple>

#include "bvh.h"

using namespace subdivtrace;

TEST_CASE("BVH: float nodes hold their items' boxes and the traversal finds every box a ray hits",
          "[bvh][threads]") {
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
        std::size_t outside = 0, bad_children = 0;
        const auto holds = [&](const detail::BvhNode& node, const Vec3& blo, const Vec3& bhi) {
            const Vec3 nlo = node.box_lo(bvh.origin()), nhi = node.box_hi(bvh.origin());
            return nlo.x <= blo.x && nlo.y <= blo.y && nlo.z <= blo.z && nhi.x >= bhi.x &&
                   nhi.y >= bhi.y && nhi.z >= bhi.z;
        };
        for (std::size_t i = 0; i < bvh.node_count(); ++i) {
            const detail::BvhNode& node = bvh.node(i);
            if (node.count > 0) {
                for (std::uint32_t k = 0; k < node.count; ++k) {
                    const std::uint32_t item = bvh.item(node.first + k);
                    ++seen[item];
                    outside += holds(node, lo[item], hi[item]) ? 0 : 1;
                }
                continue;
            }
            if (node.first + 1 >= bvh.node_count()) {
                ++bad_children;
                continue;
            }
            for (const std::size_t child : {std::size_t{node.first}, std::size_t{node.first} + 1}) {
                const detail::BvhNode& c = bvh.node(child);
                outside += holds(node, c.box_lo(bvh.origin()), c.box_hi(bvh.origin())) ? 0 : 1;
            }
        }
        CHECK(outside == 0);
        CHECK(bad_children == 0);
        CHECK(std::count(seen.begin(), seen.end(), 1) == static_cast<long>(seen.size()));
    }
}

TEST_CASE("BVH: the two-box test gives each box ray_hits_box's verdict and entry, bit for bit",
          "[bvh]") {
    // Random boxes and rays, a third of the rays parallel to an axis (an
    // infinite inverse direction; a NaN product where the ray lies in a face).
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> coordinate(-2.0, 2.0), size(0.0, 0.5);
    std::uniform_int_distribution<int> axis(0, 5);
    const Vec3 origin(0.25, -0.5, 1.0);
    const auto random_node = [&] {
        detail::BvhNode node;
        const Vec3 c(coordinate(rng), coordinate(rng), coordinate(rng));
        const Vec3 e(size(rng), size(rng), size(rng));
        node.set_box(origin, c - e, c + e);
        return node;
    };
    int hits = 0, misses = 0;
    for (int r = 0; r < 20000; ++r) {
        const detail::BvhNode a = random_node(), b = random_node();
        Vec3 ray_origin(coordinate(rng), coordinate(rng), coordinate(rng));
        // Half of them aimed near a's centre, so that both verdicts are common.
        Vec3 dir(coordinate(rng), coordinate(rng), coordinate(rng));
        if (r % 2 == 0) dir = 0.5 * (a.box_lo(origin) + a.box_hi(origin)) + 0.1 * dir - ray_origin;
        const int flat = axis(rng);
        if (flat < 3) {
            dir[flat] = 0.0;
            // In the plane of a's face along that axis, now and then.
            if (r % 7 == 0) ray_origin[flat] = a.box_lo(origin)[flat];
        }
        const RayBoxQuery q = make_ray_box_query(ray_origin, dir, 0.0, r % 5 == 0 ? 1.0 : 1e300);
        double t_a = -1.0, t_b = -1.0, expected_a = -1.0, expected_b = -1.0;
        bool hit_a = false, hit_b = false;
        detail::ray_hits_box_pair(q, origin, a, b, hit_a, hit_b, t_a, t_b);
        const bool want_a = ray_hits_box(q, a.box_lo(origin), a.box_hi(origin), expected_a);
        const bool want_b = ray_hits_box(q, b.box_lo(origin), b.box_hi(origin), expected_b);
        REQUIRE(hit_a == want_a);
        REQUIRE(hit_b == want_b);
        if (want_a) REQUIRE(std::memcmp(&t_a, &expected_a, sizeof t_a) == 0);
        if (want_b) REQUIRE(std::memcmp(&t_b, &expected_b, sizeof t_b) == 0);
        (want_a ? hits : misses) += 1;
    }
    // Both verdicts were exercised.
    CHECK(hits > 1000);
    CHECK(misses > 1000);
}
