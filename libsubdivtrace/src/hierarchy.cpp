#include "subdivtrace/hierarchy.h"

#include <algorithm>
#include <atomic>
#include <stdexcept>

#include <glm/geometric.hpp>

#include "grid.h"
#include "lru_cache.h"
#include "vertex_eval.h"

namespace subdivtrace {

namespace {

using detail::VertexKey;

/// Descendants of an interpolating scheme's node stay within this many times
/// the largest edge-point displacement of its neighbourhood from the flat
/// triangle (a geometric series of ratio <= 1/2 sums to 2x; the prototype saw
/// ratios 1/2.6 .. 1/3.4). tests/unit/test_shells.cpp holds it to containment.
constexpr double k_displacement_factor = 2.0;
/// Relative slack for rounding in the stencils, times the node's extent.
constexpr double k_rounding_slack = 1e-9;
std::atomic<std::uint64_t> g_next_hierarchy_id{1};

struct NodeKeyHash {
    std::size_t operator()(const NodeId& n) const {
        const std::uint64_t h0 = (std::uint64_t{n.face} << 32) | (std::uint64_t{n.level} << 1) | n.down;
        const std::uint64_t h1 = (std::uint64_t{n.i} << 32) | n.j;
        return static_cast<std::size_t>(detail::mix64(h0 ^ detail::mix64(h1)));
    }
};

// Corner k of child c, for parents of each orientation (see uniform.h for
// the order; derived from the grid coordinates in child_of).
const std::array<std::array<ChildCorner, 3>, 4> k_up_children = {{
    {{{false, 0}, {true, 0}, {true, 2}}},
    {{{true, 0}, {false, 1}, {true, 1}}},
    {{{true, 2}, {true, 1}, {false, 2}}},
    {{{true, 0}, {true, 1}, {true, 2}}},
}};
const std::array<std::array<ChildCorner, 3>, 4> k_down_children = {{
    {{{false, 0}, {true, 0}, {true, 2}}},
    {{{true, 0}, {false, 1}, {true, 1}}},
    {{{true, 2}, {true, 1}, {false, 2}}},
    {{{true, 2}, {true, 0}, {true, 1}}},
}};

}  // namespace

const std::array<ChildCorner, 3>& child_corners(bool parent_down, int child) {
    return parent_down ? k_down_children[child] : k_up_children[child];
}

NodeId child_of(const NodeId& node, int child) {
    NodeId c;
    c.face = node.face;
    c.level = static_cast<std::uint8_t>(node.level + 1);
    const std::uint32_t i = 2 * node.i, j = 2 * node.j;
    if (!node.down) {
        static const std::uint32_t di[4] = {0, 1, 0, 0}, dj[4] = {0, 0, 1, 0};
        c.down = child == 3;
        c.i = i + di[child];
        c.j = j + dj[child];
    } else {
        static const std::uint32_t di[4] = {1, 1, 0, 1}, dj[4] = {0, 1, 1, 1};
        c.down = child != 3;
        c.i = i + di[child];
        c.j = j + dj[child];
    }
    return c;
}

std::array<std::array<std::uint32_t, 2>, 3> node_corner_grid(const NodeId& n) {
    if (!n.down) return {{{n.i, n.j}, {n.i + 1, n.j}, {n.i, n.j + 1}}};
    return {{{n.i + 1, n.j}, {n.i + 1, n.j + 1}, {n.i, n.j + 1}}};
}

class HierarchyImpl {
public:
    HierarchyImpl(const Mesh& mesh, SchemeKind scheme, int max_level, std::size_t cache_bytes,
                  ShellKind shell_kind)
        : topo(mesh),
          scheme(scheme),
          max_level(max_level),
          shell_kind(shell_kind),
          // Half the budget for vertices, half for nodes.
          vertices(topo, scheme, cache_bytes / 2),
          nodes(cache_bytes / 2) {}

    NodeRecord build(const NodeId& id);

