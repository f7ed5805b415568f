#include "bvh.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <thread>

#include <glm/common.hpp>

#include "float_step.h"
#include "huge_pages.h"
#include "parallel.h"

namespace subdivtrace::detail {

namespace {

constexpr int k_bins = 16;
/// Trees over at least this many items build their two halves on two threads.
constexpr std::uint32_t k_parallel_items = 1u << 16;

double half_area(const Vec3& lo, const Vec3& hi) {
    const Vec3 e = glm::max(hi - lo, Vec3(0.0));
    return e.x * e.y + e.y * e.z + e.z * e.x;
}

/// Bounds of a range of items: of their boxes and of their centres.
struct Range {
    Vec3 blo{std::numeric_limits<double>::infinity()};
    Vec3 bhi{-std::numeric_limits<double>::infinity()};
    Vec3 clo{std::numeric_limits<double>::infinity()};
    Vec3 chi{-std::numeric_limits<double>::infinity()};

    void add(const Vec3& lo, const Vec3& hi, const Vec3& centre) {
        blo = glm::min(blo, lo);
        bhi = glm::max(bhi, hi);
        clo = glm::min(clo, centre);
        chi = glm::max(chi, centre);
    }
    void add(const Range& r) {
        blo = glm::min(blo, r.blo);
        bhi = glm::max(bhi, r.bhi);
        clo = glm::min(clo, r.clo);
        chi = glm::max(chi, r.chi);
    }
};

struct Builder {
    const std::vector<Vec3>& lo;
    const std::vector<Vec3>& hi;
    std::vector<BvhNode>& nodes;
    std::vector<std::uint32_t>& items;
    Vec3 origin;
    int max_leaf;

    /// An item's centre, computed where needed: a list of them would add 24
    /// bytes per item to the build's peak (22 MB for a million triangles).
    Vec3 centre(std::uint32_t it) const { return (lo[it] + hi[it]) * 0.5; }

    struct Task {
        std::uint32_t node, begin, end;
        Range range;
    };

    Range bounds(std::uint32_t begin, std::uint32_t end) const {
        Range r;
        for (std::uint32_t k = begin; k < end; ++k) {
            const std::uint32_t it = items[k];
            r.add(lo[it], hi[it], centre(it));
        }
        return r;
    }

    // Iterative over an explicit work list, so deep trees cannot overflow the stack.
    // A node's bounds come from its parent's bins (min and max are exact, so
    // they equal a pass over its items): each level reads every item twice,
    // once to bin it along all three axes and once to partition it.
    void run() {
        const std::uint32_t n_items = static_cast<std::uint32_t>(items.size());
        nodes.push_back({});
        run_from({0, 0, n_items, bounds(0, n_items)});
    }

    /// Builds the subtree of `root` (its node already allocated) over its items.
    void run_from(const Task& root) {
        std::vector<Task> work{root};
        while (!work.empty()) {
            const Task task = work.back();
            work.pop_back();
            nodes[task.node].set_box(origin, task.range.blo, task.range.bhi);
            const std::uint32_t n = task.end - task.begin;
            std::uint32_t split = 0;
            Range left_range, right_range;
            if (n > static_cast<std::uint32_t>(max_leaf))
                split = find_split(task, left_range, right_range);
            if (split == 0) {
                nodes[task.node].first = task.begin;
                nodes[task.node].count = n;
                continue;
            }
            const std::uint32_t left = static_cast<std::uint32_t>(nodes.size());
            nodes.push_back({});
            nodes.push_back({});
            nodes[task.node].first = left;
            nodes[task.node].count = 0;
            work.push_back({left, task.begin, split, left_range});
            work.push_back({left + 1, split, task.end, right_range});
        }
    }

