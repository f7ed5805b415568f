// Node addressing: children, corners and ancestors by grid arithmetic.
#include "subdivtrace/node_id.h"

#include "node_address.h"

namespace subdivtrace {

namespace {

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

namespace detail {

NodeId ancestor_at(const NodeId& id, int level) {
    if (id.level <= level) return id;
    // The ancestor's cell is the grid position shifted down; within a cell
    // of side 2^s, a descendant lies in the "down" half when its local
    // coordinates plus its own down flag reach 2^s (child_of's layout: an up
    // parent's children have at most one odd coordinate or down flag among
    // (i, j, down), a down parent's two or three; this is that, s levels at once).
    const int s = id.level - level;
    const std::uint32_t mask = (std::uint32_t{1} << s) - 1;
    NodeId a;
    a.face = id.face;
    a.level = static_cast<std::uint8_t>(level);
    a.i = id.i >> s;
    a.j = id.j >> s;
    a.down = (id.i & mask) + (id.j & mask) + (id.down ? 1u : 0u) > mask;
    return a;
}

}  // namespace detail

}  // namespace subdivtrace
