#pragma once
// Test meshes shared by the unit tests: analytic shapes (icosahedron, icosphere,
// torus), an irregular closed mesh with valences 3..12, and the stiff cases of
// DESIGN.md section 9. All closed meshes are consistently oriented, counter-
// clockwise seen from outside. Also: conversion to and from OpenMesh (the
// independent reference for Loop and Butterfly) and a position matcher.

#include <cstdint>
#include <vector>

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include "stability/stiff_meshes.h"
#include "subdivtrace/mesh.h"

namespace subdivtrace::testmesh {

// The stiff meshes the `subdivtrace stability` table builds too:
// icosahedron, sliver_mesh, zero_area_mesh, high_valence_fan, folded,
// add_box, offset_mesh (libsubdivtrace/tools/stability/stiff_meshes.h).
using tools::add_box;
using tools::folded;
using tools::high_valence_fan;
using tools::icosahedron;
using tools::offset_mesh;
using tools::sliver_mesh;
using tools::zero_area_mesh;

/// The icosahedron split 1-to-4 `subdivisions` times with every vertex
/// projected to the unit sphere (1 -> 42 vertices, 80 faces).
Mesh icosphere(int subdivisions);

/// Torus around the z axis: `rings` steps around the big circle (radius R),
/// `sides` steps around the tube (radius r); 2 * rings * sides triangles.
Mesh torus(int rings, int sides, double R, double r);

/// A closed, manifold, genus-0 mesh with vertex valences from 3 to 12 (both
/// reached): a 320-face icosphere with random, then targeted, edge flips that
/// keep every face facing outward, then radially perturbed positions.
Mesh irregular_closed(unsigned seed);

/// Open bumpy patch over [-1, 1]^2 with (n + 1)^2 vertices and 2 n^2 triangles;
/// vertex (i, j) (i along x, j along y) has index j * (n + 1) + i. Diagonals
/// alternate, so interior valences are 4, 6 and 8.
Mesh open_grid(int n);
/// Index of vertex (i, j) of open_grid(n).
inline std::uint32_t grid_index(int n, int i, int j) {
    return static_cast<std::uint32_t>(j * (n + 1) + i);
}

/// A unit sphere made like the Utah teapot: 6 patches (the cube's faces, each
/// an n x n grid of quads split into triangles, projected onto the sphere),
/// each patch with its own (n + 1)^2 vertices, so every seam vertex is written
/// once per patch that touches it, with bit-identical positions (each is the
/// normalised cube point of the same integer lattice coordinates). Per-vertex
/// UVs are each patch's own grid (i / n, j / n): along a seam, one position
/// has several UVs. `uv_indices` is empty (the face indices index the UVs).
/// With `shared`, the same sphere with one vertex per position, found through
/// the integer lattice (not by comparing floats), numbered in order of first
/// appearance in the patch-split arrays; its UVs are per corner (uv_indices).
/// Faces are counter-clockwise seen from outside, in the same order in both.
MeshArrays patch_split_sphere(int n, bool shared);

/// Axis-aligned cube [-1, 1]^3, 12 triangles, with faceted normals: every
/// corner carries its face's normal, so its 12 edges are creases (the face diagonals are not) (as a mesh2
/// cube written with one normal per face).
Mesh faceted_cube();

/// Closed cylinder around the z axis (radius r, z in [-h, h]), `n` sides,
/// caps fanned around a centre vertex. Side corners carry the exact radial
/// normal, cap corners the axial one: the two rims are creases.
Mesh split_normal_cylinder(int n, double r, double h);

/// icosphere(subdivisions) with the exact sphere normal at every corner.
Mesh icosphere_with_normals(int subdivisions);

/// The unit sphere made from an octahedron split 1-to-4 `subdivisions` times
/// (projected), cut at the equator into its upper (z >= 0) or lower half:
/// two open meshes whose boundaries are the same polyline in z = 0.
Mesh octasphere_half(int subdivisions, bool upper);

/// Longest edge squared over twice the area (infinite for zero area).
double max_aspect_ratio(const Mesh& mesh);

/// Vertex valences (distinct neighbours through triangle edges).
std::vector<int> valences(const Mesh& mesh);

/// A triangle rotated so its smallest index comes first (same orientation):
/// equal for the same face whichever corner it starts at.
Triangle canonical(Triangle t);

/// Length of the bounding-box diagonal of the positions.
double bbox_diagonal(const std::vector<Vec3>& positions);

/// Matches each of `a` to its nearest point of `b` (grid search, cell size
/// `cell`). Returns the matched indices (UINT32_MAX where no point of b lies in
/// the neighbouring cells) and the largest matched distance in *max_distance.
std::vector<std::uint32_t> match_positions(const std::vector<Vec3>& a,
                                           const std::vector<Vec3>& b, double cell,
                                           double* max_distance);

/// OpenMesh's TriMesh in double precision.
struct DTraits : OpenMesh::DefaultTraits {
    using Point = OpenMesh::Vec3d;
    using Normal = OpenMesh::Vec3d;
};
using OmMesh = OpenMesh::TriMesh_ArrayKernelT<DTraits>;

/// Same vertices (same indices) and faces (same order); attributes dropped.
OmMesh to_openmesh(const Mesh& mesh);
Mesh from_openmesh(const OmMesh& om);

}  // namespace subdivtrace::testmesh