    /// Partitions items by the cheapest binned SAH plane along the axis where
    /// their centres spread most (as pbrt-v4's BVHAggregate does: binning all
    /// three axes tripled the build's time, 1.2 s of the 3 s a 943k-triangle
    /// surface took to build, for trees that trace alike); returns the split
    /// index and the two sides' bounds, or 0 to make a leaf.
    std::uint32_t find_split(const Task& task, Range& left_range, Range& right_range) {
        const std::uint32_t n = task.end - task.begin;
        const Vec3& clo = task.range.clo;
        const Vec3& chi = task.range.chi;
        const Vec3 spread = chi - clo;
        const int axis = spread.x >= spread.y && spread.x >= spread.z ? 0 : (spread.y >= spread.z ? 1 : 2);
        int best_bin = -1;
        double best_cost = std::numeric_limits<double>::infinity();
        struct Bin {
            Range range;
            std::uint32_t count = 0;
        } bins[k_bins];
        const double scale = spread[axis] > 0.0 ? k_bins / spread[axis] : 0.0;
        auto bin_of = [&](const Vec3& c) {
            return std::clamp(static_cast<int>((c[axis] - clo[axis]) * scale), 0, k_bins - 1);
        };
        if (spread[axis] > 0.0) {
            for (std::uint32_t k = task.begin; k < task.end; ++k) {
                const std::uint32_t it = items[k];
                const Vec3 c = centre(it);
                Bin& bin = bins[bin_of(c)];
                bin.range.add(lo[it], hi[it], c);
                ++bin.count;
            }
            double right_area[k_bins];
            std::uint32_t right_count[k_bins];
            Vec3 rlo(std::numeric_limits<double>::infinity()), rhi(-rlo);
            std::uint32_t rc = 0;
            for (int b = k_bins - 1; b > 0; --b) {
                rlo = glm::min(rlo, bins[b].range.blo);
                rhi = glm::max(rhi, bins[b].range.bhi);
                rc += bins[b].count;
                right_area[b] = half_area(rlo, rhi);
                right_count[b] = rc;
            }
            Vec3 llo(std::numeric_limits<double>::infinity()), lhi(-llo);
            std::uint32_t lc = 0;
            for (int b = 0; b < k_bins - 1; ++b) {
                llo = glm::min(llo, bins[b].range.blo);
                lhi = glm::max(lhi, bins[b].range.bhi);
                lc += bins[b].count;
                if (lc == 0 || right_count[b + 1] == 0) continue;
                const double cost = lc * half_area(llo, lhi) + right_count[b + 1] * right_area[b + 1];
                if (cost < best_cost) best_cost = cost, best_bin = b;
            }
        }
        // A leaf costs n intersections over the whole box; keep it if no split is cheaper.
        const double leaf_cost = n * half_area(task.range.blo, task.range.bhi);
        if (best_bin < 0 || (n <= 16 && best_cost >= leaf_cost)) {
            if (n <= 16 || best_bin < 0) {
                const std::uint32_t mid = median_split(task, n <= 16);
                if (mid != 0) {
                    left_range = bounds(task.begin, mid);
                    right_range = bounds(mid, task.end);
                }
                return mid;
            }
        }
        auto mid = std::partition(items.begin() + task.begin, items.begin() + task.end,
                                  [&](std::uint32_t it) { return bin_of(centre(it)) <= best_bin; });
        for (int b = 0; b < k_bins; ++b) (b <= best_bin ? left_range : right_range).add(bins[b].range);
        return static_cast<std::uint32_t>(mid - items.begin());
    }

