#include "creases.h"

#include <algorithm>
#include <tuple>

#include <glm/geometric.hpp>

#include "disjoint_sets.h"
#include "edge_sides.h"
#include "subdivtrace/scheme.h"
#include "vertex_faces.h"

namespace subdivtrace::detail {

Vec3 given_normal_of(const Mesh& mesh, std::uint32_t face, std::uint32_t v) {
    if (!mesh.has_normals()) return Vec3(0.0);
    const Triangle& t = mesh.triangles[face];
    for (int c = 0; c < 3; ++c)
        if (t[c] == v) return finish_normal(mesh.corner_normals[3 * face + c]);
    return Vec3(0.0);
}

bool normals_split(const Vec3& n1, const Vec3& n2) {
    const double l1 = glm::length(n1), l2 = glm::length(n2);
    // A zero normal carries no direction: it splits nothing.
    if (!(l1 > 0.0) || !(l2 > 0.0)) return false;
    return glm::dot(n1, n2) < (1.0 - 1e-8) * l1 * l2;
}

std::vector<std::uint8_t> crease_masks(const Mesh& mesh) {
    if (!mesh.has_normals()) return std::vector<std::uint8_t>(mesh.triangles.size(), 0);
    return crease_masks(mesh, sorted_edge_sides(mesh.triangles, mesh.positions.size()));
}

std::vector<std::uint8_t> crease_masks(const Mesh& mesh, const HugeArray<EdgeSide>& sides) {
    std::vector<std::uint8_t> masks(mesh.triangles.size(), 0);
    if (!mesh.has_normals()) return masks;
    // The given normal at base vertex v in triangle f.
    const auto normal_at = [&](std::uint32_t f, std::uint32_t v) {
        return mesh.corner_normals[3 * f + corner_of(mesh.triangles[f], v)];
    };
    for_each_edge(sides, [&](const EdgeSide* first, const EdgeSide* last) {
        if (last - first != 2) return;
        const EdgeSide& x = first[0];
        const EdgeSide& y = first[1];
        if (normals_split(normal_at(x.face, x.lo), normal_at(y.face, x.lo)) ||
            normals_split(normal_at(x.face, x.hi), normal_at(y.face, x.hi))) {
            masks[x.face] |= static_cast<std::uint8_t>(1u << x.corner);
            masks[y.face] |= static_cast<std::uint8_t>(1u << y.corner);
        }
    });
    return masks;
}

std::uint32_t label_sectors(const std::vector<FanCorner>& corners, std::vector<std::uint32_t>& labels) {
    const std::size_t n = corners.size();
    DisjointSets sectors(n);
    // Each edge at the centre, named by its other end, with the corners on it.
    struct Side {
        std::uint32_t nbr;
        std::uint32_t corner;
        bool crease;
    };
    std::vector<Side> sides;
    sides.reserve(2 * n);
    for (std::size_t k = 0; k < n; ++k) {
        const auto corner = static_cast<std::uint32_t>(k);
        sides.push_back({corners[k].next, corner, corners[k].crease_next});
        sides.push_back({corners[k].prev, corner, corners[k].crease_prev});
    }
    std::sort(sides.begin(), sides.end(),
              [](const Side& x, const Side& y) { return std::tie(x.nbr, x.corner) < std::tie(y.nbr, y.corner); });
    // The corners on one edge share a sector unless the edge is a crease.
    for (auto first = sides.begin(); first != sides.end();) {
        const auto last = std::find_if(first, sides.end(),
                                       [&](const Side& s) { return s.nbr != first->nbr; });
        if (std::none_of(first, last, [](const Side& s) { return s.crease; }))
            for (auto it = first + 1; it != last; ++it) sectors.unite(first->corner, it->corner);
        first = last;
    }
    labels.assign(n, UINT32_MAX);
    std::vector<std::uint32_t> root_label(n, UINT32_MAX);
    std::uint32_t count = 0;
    for (std::size_t k = 0; k < n; ++k) {
        const std::uint32_t r = sectors.find(static_cast<std::uint32_t>(k));
        if (root_label[r] == UINT32_MAX) root_label[r] = count++;
        labels[k] = root_label[r];
    }
    return count;
}

void restrict_to_sector(VertexRing& ring, const std::uint8_t* curve, std::size_t& index) {
    const std::size_t n = ring.nbrs.size();
    if (!ring.regular || n == 0 || index >= n) return;
    // Walk back and forward from `index` to the nearest curve edges (an open
    // fan's ends are boundary edges, curve edges too).
    std::size_t first = index, last = index;
    std::size_t steps = 0;
    while (!curve[first] && steps < n) {
        if (first == 0) {
            if (!ring.closed) break;
            first = n;
        }
        --first;
        ++steps;
    }
    steps = 0;
    while (!curve[last] && steps < n) {
        if (last + 1 == n) {
            if (!ring.closed) break;
            last = static_cast<std::size_t>(-1);
        }
        ++last;
        ++steps;
    }
    if (!curve[first] && !curve[last]) return;  // one sector after all
    std::vector<Vec3> sector;
    for (std::size_t k = first;; k = (k + 1) % n) {
        sector.push_back(ring.nbrs[k]);
        if (k == last) break;
    }
    index = (index + n - first) % n;
    ring.nbrs.swap(sector);
    ring.closed = false;
}

}  // namespace subdivtrace::detail
