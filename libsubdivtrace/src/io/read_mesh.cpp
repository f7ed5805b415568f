// Mesh files in: read_mesh dispatches on the extension (mesh_io.h).
//
// The readers are our own, small and strict, rather than OpenMesh's: OpenMesh 9
// reserves memory from header counts before reading (an OFF or PLY header that
// claims 4e9 vertices ends in std::bad_alloc), drops faces it cannot add to its
// half-edge structure (non-manifold edges, bad indices, vertices that failed to
// parse) with only a line on std::cerr and still reports success, and accepts
// empty or truncated STL files as meshes without faces. Here every claimed count
// is checked against the bytes that follow before anything is reserved, every
// read is bounds-checked, and every problem becomes a MeshError naming the file.
#include "io/io_util.h"
#include "io/readers.h"
#include "subdivtrace/mesh_io.h"

namespace subdivtrace {

namespace io {

Polygons read_polygons(const std::string& ext, const std::string& path, const std::string& data,
                       std::vector<std::string>* warnings) {
    if (ext == "obj") return read_obj(path, data, warnings);
    if (ext == "off") return read_off(path, data);
    if (ext == "ply") return read_ply(path, data, warnings);
    if (ext == "stl") return read_stl(path, data, warnings);
    fail(path, "unsupported file format '" + ext + "' (expected .obj, .off, .ply or .stl)");
}

}  // namespace io

Mesh read_mesh(const std::string& path, std::vector<std::string>* warnings,
               const WeldOptions& weld, WeldReport* report) {
    const std::string ext = io::extension_of(path);
    if (ext != "obj" && ext != "off" && ext != "ply" && ext != "stl")
        io::fail(path,
                 "unsupported file format '" + ext + "' (expected .obj, .off, .ply or .stl)");
    // The file's bytes are freed once parsed: they had been the largest
    // part of reading's peak memory (a 117 MB OBJ export).
    io::Polygons polygons = io::read_polygons(ext, path, io::read_file(path), warnings);
    return io::mesh_from_polygons(polygons, path, warnings, weld, report);
}

}  // namespace subdivtrace
