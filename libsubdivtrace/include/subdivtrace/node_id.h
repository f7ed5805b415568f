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
const std::array<ChildCorner, 3>& child_corners(bool parent_down, int child);

/// Child c (0..3) of a node; children of a node cover it exactly, in the
/// order subdivide_uniform uses (uniform.h).
NodeId child_of(const NodeId& node, int child);

/// Grid coordinates (i, j) of a node's corners at its level.
std::array<std::array<std::uint32_t, 2>, 3> node_corner_grid(const NodeId& node);

}  // namespace subdivtrace
