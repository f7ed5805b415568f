#pragma once
// A slow, plain reference of the normal scheme's uniform subdivision, for the
// tests only. OpenMesh is the independent reference for Loop and Butterfly;
// it has no normal scheme, so this one is written as plainly as possible and
// shares nothing with the library's connectivity code: edges are found in a
// std::map, vertex normals are summed over every triangle, boundary
// neighbours are collected by counting each edge's triangles. It shares only
// the per-stencil formulas of scheme.h (normal_edge_point,
// normal_curve_edge_point, angle_weighted_normal), which test_schemes.cpp
// checks on their own. Smooth meshes only: no creases, no given normals.
#include <vector>

#include "subdivtrace/mesh.h"

namespace subdivtrace::testmesh {

struct ReferenceLevel {
    std::vector<Vec3> positions;
    /// Children 4t .. 4t+3 of triangle t, corners in uniform.h's order.
    std::vector<Triangle> triangles;
    /// Each vertex's normalised sum of angle-weighted corner normals.
    std::vector<Vec3> vertex_normals;
};

/// The normal scheme applied `levels` times to `mesh` (which must have no
/// creases and no given normals), every level recomputed from scratch.
ReferenceLevel reference_normal_scheme(const Mesh& mesh, int levels);

}  // namespace subdivtrace::testmesh
