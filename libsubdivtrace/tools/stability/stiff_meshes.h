#pragma once
// Meshes with the stiff features of DESIGN.md section 9, built in code: shared
// by the `subdivtrace stability` table and the unit tests. All closed meshes
// are consistently oriented, counter-clockwise seen from outside.

#include "subdivtrace/mesh.h"

namespace subdivtrace::tools {

/// Regular icosahedron, circumradius 1: 12 vertices, 20 faces.
Mesh icosahedron();

/// Closed icosahedron with one edge split very near an endpoint: two needle
/// triangles of aspect ratio ~1e6 (longest edge squared over twice the area).
Mesh sliver_mesh();

/// Closed icosahedron with an exactly collinear T-junction closed by a
/// zero-area triangle.
Mesh zero_area_mesh();

/// Closed bipyramid: a ring of n vertices and two apexes of valence n.
Mesh high_valence_fan(int n);

/// A thin closed lens (two cones of height 1e-4 on a unit ring of 8): faces
/// that meet at the rim have normals ~180 degrees apart.
Mesh folded();

/// Axis-aligned box [lo, hi] appended to `m`: 12 triangles facing out, each
/// face split along the diagonal from its (min, min) to its (max, max) corner.
void add_box(Mesh& m, const Vec3& lo, const Vec3& hi);

/// p * scale + offset for every position (normals and UVs unchanged).
Mesh offset_mesh(Mesh mesh, const Vec3& offset, double scale);

}  // namespace subdivtrace::tools
