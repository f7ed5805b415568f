#pragma once
// The mesh file readers (one file each: read_obj.cpp, read_off.cpp,
// read_ply.cpp, read_stl.cpp). Each parses the bytes of a whole file into
// Polygons, failing with MeshError("<path>: <reason>") on anything it cannot
// read; mesh_from_polygons then triangulates, welds and validates. Fuzz
// harnesses (tests/fuzz) call them directly, without a file.

#include <cstdint>
#include <string>
#include <vector>

#include "subdivtrace/mesh.h"

namespace subdivtrace::io {

/// Polygons as parsed, before triangulation.
struct Polygons {
    std::vector<Vec3> positions;
    std::vector<Vec3> normals;
    std::vector<Vec2> uvs;
    std::vector<std::uint32_t> sizes;  // corners per polygon
    std::vector<std::int64_t> v;       // corner vertex indices (0-based)
    std::vector<std::int64_t> vn;      // empty or one per corner
    std::vector<std::int64_t> vt;      // empty or one per corner
};

Polygons read_obj(const std::string& path, const std::string& data,
                  std::vector<std::string>* warnings);
Polygons read_off(const std::string& path, const std::string& data);
Polygons read_ply(const std::string& path, const std::string& data,
                  std::vector<std::string>* warnings);
/// Binary when the size is exactly 84 + 50 n, else ASCII if it starts with "solid".
Polygons read_stl(const std::string& path, const std::string& data,
                  std::vector<std::string>* warnings);

/// The reader of extension `ext` ("obj", "off", "ply" or "stl", lower case)
/// applied to `data`; fails naming `path` for any other extension.
Polygons read_polygons(const std::string& ext, const std::string& path, const std::string& data,
                       std::vector<std::string>* warnings);

/// Fan-triangulates (one warning counting the polygons) and hands over to
/// mesh_from_arrays, which checks ranges and values, welds coincident vertices
/// and drops triangles that repeat a vertex. Consumes `in`: its arrays are
/// moved into the mesh or freed as soon as they are read.
Mesh mesh_from_polygons(Polygons& in, const std::string& path,
                        std::vector<std::string>* warnings, const WeldOptions& weld,
                        WeldReport* report);

}  // namespace subdivtrace::io
