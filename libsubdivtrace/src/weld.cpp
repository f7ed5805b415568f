// Welding coincident vertices (weld.h).
#include "weld.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>

#include <glm/geometric.hpp>

#include "huge_pages.h"

namespace subdivtrace {

namespace {

using Key = std::array<double, 3>;

std::uint64_t hash_key(const Key& k) {
    // The bits of the three doubles through a 64-bit finaliser (splitmix64):
    // keys are exact values, so equal keys have equal bits once -0 is folded.
    std::uint64_t h = 0;
    for (double d : k) {
        std::uint64_t u;
        std::memcpy(&u, &d, 8);
        h = (h ^ u) * 0x9E3779B97F4A7C15ull;
        h ^= h >> 29;
    }
    h *= 0xBF58476D1CE4E5B9ull;
    return h ^ (h >> 32);
}

/// Open-addressing table from a key to the newest representative with that
/// key. A slot holds the key's upper 32 hash bits and the representative + 1
/// (0 = empty), so a probe reads the representative's key only when the hash
/// bits match: one cache miss per lookup, 16 bytes per vertex.
class KeyTable {
public:
    explicit KeyTable(std::size_t n) {
        std::size_t size = 16;
        while (size < 2 * n) size *= 2;
        slots_.assign(size, 0);
        mask_ = size - 1;
    }
    /// The representative stored for `key` (or k_none), and where it sits.
    template <class KeyOf>
    std::uint32_t* find(const Key& key, std::uint64_t& tag, const KeyOf& key_of) {
        const std::uint64_t h = hash_key(key);
        tag = h >> 32 << 32;
        for (std::size_t s = h & mask_;; s = (s + 1) & mask_) {
            std::uint64_t& slot = slots_[s];
            if (slot == 0) {
                last_ = &slot;
                return nullptr;
            }
            if ((slot >> 32 << 32) == tag) {
                const std::uint32_t r = static_cast<std::uint32_t>(slot) - 1;
                if (key_of(r) == key) {
                    last_ = &slot;
                    found_ = r;
                    return &found_;
                }
            }
        }
    }
    /// Stores representative `r` under the key of the last find (its head).
    void set_last(std::uint64_t tag, std::uint32_t r) { *last_ = tag | (std::uint64_t{r} + 1); }

private:
    std::vector<std::uint64_t> slots_;
    std::size_t mask_ = 0;
    std::uint64_t* last_ = nullptr;
    std::uint32_t found_ = 0;
};

constexpr std::uint32_t k_none = std::numeric_limits<std::uint32_t>::max();

Key canonical(const Vec3& p) { return {p.x + 0.0, p.y + 0.0, p.z + 0.0}; }  // -0 + 0 = +0

/// Gives back the room reserved for every input position where welding kept
/// far fewer (an STL's corners weld to about a sixth).
void fit_welded(std::vector<Vec3>& positions) {
    if (positions.size() < positions.capacity() / 2) positions.shrink_to_fit();
}

}  // namespace

WeldMap weld_positions(const std::vector<Vec3>& positions, double tolerance) {
    WeldMap out;
    const std::size_t n = positions.size();
    // Each array allocated once, on huge pages (huge_pages.h): a 1M-triangle
    // export grew its positions by doubling, faulting 4 kB pages.
    detail::assign_huge(out.remap, n, std::uint32_t{0});
    detail::reserve_huge(out.positions, n);
    KeyTable table(n);
    std::uint64_t tag = 0;

    if (!(tolerance > 0.0)) {
        // Exact: the key is the position itself.
        auto key_of = [&](std::uint32_t r) { return canonical(out.positions[r]); };
        for (std::size_t i = 0; i < n; ++i) {
            const std::uint32_t* r = table.find(canonical(positions[i]), tag, key_of);
            if (r) {
                out.remap[i] = *r;
            } else {
                out.remap[i] = static_cast<std::uint32_t>(out.positions.size());
                table.set_last(tag, out.remap[i]);
                out.positions.push_back(positions[i]);
            }
        }
        fit_welded(out.positions);
        return out;
    }

    // Within `tolerance`: grid cells of twice that size; a point's partners lie
    // in the cells its tolerance box overlaps (1 or 2 per axis). Representatives
    // sharing a cell are chained through `next`.
    const double h = 2.0 * tolerance;
    auto cell = [&](const Vec3& p) {
        return Key{std::floor(p.x / h), std::floor(p.y / h), std::floor(p.z / h)};
    };
    auto key_of = [&](std::uint32_t r) { return cell(out.positions[r]); };
    std::vector<std::uint32_t> next;
    detail::reserve_huge(next, n);
    const double tol2 = tolerance * tolerance;
    for (std::size_t i = 0; i < n; ++i) {
        const Vec3& p = positions[i];
        const Key lo = cell(p - Vec3(tolerance)), hi = cell(p + Vec3(tolerance));
        // The lowest-numbered representative within reach wins, so the result
        // depends only on the input order.
        std::uint32_t match = k_none;
        // (1 or 2 cells per axis; capped at 3, where rounding of huge cell
        // numbers could make the count odd, and never looping on x + 1 == x.)
        const int nx = static_cast<int>(std::min(2.0, hi[0] - lo[0]));
        const int ny = static_cast<int>(std::min(2.0, hi[1] - lo[1]));
        const int nz = static_cast<int>(std::min(2.0, hi[2] - lo[2]));
        for (int dx = 0; dx <= nx; ++dx)
            for (int dy = 0; dy <= ny; ++dy)
                for (int dz = 0; dz <= nz; ++dz) {
                    const Key k{lo[0] + dx, lo[1] + dy, lo[2] + dz};
                    const std::uint32_t* head = table.find(k, tag, key_of);
                    for (std::uint32_t r = head ? *head : k_none; r != k_none; r = next[r]) {
                        const Vec3 d = out.positions[r] - p;
                        if (glm::dot(d, d) <= tol2 && r < match) match = r;
                    }
                }
        if (match == k_none) {
            match = static_cast<std::uint32_t>(out.positions.size());
            const std::uint32_t* head = table.find(cell(p), tag, key_of);
            next.push_back(head ? *head : k_none);
            table.set_last(tag, match);
            out.positions.push_back(p);
        }
        out.remap[i] = match;
    }
    fit_welded(out.positions);
    return out;
}

}  // namespace subdivtrace
