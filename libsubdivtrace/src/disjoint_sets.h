#pragma once
// Union-find over 0 .. n-1 (path halving; the smaller root wins a union, so
// a set's root is its smallest member): the sectors around a vertex
// (label_sectors) and a mesh's components (analyze_mesh).

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <vector>

namespace subdivtrace::detail {

class DisjointSets {
public:
    explicit DisjointSets(std::size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0u); }

    std::uint32_t find(std::uint32_t x) {
        while (parent_[x] != x) x = parent_[x] = parent_[parent_[x]];
        return x;
    }

    void unite(std::uint32_t a, std::uint32_t b) {
        a = find(a);
        b = find(b);
        if (a != b) parent_[std::max(a, b)] = std::min(a, b);
    }

private:
    std::vector<std::uint32_t> parent_;
};

}  // namespace subdivtrace::detail