    detail::BaseTopology topo;
    SchemeKind scheme;
    int max_level;
    ShellKind shell_kind;
    detail::VertexEvaluator vertices;
    detail::ShardedLruCache<NodeId, NodeRecord, NodeKeyHash> nodes;
    std::atomic<std::uint64_t> built{0};
    const std::uint64_t id_ = g_next_hierarchy_id.fetch_add(1);
};

NodeRecord HierarchyImpl::build(const NodeId& id) {
    // One scratch table per thread, kept across builds as a private front to
    // the shared vertex cache (bounded; values are deterministic, so keeping
    // them cannot change a result). Cleared when another hierarchy uses it.
    struct ThreadScratch {
        std::uint64_t owner = 0;
        detail::EvalScratch table;
    };
    thread_local ThreadScratch mine;
    if (mine.owner != id_) {
        mine.table.clear();
        mine.owner = id_;
    }
    detail::EvalScratch& scratch = mine.table;
    const int level = id.level;
    const auto grid = node_corner_grid(id);
    std::array<VertexKey, 3> keys;
    NodeRecord rec;
    for (int c = 0; c < 3; ++c) {
        keys[c] = topo.canonical(id.face, level, grid[c][0], grid[c][1]);
        rec.position[c] = vertices.position(keys[c], level, scratch);
        rec.normal[c] = vertices.normal(keys[c], level, scratch);
        rec.draw_position[c] = vertices.draw_position(keys[c], scratch);
    }

    // Slab axis: the node's own plane (or its corners' mean normal if it is degenerate).
    Shell& shell = rec.shell;
    Vec3 axis = finish_normal(glm::cross(rec.position[1] - rec.position[0],
                                    rec.position[2] - rec.position[0]));
    if (axis == Vec3(0.0)) axis = finish_normal(rec.normal[0] + rec.normal[1] + rec.normal[2]);
    shell.axis = shell_kind == ShellKind::aabb_slab ? axis : Vec3(0.0);
    if (shell.axis != Vec3(0.0)) {
        shell.slab_min = shell.slab_max = glm::dot(shell.axis, rec.position[0]);
    }
    for (int c = 0; c < 3; ++c) {
        shell.grow_both(rec.position[c]);
        shell.grow_both(rec.draw_position[c]);
    }

    if (level < max_level) {
        detail::KeyPairs pairs;
        if (scheme == SchemeKind::loop) {
            // Loop's stencils are convex combinations, so every descendant
            // (and limit point) lies in the hull of the corners' 1-rings.
            for (int c = 0; c < 3; ++c) {
                vertices.incident_pairs(keys[c], level, pairs);
                for (const auto& pr : pairs) shell.grow_both(vertices.position(pr.from, level, scratch));
            }
        } else {
            // Interpolating: the children's edge points are exact; deeper
            // levels are bounded by the displacement of every edge point in
            // the corners' neighbourhood, times a series factor.
            double max_displacement = 0.0;
            for (int c = 0; c < 3; ++c) {
                max_displacement = std::max(max_displacement,
                                            vertices.edge_displacement(keys[c], level, scratch));
            }
            for (int e = 0; e < 3; ++e) {
                const VertexKey mid = topo.canonical(id.face, level + 1,
                                                     grid[e][0] + grid[(e + 1) % 3][0],
                                                     grid[e][1] + grid[(e + 1) % 3][1]);
                shell.grow_both(vertices.position(mid, level + 1, scratch));
            }
            if (level + 1 < max_level) shell.pad(k_displacement_factor * max_displacement);
        }
    }
    const Vec3 extent = shell.hi - shell.lo;
    const double size = std::max({extent.x, extent.y, extent.z, glm::length(shell.lo),
                                  glm::length(shell.hi)});
    shell.pad(k_rounding_slack * size);
    built.fetch_add(1, std::memory_order_relaxed);
    return rec;
}

Hierarchy::Hierarchy(const Mesh& mesh, SchemeKind scheme, int max_level,
                     std::size_t cache_bytes, ShellKind shell_kind)
    : impl_(std::make_unique<HierarchyImpl>(mesh, scheme, max_level, cache_bytes, shell_kind)) {}

Hierarchy::~Hierarchy() = default;

SchemeKind Hierarchy::scheme() const { return impl_->scheme; }
int Hierarchy::max_level() const { return impl_->max_level; }
std::size_t Hierarchy::face_count() const { return impl_->topo.face_count(); }
bool Hierarchy::closed() const { return impl_->topo.closed(); }

NodeRecord Hierarchy::node(const NodeId& id) const {
    NodeRecord rec;
    if (impl_->nodes.lookup(id, rec)) return rec;
    rec = impl_->build(id);
    impl_->nodes.insert(id, rec);
    return rec;
}

HierarchyCounters Hierarchy::counters() const {
    const detail::CacheCounters v = impl_->vertices.counters();
    const detail::CacheCounters n = impl_->nodes.counters();
    HierarchyCounters c;
    c.nodes_built = impl_->built.load();
    c.node_hits = n.hits;
    c.node_misses = n.misses;
    c.vertex_hits = v.hits;
    c.vertex_misses = v.misses;
    c.evictions = v.evictions + n.evictions;
    c.bytes = v.bytes + n.bytes;
    c.peak_bytes = v.peak_bytes + n.peak_bytes;
    return c;
}

}  // namespace subdivtrace
