#include "bvh.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/common.hpp>

namespace subdivtrace::detail {

namespace {

constexpr int k_bins = 16;

double half_area(const Vec3& lo, const Vec3& hi) {
    const Vec3 e = glm::max(hi - lo, Vec3(0.0));
    return e.x * e.y + e.y * e.z + e.z * e.x;
}

struct Builder {
    const std::vector<Vec3>& lo;
    const std::vector<Vec3>& hi;
    std::vector<Vec3> centre;
    std::vector<BvhNode>& nodes;
    std::vector<std::uint32_t>& items;
    Vec3 origin;
    int max_leaf;

    void bounds(std::uint32_t begin, std::uint32_t end, Vec3& blo, Vec3& bhi, Vec3& clo,
                Vec3& chi) const {
        blo = clo = Vec3(std::numeric_limits<double>::infinity());
        bhi = chi = Vec3(-std::numeric_limits<double>::infinity());
        for (std::uint32_t k = begin; k < end; ++k) {
            const std::uint32_t it = items[k];
            blo = glm::min(blo, lo[it]);
            bhi = glm::max(bhi, hi[it]);
            clo = glm::min(clo, centre[it]);
            chi = glm::max(chi, centre[it]);
        }
    }

    // Iterative over an explicit work list, so deep trees cannot overflow the stack.
    void run() {
        struct Task {
            std::uint32_t node, begin, end;
        };
        std::vector<Task> work{{0, 0, static_cast<std::uint32_t>(items.size())}};
        nodes.push_back({});
        while (!work.empty()) {
            const Task task = work.back();
            work.pop_back();
            Vec3 blo, bhi, clo, chi;
            bounds(task.begin, task.end, blo, bhi, clo, chi);
            nodes[task.node].set_box(origin, blo, bhi);
            const std::uint32_t n = task.end - task.begin;
            std::uint32_t split = 0;
            if (n > static_cast<std::uint32_t>(max_leaf)) split = find_split(task, clo, chi, blo, bhi);
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
            work.push_back({left, task.begin, split});
            work.push_back({left + 1, split, task.end});
        }
    }

    /// Partitions items by the cheapest binned SAH plane; returns the split
    /// index, or 0 to make a leaf.
    template <class T>
    std::uint32_t find_split(const T& task, const Vec3& clo, const Vec3& chi, const Vec3& blo,
                             const Vec3& bhi) {
        const std::uint32_t n = task.end - task.begin;
        double best_cost = std::numeric_limits<double>::infinity();
        int best_axis = -1, best_bin = 0;
        for (int axis = 0; axis < 3; ++axis) {
            const double extent = chi[axis] - clo[axis];
            if (!(extent > 0.0)) continue;
            struct Bin {
                Vec3 lo{std::numeric_limits<double>::infinity()};
                Vec3 hi{-std::numeric_limits<double>::infinity()};
                std::uint32_t count = 0;
            } bins[k_bins];
            const double scale = k_bins / extent;
            for (std::uint32_t k = task.begin; k < task.end; ++k) {
                const std::uint32_t it = items[k];
                int b = static_cast<int>((centre[it][axis] - clo[axis]) * scale);
                b = std::clamp(b, 0, k_bins - 1);
                bins[b].lo = glm::min(bins[b].lo, lo[it]);
                bins[b].hi = glm::max(bins[b].hi, hi[it]);
                ++bins[b].count;
            }
            double right_area[k_bins];
            std::uint32_t right_count[k_bins];
            Vec3 rlo(std::numeric_limits<double>::infinity()), rhi(-rlo);
            std::uint32_t rc = 0;
            for (int b = k_bins - 1; b > 0; --b) {
                rlo = glm::min(rlo, bins[b].lo);
                rhi = glm::max(rhi, bins[b].hi);
                rc += bins[b].count;
                right_area[b] = half_area(rlo, rhi);
                right_count[b] = rc;
            }
            Vec3 llo(std::numeric_limits<double>::infinity()), lhi(-llo);
            std::uint32_t lc = 0;
            for (int b = 0; b < k_bins - 1; ++b) {
                llo = glm::min(llo, bins[b].lo);
                lhi = glm::max(lhi, bins[b].hi);
                lc += bins[b].count;
                if (lc == 0 || right_count[b + 1] == 0) continue;
                const double cost = lc * half_area(llo, lhi) + right_count[b + 1] * right_area[b + 1];
                if (cost < best_cost) best_cost = cost, best_axis = axis, best_bin = b;
            }
        }
        // A leaf costs n intersections over the whole box; keep it if no split is cheaper.
        const double leaf_cost = n * half_area(blo, bhi);
        if (best_axis < 0 || (n <= 16 && best_cost >= leaf_cost)) {
            if (n <= 16 || best_axis < 0) return median_split(task, clo, chi, n <= 16);
        }
        const double scale = k_bins / (chi[best_axis] - clo[best_axis]);
        auto mid = std::partition(items.begin() + task.begin, items.begin() + task.end,
                                  [&](std::uint32_t it) {
                                      int b = static_cast<int>((centre[it][best_axis] - clo[best_axis]) * scale);
                                      return std::clamp(b, 0, k_bins - 1) <= best_bin;
                                  });
        return static_cast<std::uint32_t>(mid - items.begin());
    }

    /// Fallback when binning cannot separate (all centres equal) or a leaf is
    /// cheaper: a leaf if small enough, else an object median split.
    template <class T>
    std::uint32_t median_split(const T& task, const Vec3& clo, const Vec3& chi, bool allow_leaf) {
        if (allow_leaf) return 0;
        const Vec3 e = chi - clo;
        const int axis = e.x >= e.y && e.x >= e.z ? 0 : (e.y >= e.z ? 1 : 2);
        const std::uint32_t mid = task.begin + (task.end - task.begin) / 2;
        std::nth_element(items.begin() + task.begin, items.begin() + mid, items.begin() + task.end,
                         [&](std::uint32_t a, std::uint32_t b) { return centre[a][axis] < centre[b][axis]; });
        return mid;
    }
};

}  // namespace

void Bvh::build(const std::vector<Vec3>& lo, const std::vector<Vec3>& hi, int max_leaf_size) {
    nodes_.clear();
    items_.resize(lo.size());
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
    // made once the builder's centres (24 bytes per item) are freed.
    std::vector<BvhNode> nodes;
    nodes.reserve(2 * lo.size());
    {
        Builder b{lo, hi, {}, nodes, items_, origin_, max_leaf_size};
        b.centre.resize(lo.size());
        for (std::size_t k = 0; k < lo.size(); ++k) b.centre[k] = (lo[k] + hi[k]) * 0.5;
        b.run();
    }
    nodes_.assign(nodes.begin(), nodes.end());
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
    while (origin + static_cast<double>(f) > x) f = std::nextafter(f, -k_float_inf);
    return f;
}

/// The float f nearest above x - origin with origin + f >= x.
float offset_up(double origin, double x) {
    const double d = x - origin;
    if (!(d <= k_float_max)) return k_float_inf;
    float f = d < -k_float_max ? -k_float_max : static_cast<float>(d);
    while (origin + static_cast<double>(f) < x) f = std::nextafter(f, k_float_inf);
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
