#pragma once
/// \file mesh_io.h
/// Mesh files in and out: OBJ, OFF, PLY (ASCII and binary), STL (ASCII and
/// binary), and POV-Ray mesh2 text. See docs/mesh_input.md.

#include <string>
#include <vector>

#include "subdivtrace/mesh.h"
#include "subdivtrace/uniform.h"

namespace subdivtrace {

/// Reads a mesh file; the format comes from the extension (.obj .off .ply .stl,
/// any case). Polygons are fan-triangulated, OBJ `v/vt/vn` corners become
/// corner_uvs / corner_normals, PLY and NOFF per-vertex normals become corner
/// normals. Throws MeshError "<path>: <reason>" for every bad input (missing,
/// empty or truncated file, a header whose counts the file size cannot hold,
/// out-of-range indices, NaN/Inf values, no faces); never allocates more than a
/// fixed multiple of the file size. Recoverable oddities (polygons, dropped
/// triangles that repeat a vertex, ignored statements) are appended to
/// `warnings`, each prefixed with the path. Coincident vertices are welded as
/// `weld` says (mesh_from_arrays; by default bit-identical positions become one
/// vertex, including an STL file's), and `report` (optional) counts them.
Mesh read_mesh(const std::string& path, std::vector<std::string>* warnings = nullptr,
               const WeldOptions& weld = {}, WeldReport* report = nullptr);

/// Writes `mesh` in the format of the extension (.obj .off .ply .stl). Normals
/// go where the format has them: OBJ `vn` (deduplicated, per corner), PLY
/// per-vertex nx ny nz (averaged where corners disagree), STL facet normals
/// (geometric); OFF has none. STL stores single precision, the others full
/// double precision. The file is written to a temporary name beside `path` and
/// renamed, so a failure leaves no partial output. Throws MeshError naming
/// `path` on an invalid mesh, an unknown extension or a write error.
void write_mesh(const std::string& path, const Mesh& mesh);
/// The same for a subdivided mesh, as write_mesh(path, to_mesh(sub)) writes
/// it, reading its normals in place (one per vertex, plus the corners that
/// differ) instead of a copy with one per corner.
void write_mesh(const std::string& path, const SubdividedMesh& sub);

/// POV-Ray 3.7 text `#declare IDENT = mesh2 { ... }`: vertex_vectors,
/// normal_vectors and uv_vectors (only if the mesh has them, deduplicated),
/// face_indices, normal_indices, uv_indices; numbers in full precision (%.17g).
/// `ident` must satisfy is_pov_identifier (else std::invalid_argument).
std::string mesh2_text(const Mesh& mesh, const std::string& ident);

/// Writes mesh2_text to `path` (temporary file + rename, like write_mesh),
/// streamed through a buffer rather than built in memory first.
void write_mesh2(const std::string& path, const Mesh& mesh, const std::string& ident);
/// The same for a subdivided mesh, as write_mesh2(path, to_mesh(sub), ident)
/// writes it, its normals read in place (write_mesh's overload).
void write_mesh2(const std::string& path, const SubdividedMesh& sub, const std::string& ident);

/// True if `text` is usable as a POV-Ray identifier: a letter, then letters,
/// digits or underscores, at most 40 characters. (Reserved words are all
/// lowercase; an identifier with an uppercase letter can never be one.)
bool is_pov_identifier(const std::string& text);

/// Turns any text (a file stem) into a POV-Ray identifier: other characters
/// become '_', a leading non-letter gets the prefix "Mesh_", the first letter
/// is capitalised, and the result is cut to 40 characters.
std::string pov_identifier(const std::string& text);

}  // namespace subdivtrace
