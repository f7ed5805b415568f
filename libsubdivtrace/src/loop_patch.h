#pragma once
// Loop's surface over a regular triangle (its three corners of valence 6,
// with no boundary or crease at them) is the quartic box spline of 12
// control points, one polynomial piece: a Bezier triangle of degree 4 whose
// 15 points are fixed combinations of the 12 (Lai 1992; Stam 1998). The
// Bezier net holds the surface in its convex hull, and so every limit point
// drawn below the triangle at any level: what a regular node's shell bounds
// (node_shell.cpp).

#include <array>
#include <cstdint>

#include "patch.h"

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

}  // namespace subdivtrace::detail
