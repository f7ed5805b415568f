#pragma once
/// \file mesh_report.h
/// What a mesh looks like to the schemes: counts, boundaries, non-manifold
/// edges, degenerate and duplicate triangles, valences (`subdivtrace info`).

#include <cstddef>
#include <vector>

#include <string>

#include "subdivtrace/mesh.h"
#include "subdivtrace/scheme.h"

namespace subdivtrace {

/// Counts over a Mesh; an edge is an unordered vertex pair used by a triangle.
struct MeshReport {
    std::size_t vertices = 0;
    std::size_t faces = 0;
    std::size_t edges = 0;
    /// Vertices no triangle uses (kept, ignored by the schemes).
    std::size_t unreferenced_vertices = 0;
    /// Edges with exactly one triangle.
    std::size_t boundary_edges = 0;
    /// Edges with more than two triangles (the schemes treat them as boundary).
    std::size_t nonmanifold_edges = 0;
    /// Vertices on a non-manifold edge or with several separate fans of
    /// triangles: the schemes keep them fixed (corners).
    std::size_t singular_vertices = 0;
    /// Triangles of exactly zero area (collinear corners, decided exactly).
    std::size_t degenerate_faces = 0;
    /// Triangles whose vertex set equals an earlier triangle's (either winding).
    std::size_t duplicate_faces = 0;
    /// Connected components (through shared vertices) of the used vertices.
    std::size_t components = 0;
    /// valence_histogram[k] = number of used vertices with k distinct neighbours.
    std::vector<std::size_t> valence_histogram;
    int min_valence = 0;
    int max_valence = 0;
    /// Bounds of the used vertices.
    Bounds3 bounds;
    /// Every edge has exactly two triangles.
    bool closed = false;
    bool has_normals = false;
    bool has_uvs = false;
    /// Edges whose two triangles give different normals at an endpoint: the
    /// schemes keep them sharp (docs/schemes.md, "Creases and boundaries").
    std::size_t crease_edges = 0;
};

/// Analyses `mesh` (which must satisfy validate_mesh). Linear-logarithmic time.
MeshReport analyze_mesh(const Mesh& mesh);

/// The warning a user needs when `scheme` will not use the mesh's normals as
/// normals (Loop and Butterfly read positions only; split normals still mark
/// creases), naming `source`; empty when there is nothing to say.
std::string given_normals_warning(const Mesh& mesh, SchemeKind scheme, const std::string& source);

/// Exact test: true if a, b, c are collinear (the triangle has zero area).
/// Uses exact orientation signs of the three axis projections, so it neither
/// misses a tiny sliver nor calls a rounded-to-zero cross product degenerate.
bool is_degenerate_triangle(const Vec3& a, const Vec3& b, const Vec3& c);

}  // namespace subdivtrace
