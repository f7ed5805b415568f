#pragma once
// A binned-SAH bounding volume hierarchy over boxes (Wald 2007, as in pbrt-v4
// and madmann91/bvh): the top level over base-triangle shells, and the
// uniform baseline's BVH over its triangles, built with the same care.

#include <cstdint>
#include <vector>

#include "double_pairs.h"
#include "subdivtrace/shell.h"

namespace subdivtrace::detail {

/// 32 bytes (a double box took 56): the box in single precision relative to
/// the tree's origin, rounded outwards so that `origin + stored`, evaluated in
/// double exactly as the traversal does, holds the double box (a ray that
/// hits an item's box hits every node above it).
struct BvhNode {
    float lo[3];
    float hi[3];
    std::uint32_t first = 0;  ///< first item (leaf) or left child (inner; right = left + 1)
    std::uint32_t count = 0;  ///< items in a leaf; 0 for inner nodes

    Vec3 box_lo(const Vec3& origin) const {
        return Vec3(origin.x + lo[0], origin.y + lo[1], origin.z + lo[2]);
    }
    Vec3 box_hi(const Vec3& origin) const {
        return Vec3(origin.x + hi[0], origin.y + hi[1], origin.z + hi[2]);
    }
    /// Stores [blo, bhi] relative to origin, rounded outwards as above.
    void set_box(const Vec3& origin, const Vec3& blo, const Vec3& bhi);
};

/// ray_hits_box on the boxes of two nodes (`origin` + their stored boxes),
/// both at once where SSE2 is: each lane does ray_hits_box's operations in
/// its order, so the verdicts and entry distances are the same bits (a
/// traversal tests both children of every node it enters: in the blob5k
/// close-up 36 boxes a ray, one by one a sixth of the render).
inline void ray_hits_box_pair(const RayBoxQuery& q, const Vec3& origin, const BvhNode& a, const BvhNode& b,
                              bool& hit_a, bool& hit_b, double& t_a, double& t_b) {
#if defined(__SSE2__)
    __m128d lo[3], hi[3];
    for (int k = 0; k < 3; ++k) {
        // box_lo and box_hi: the origin plus the stored floats, in double.
        const __m128d o = _mm_set1_pd(origin[k]);
        lo[k] = _mm_add_pd(o, pair_of(a.lo[k], b.lo[k]));
        hi[k] = _mm_add_pd(o, pair_of(a.hi[k], b.hi[k]));
    }
    __m128d t_near = _mm_set1_pd(q.t_min);
    __m128d t_far = _mm_set1_pd(q.t_max);
    ray_box_interval_pair(q, lo, hi, t_near, t_far);
    lane_verdicts(_mm_cmpgt_pd(t_near, t_far), t_near, hit_a, hit_b, t_a, t_b);
#else
    hit_a = ray_hits_box(q, a.box_lo(origin), a.box_hi(origin), t_a);
    hit_b = ray_hits_box(q, b.box_lo(origin), b.box_hi(origin), t_b);
#endif
}

class Bvh {
public:
    Bvh() = default;
    /// Builds over the boxes; items are referred to by their index. The
    /// boxes are taken (pass them with std::move) and freed before the tree
    /// takes its final copy, so a big build holds one of them at a time.
    void build(std::vector<Vec3> lo, std::vector<Vec3> hi, int max_leaf_size = 4);

    bool empty() const { return nodes_.empty(); }
    const Vec3& origin() const { return origin_; }
    const BvhNode& root() const { return nodes_.front(); }
    std::size_t node_count() const { return nodes_.size(); }
    const BvhNode& node(std::size_t i) const { return nodes_[i]; }
    std::uint32_t item(std::size_t k) const { return items_[k]; }
    std::size_t memory_bytes() const {
        return nodes_.capacity() * sizeof(BvhNode) + items_.capacity() * sizeof(std::uint32_t);
    }

    /// Visits leaves front to back while their box is entered before t_max;
    /// visit(item) may lower t_max (a closer hit). t_max is read by reference.
    template <class Visit>
    void traverse(const RayBoxQuery& query, const double& t_max, Visit visit) const {
        traverse_leaves(query, t_max, [&](const std::uint32_t* items, std::uint32_t count) {
            for (std::uint32_t k = 0; k < count; ++k) visit(items[k]);
        });
    }

    /// traverse(), a leaf at a time: visit_leaf(items, count) with its items.
    template <class VisitLeaf>
    void traverse_leaves(const RayBoxQuery& query, const double& t_max, VisitLeaf visit_leaf) const {
        if (nodes_.empty()) return;
        // Each node's box is tested once, by its parent (which orders the two
        // children by it); the stack keeps where the ray enters it, so a node
        // popped after a closer hit lowered t_max is dropped by one
        // comparison. That is the box test's own verdict: t_max only shrinks,
        // and the test fails exactly when the entry lies beyond it.
        struct Pending {
            std::uint32_t node;
            double t_entry;
        };
        Pending stack[256];  // SAH trees over 1e9 items stay far below this depth
        int top = 0;
        RayBoxQuery q = query;
        q.t_max = t_max;
        double t_root = 0.0;
        if (!ray_hits_box(q, root().box_lo(origin_), root().box_hi(origin_), t_root)) return;
        stack[top++] = {0, t_root};
        while (top > 0) {
            const Pending pending = stack[--top];
            if (pending.t_entry > t_max) continue;
            const BvhNode& node = nodes_[pending.node];
            if (node.count > 0) {
                visit_leaf(&items_[node.first], node.count);
                continue;
            }
            // Near child last on the stack, so it is visited first.
            q.t_max = t_max;
            const BvhNode& left = nodes_[node.first];
            const BvhNode& right = nodes_[node.first + 1];
            double tl = 0.0, tr = 0.0;
            bool hl = false, hr = false;
            ray_hits_box_pair(q, origin_, left, right, hl, hr, tl, tr);
            if (hl && hr) {
                if (tl <= tr) {
                    stack[top++] = {node.first + 1, tr};
                    stack[top++] = {node.first, tl};
                } else {
                    stack[top++] = {node.first, tl};
                    stack[top++] = {node.first + 1, tr};
                }
            } else if (hl) {
                stack[top++] = {node.first, tl};
            } else if (hr) {
                stack[top++] = {node.first + 1, tr};
            }
        }
    }

private:
    Vec3 origin_{0.0};  ///< node boxes are stored relative to it (the root box's centre)
    std::vector<BvhNode> nodes_;
    std::vector<std::uint32_t> items_;
};

}  // namespace subdivtrace::detail
