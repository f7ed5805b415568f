#pragma once
// Loop's surface over a regular triangle (its three corners of valence 6,
// with no boundary or crease at them) is the quartic box spline of 12
// control points, one polynomial piece: a Bezier triangle of degree 4 whose
// 15 points are fixed combinations of the 12 (Lai 1992; Stam 1998). The
// Bezier net holds the surface in its convex hull, and so every limit point
// drawn below the triangle at any level: what a regular node's shell bounds
// (node_shell.cpp). Below a triangle with an irregular corner, every part
// but the one at that corner is such a triangle a level or more down, and
// the part at the corner shrinks by half with each level (LoopCornerFrame).

#include <array>
#include <cstdint>
#include <vector>

#include "patch.h"
#include "subdivtrace/shell.h"

namespace subdivtrace::detail {

/// The 12 control points of a regular triangle ABC, placed on the lattice
/// where A = (0, 0), B = (1, 0), C = (0, 1) and a vertex's six neighbours lie
/// at +-(1, 0), +-(0, 1), +-(1, -1): A, B, C, then (-1, 0), (0, -1), (1, -1),
/// (-1, 1), (2, 0), (1, 1), (2, -1), (0, 2), (-1, 2).
using LoopPatchPoints = std::array<Vec3, 12>;

/// The 15 points of the degree-4 Bezier net, b_abc (a + b + c = 4: the
/// weights of A, B and C), in the order of `k_loop_bezier_index`.
using LoopBezierNet = std::array<Vec3, 15>;

/// (a, b, c) of each point of a LoopBezierNet.
extern const std::array<std::array<std::uint8_t, 3>, 15> k_loop_bezier_index;

/// The Bezier net of the patch of `points` (exact rational weights, /24).
LoopBezierNet loop_bezier_net(const LoopPatchPoints& points);

/// The control points of patch triangle t (level p.level), from its
/// corners' ordered rings (after finish()), where each corner has a whole
/// ring of valence 6 in one sector and no curve edge, and the rings agree
/// on the lattice (false otherwise: the patch is not regular).
bool loop_patch_points(const Patch& p, std::uint32_t t, LoopPatchPoints& out);

/// Grows `shell` by the corners' rings one level down of patch triangle t's
/// child at corner c (the whole triangle's bound, corner by corner): the
/// corner's new position and the points of its edges in t's sector. Loop's
/// stencils are convex combinations, so what a child draws lies in the hull
/// of its corners' rings.
void grow_by_corner_ring(const Patch& p, const Patch& next, std::uint32_t t, int c, Shell& shell);

/// Patch triangle t's children one level down, for Loop's shells: the
/// points of its neighbourhood there (on the lattice of LoopPatchPoints
/// with coordinates doubled: t's new corners A1, B1, C1, the points mXY of
/// its edges and of the edges to the vertices D, E, F across them), and the
/// control points of each child that is regular (corner children 0, 1, 2
/// at t's corners, 3 the middle one, which always is).
struct LoopChildren {
    Vec3 A1, B1, C1, mAB, mBC, mCA, mAD, mBD, mBE, mCE, mCF, mAF;
    std::array<std::uint32_t, 3> across{};  ///< patch vertices D, E, F
    std::array<bool, 3> regular{};
    std::array<LoopPatchPoints, 4> points;
};
/// Fills `out` for patch triangle t (finished, with `next` its next level's
/// points around t); false where an edge of t is a boundary or crease, a
/// point is missing, or the neighbourhood does not fit the lattice.
bool loop_children_points(const Patch& p, const Patch& next, std::uint32_t t, LoopChildren& out);

/// The neighbourhood of the child at an irregular corner P of a node, one
/// level down, on the lattice of loop_patch.h with P = (0, 0): the child is
/// (P, X, Y) with X = (2, 0) on the node's edge to its next corner and
/// Y = (0, 2) on the edge from its previous one; M = (2, 2) across XY;
/// XB = (4, 0) and YC = (0, 4) the node's other corners; XD1 = (2, -2) and
/// XD2 = (4, -2) below PX, YF1 = (-2, 2) and YF2 = (-2, 4) beyond PY; and
/// P's whole ring counter-clockwise from X (X, Y, YF1, ..., XD1). These are
/// the control points the child depends on (the vertices of every triangle
/// at one of its corners), so the hull of them all holds everything drawn
/// below it.
struct LoopCornerFrame {
    Vec3 P, X, Y, M, XB, YC, XD1, XD2, YF1, YF2;
    std::vector<Vec3> ring;
    /// Grows `shell` by every point of the frame.
    void grow(Shell& shell) const;
};

/// The frame of the child at corner c of patch triangle t (finished, with
/// `next` its next level's points around t, and `ch` from
/// loop_children_points). False where that corner lies on a boundary or
/// crease, or its ring does not close as the lattice says.
bool loop_corner_frame(const Patch& p, const Patch& next, std::uint32_t t, int c, const LoopChildren& ch,
                       LoopCornerFrame& out);

/// The frame's child one level further down: of its four children, the
/// middle one and those at X and Y have corners of valence 6, so each is a
/// Bezier triangle (`nets`, in LoopPatchPoints order: middle, at X, at Y);
/// the one at P depends on `below`, the frame one level down (Loop's
/// interior rules applied to the frame's points), whose hull is about half
/// the size of this frame's.
void refine_corner_frame(const LoopCornerFrame& frame, std::array<LoopPatchPoints, 3>& nets,
                         LoopCornerFrame& below);

/// Levels below a corner's child that Loop's shells refine its frame
/// (grow_by_children): the hull left at the corner halves with each. In
/// Loop's bunny close-up (320x240) a ray visited 19.3 nodes with the
/// corners' rings, then 12.2, 9.9, 8.9 and 8.6 with 1-4 levels; whole
/// process, each level after the first took 0.86x, 0.94x, then 1.03x the
/// CPU of the one before (docs/benchmarks.md).
constexpr int k_loop_corner_levels = 3;

/// Grows `shell` by everything Loop draws below patch triangle t (finished,
/// with `next` its next level's points around t), child by child: the
/// Bezier net of each child whose corners are regular one level down (the
/// middle child always, a corner's child where that corner is regular);
/// a child at a corner that is not regular, by the nets of its frame
/// refined k_loop_corner_levels times and the hull of the last frame, or
/// where that does not apply (a boundary or crease at the corner), by the
/// box of its corners' rings one level down. False (shell untouched) where
/// an edge of t is a boundary or crease or the neighbourhood does not fit
/// the lattice.
bool grow_by_children(const Patch& p, const Patch& next, std::uint32_t t, Shell& shell);

}  // namespace subdivtrace::detail
