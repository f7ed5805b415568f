#pragma once
/// \file node_id.h
/// Names of the hierarchy's nodes: a node is a triangle of the uniform
/// level-L mesh, named by its base triangle and its position in that
/// triangle's grid, so children, ancestors and corners follow by arithmetic.

#include <array>
#include <cstdint>

namespace subdivtrace {

/// A triangle of the uniform level-`level` mesh inside base triangle `face`.
/// Grid triangle (i, j) of resolution 2^level: "up" has corners (i,j) (i+1,j)
/// (i,j+1), "down" has (i+1,j) (i+1,j+1) (i,j+1) (weights on the base
/// triangle's corners 1 and 2, in units of 2^-level).
struct NodeId {
    std::uint32_t face = 0;
    std::uint8_t level = 0;
    bool down = false;
    std::uint32_t i = 0;
    std::uint32_t j = 0;

    bool operator==(const NodeId& o) const {
        return face == o.face && level == o.level && down == o.down && i == o.i && j == o.j;
    }
};

/// The level-0 node of base triangle `face`.
inline NodeId root_node(std::uint32_t face) { return NodeId{face, 0, false, 0, 0}; }

/// Which corner of a child is which point of its parent: corner k of child c
/// is parent corner `index` (is_edge false) or the midpoint of parent edge
/// `index` (is_edge true; edge e runs from corner e to corner (e+1)%3).
struct ChildCorner {
    bool is_edge;
    std::uint8_t index;
};
inline const std::array<ChildCorner, 3>& child_corners(bool parent_down, int child) {
    // Derived from the grid coordinates in child_of (see uniform.h for the order).
    static constexpr std::array<std::array<ChildCorner, 3>, 4> up = {{
        {{{false, 0}, {true, 0}, {true, 2}}},
        {{{true, 0}, {false, 1}, {true, 1}}},
        {{{true, 2}, {true, 1}, {false, 2}}},
        {{{true, 0}, {true, 1}, {true, 2}}},
    }};
    static constexpr std::array<std::array<ChildCorner, 3>, 4> down = {{
        {{{false, 0}, {true, 0}, {true, 2}}},
        {{{true, 0}, {false, 1}, {true, 1}}},
        {{{true, 2}, {true, 1}, {false, 2}}},
        {{{true, 2}, {true, 0}, {true, 1}}},
    }};
    return parent_down ? down[child] : up[child];
}

/// Child c (0..3) of a node; children of a node cover it exactly, in the
/// order subdivide_uniform uses (uniform.h). (Inline, as the arithmetic
/// below: the tracer asks for children millions of times per frame.)
inline NodeId child_of(const NodeId& node, int child) {
    static constexpr std::uint32_t up_di[4] = {0, 1, 0, 0}, up_dj[4] = {0, 0, 1, 0};
    static constexpr std::uint32_t down_di[4] = {1, 1, 0, 1}, down_dj[4] = {0, 1, 1, 1};
    NodeId c;
    c.face = node.face;
    c.level = static_cast<std::uint8_t>(node.level + 1);
    c.down = node.down ? child != 3 : child == 3;
    c.i = 2 * node.i + (node.down ? down_di : up_di)[child];
    c.j = 2 * node.j + (node.down ? down_dj : up_dj)[child];
    return c;
}

/// Grid coordinates (i, j) of a node's corners at its level.
inline std::array<std::array<std::uint32_t, 2>, 3> node_corner_grid(const NodeId& n) {
    if (!n.down) return {{{n.i, n.j}, {n.i + 1, n.j}, {n.i, n.j + 1}}};
    return {{{n.i + 1, n.j}, {n.i + 1, n.j + 1}, {n.i, n.j + 1}}};
}

}  // namespace subdivtrace