    /// Fallback when binning cannot separate (all centres equal) or a leaf is
    /// cheaper: a leaf if small enough, else an object median split.
    std::uint32_t median_split(const Task& task, bool allow_leaf) {
        if (allow_leaf) return 0;
        const Vec3 e = task.range.chi - task.range.clo;
        const int axis = e.x >= e.y && e.x >= e.z ? 0 : (e.y >= e.z ? 1 : 2);
        const std::uint32_t mid = task.begin + (task.end - task.begin) / 2;
        std::nth_element(items.begin() + task.begin, items.begin() + mid, items.begin() + task.end,
                         [&](std::uint32_t a, std::uint32_t b) { return centre(a)[axis] < centre(b)[axis]; });
        return mid;
    }
};

}  // namespace

void Bvh::build(std::vector<Vec3> lo, std::vector<Vec3> hi, int max_leaf_size) {
    nodes_.clear();
    resize_huge(items_, lo.size());
    for (std::uint32_t k = 0; k < items_.size(); ++k) items_[k] = k;
    if (lo.empty()) return;
    // Boxes are stored relative to the middle of all of them, so single
    // precision keeps detail far from the coordinate origin.
    Vec3 all_lo = lo.front(), all_hi = hi.front();
    for (std::size_t k = 1; k < lo.size(); ++k) {
        all_lo = glm::min(all_lo, lo[k]);
        all_hi = glm::max(all_hi, hi[k]);
    }
    const Vec3 mid = (all_lo + all_hi) * 0.5;
    origin_ = std::isfinite(mid.x) && std::isfinite(mid.y) && std::isfinite(mid.z) ? mid : Vec3(0.0);
    // Nodes go to a list reserved for the most a tree over n items can have
    // (2n - 1): pages past the nodes written are never touched, so never
    // resident, and no growth copies the list. The tree keeps an exact copy,
    // made once the boxes (48 bytes per item) are freed.
    const std::uint32_t n = static_cast<std::uint32_t>(lo.size());
    if (n < k_parallel_items || std::thread::hardware_concurrency() < 2) {
        std::vector<BvhNode> nodes;
        reserve_huge(nodes, 2 * lo.size());
        Builder{lo, hi, nodes, items_, origin_, max_leaf_size}.run();
        lo = std::vector<Vec3>();
        hi = std::vector<Vec3>();
        reserve_huge(nodes_, nodes.size());
        nodes_.assign(nodes.begin(), nodes.end());
        return;
    }
    // A large tree: the root's split here, then its two subtrees on two
    // threads (their items are disjoint ranges), each into a list of its
    // own, joined below. Splits depend only on a range's items, so the tree
    // is the one a single thread builds, only numbered differently.
    std::vector<BvhNode> root(1);
    Builder top{lo, hi, root, items_, origin_, max_leaf_size};
    const Builder::Task all{0, 0, n, top.bounds(0, n)};
    root[0].set_box(origin_, all.range.blo, all.range.bhi);
    Range left_range, right_range;
    const std::uint32_t split = top.find_split(all, left_range, right_range);
    if (split == 0) {  // one leaf (cannot happen above max_leaf items, kept for safety)
        root[0].first = 0;
        root[0].count = n;
        nodes_ = root;
        return;
    }
    std::vector<BvhNode> left(1), right(1);
    reserve_huge(left, 2 * std::size_t{split});
    reserve_huge(right, 2 * std::size_t{n - split});
    struct NoState {};
    run_in_parallel<NoState>(2, [&](std::size_t half, NoState&) {
        if (half == 0)
            Builder{lo, hi, left, items_, origin_, max_leaf_size}.run_from({0, 0, split, left_range});
        else
            Builder{lo, hi, right, items_, origin_, max_leaf_size}.run_from({0, split, n, right_range});
    });
    lo = std::vector<Vec3>();
    hi = std::vector<Vec3>();
    // Node 0 the root, 1 and 2 its children, then the left subtree's other
    // nodes, then the right's (siblings stay adjacent in each).
    const auto left_index = [&](std::uint32_t i) { return i == 0 ? 1u : 2u + i; };
    const auto right_index = [&](std::uint32_t i) {
        return i == 0 ? 2u : 2u + static_cast<std::uint32_t>(left.size()) - 1u + i;
    };
    resize_huge(nodes_, 1 + left.size() + right.size());
    nodes_[0] = root[0];
    nodes_[0].first = 1;
    nodes_[0].count = 0;
    for (std::uint32_t i = 0; i < left.size(); ++i) {
        BvhNode node = left[i];
        if (node.count == 0) node.first = left_index(node.first);
        nodes_[left_index(i)] = node;
    }
    for (std::uint32_t i = 0; i < right.size(); ++i) {
        BvhNode node = right[i];
        if (node.count == 0) node.first = right_index(node.first);
        nodes_[right_index(i)] = node;
    }
}

namespace {

constexpr float k_float_max = std::numeric_limits<float>::max();
constexpr float k_float_inf = std::numeric_limits<float>::infinity();

/// The float f nearest below x - origin such that origin + f (in double, as
/// the traversal computes it) is <= x.
float offset_down(double origin, double x) {
    const double d = x - origin;
    if (!(d >= -k_float_max)) return -k_float_inf;  // also NaN: never cull
    float f = d > k_float_max ? k_float_max : static_cast<float>(d);
    while (origin + static_cast<double>(f) > x) f = next_float_down(f);
    return f;
}

/// The float f nearest above x - origin with origin + f >= x.
float offset_up(double origin, double x) {
    const double d = x - origin;
    if (!(d <= k_float_max)) return k_float_inf;
    float f = d < -k_float_max ? -k_float_max : static_cast<float>(d);
    while (origin + static_cast<double>(f) < x) f = next_float_up(f);
    return f;
}

}  // namespace

void BvhNode::set_box(const Vec3& origin, const Vec3& blo, const Vec3& bhi) {
    for (int a = 0; a < 3; ++a) {
        lo[a] = offset_down(origin[a], blo[a]);
        hi[a] = offset_up(origin[a], bhi[a]);
    }
}

}  // namespace subdivtrace::detail
