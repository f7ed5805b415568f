// Mesh files out: OBJ, OFF, binary PLY, binary STL (mesh_io.h).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "finite_values.h"
#include "io/io_util.h"
#include "io/mesh_out.h"
#include "subdivtrace/mesh_io.h"
#include "subdivtrace/uniform.h"

namespace subdivtrace {

namespace io {

void validate_subdivided(const SubdividedMesh& sub, const std::string& path) {
    if (sub.triangles.empty()) fail(path, "no faces");
    detail::check_finite(sub.positions, "vertex", path);
    detail::check_finite(sub.vertex_normals, "vertex normal", path);
    for (const SubdividedMesh::SplitCorner& s : sub.split_corners)
        if (!detail::is_finite(s.normal)) fail(path, "corner normal " + std::to_string(s.slot) + " is not finite");
}

}  // namespace io

namespace {

using io::Dedup;
using io::MeshOut;

/// Little-endian binary values out through a buffer of its own: one
/// fwrite per value (8 bytes) had held a PLY of 10 M vertices to about
/// 80 MB/s. Flushed when full and by flush(); write errors stay on the FILE
/// (write_atomically checks it).
class BinaryOut {
public:
    explicit BinaryOut(std::FILE* f) : f_(f) { buffer_.reserve(k_capacity); }
    ~BinaryOut() { flush(); }
    void put_le(std::uint64_t bits, int bytes) {
        if (buffer_.size() + 8 > k_capacity) flush();
        for (int i = 0; i < bytes; ++i) buffer_.push_back(static_cast<unsigned char>(bits >> (8 * i)));
    }
    void put_f64(double d) {
        std::uint64_t u;
        std::memcpy(&u, &d, 8);
        put_le(u, 8);
    }
    void put_f32(double d) {
        const float x = static_cast<float>(d);
        std::uint32_t u;
        std::memcpy(&u, &x, 4);
        put_le(u, 4);
    }
    void put_bytes(const void* data, std::size_t n) {
        flush();
        std::fwrite(data, 1, n, f_);
    }
    void flush() {
        if (!buffer_.empty()) std::fwrite(buffer_.data(), 1, buffer_.size(), f_);
        buffer_.clear();
    }

private:
    static constexpr std::size_t k_capacity = std::size_t{1} << 20;
    std::FILE* f_;
    std::vector<unsigned char> buffer_;
};

void write_obj(std::FILE* f, const MeshOut& mesh) {
    std::fprintf(f, "# subdivtrace: %zu vertices, %zu triangles\n", mesh.positions.size(),
                 mesh.triangles.size());
    for (const Vec3& p : mesh.positions) std::fprintf(f, "v %.17g %.17g %.17g\n", p.x, p.y, p.z);
    Dedup<Vec2, 2> uvs;
    Dedup<Vec3, 3> normals;
    std::vector<std::uint32_t> vt, vn;
    for (const Vec2& t : mesh.corner_uvs) vt.push_back(uvs.add(t));
    if (mesh.has_normals())
        for (std::size_t c = 0; c < 3 * mesh.triangles.size(); ++c) vn.push_back(normals.add(mesh.normal(c)));
    for (const Vec2& t : uvs.values) std::fprintf(f, "vt %.17g %.17g\n", t.x, t.y);
    for (const Vec3& n : normals.values) std::fprintf(f, "vn %.17g %.17g %.17g\n", n.x, n.y, n.z);
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        std::fputc('f', f);
        for (int k = 0; k < 3; ++k) {
            const std::size_t c = 3 * t + static_cast<std::size_t>(k);
            std::fprintf(f, " %u", mesh.triangles[t][static_cast<std::size_t>(k)] + 1);
            if (!vt.empty()) std::fprintf(f, "/%u", vt[c] + 1);
            if (!vn.empty()) std::fprintf(f, vt.empty() ? "//%u" : "/%u", vn[c] + 1);
        }
        std::fputc('\n', f);
    }
}

void write_off(std::FILE* f, const MeshOut& mesh) {
    std::fprintf(f, "OFF\n%zu %zu 0\n", mesh.positions.size(), mesh.triangles.size());
    for (const Vec3& p : mesh.positions) std::fprintf(f, "%.17g %.17g %.17g\n", p.x, p.y, p.z);
    for (const Triangle& t : mesh.triangles) std::fprintf(f, "3 %u %u %u\n", t[0], t[1], t[2]);
}

void write_ply(std::FILE* f, const MeshOut& mesh) {
    // Per-vertex attributes: a corner value if all of a vertex's corners agree,
    // else (normals only) their normalised average.
    const std::size_t nv = mesh.positions.size();
    std::vector<Vec3> normals(mesh.has_normals() ? nv : 0, Vec3(0.0));
    std::vector<Vec2> uvs(mesh.has_uvs() ? nv : 0, Vec2(0.0));
    std::vector<unsigned char> seen(nv, 0), normal_agree(nv, 1), uv_agree(nv, 1);
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
        for (std::size_t k = 0; k < 3; ++k) {
            const std::uint32_t v = mesh.triangles[t][k];
            const std::size_t c = 3 * t + k;
            if (mesh.has_normals()) {
                const Vec3 n = mesh.normal(c);
                if (seen[v] && normals[v] != n) normal_agree[v] = 0;
                if (!seen[v]) normals[v] = n;
            }
            if (mesh.has_uvs()) {
                if (seen[v] && uvs[v] != mesh.corner_uvs[c]) uv_agree[v] = 0;
                if (!seen[v]) uvs[v] = mesh.corner_uvs[c];
            }
            seen[v] = 1;
        }
    const bool normals_disagree =
        mesh.has_normals() && !std::all_of(normal_agree.begin(), normal_agree.end(), [](auto a) { return a; });
    if (normals_disagree) {
        // Averages only where a vertex's corners disagree (creases): a
        // smooth mesh needs no second array of vertex normals.
        std::vector<Vec3> sum(nv, Vec3(0.0));
        for (std::size_t c = 0; c < 3 * mesh.triangles.size(); ++c)
            sum[mesh.triangles[c / 3][c % 3]] += mesh.normal(c);
        for (std::size_t v = 0; v < nv; ++v)
            if (!normal_agree[v]) {
                const double len = glm::length(sum[v]);
                normals[v] = len > 0.0 ? sum[v] / len : Vec3(0.0);
            }
    }
    const bool write_uv =
        mesh.has_uvs() && std::all_of(uv_agree.begin(), uv_agree.end(), [](auto a) { return a; });

    std::fprintf(f,
                 "ply\nformat binary_little_endian 1.0\ncomment subdivtrace\n"
                 "element vertex %zu\nproperty double x\nproperty double y\nproperty double z\n",
                 nv);
    if (mesh.has_normals())
        std::fputs("property double nx\nproperty double ny\nproperty double nz\n", f);
    if (write_uv) std::fputs("property double u\nproperty double v\n", f);
    std::fprintf(f, "element face %zu\nproperty list uchar uint vertex_indices\nend_header\n",
                 mesh.triangles.size());
    BinaryOut out(f);
    for (std::size_t v = 0; v < nv; ++v) {
        for (int i = 0; i < 3; ++i) out.put_f64(mesh.positions[v][i]);
        if (mesh.has_normals())
            for (int i = 0; i < 3; ++i) out.put_f64(normals[v][i]);
        if (write_uv)
            for (int i = 0; i < 2; ++i) out.put_f64(uvs[v][i]);
    }
    for (const Triangle& t : mesh.triangles) {
        out.put_le(3, 1);
        for (std::uint32_t v : t) out.put_le(v, 4);
    }
}

void write_stl(std::FILE* f, const MeshOut& mesh) {
    char header[80] = {};
    std::snprintf(header, sizeof header, "subdivtrace binary STL");
    BinaryOut out(f);
    out.put_bytes(header, 80);
    out.put_le(mesh.triangles.size(), 4);
    for (const Triangle& t : mesh.triangles) {
        const Vec3 &a = mesh.positions[t[0]], &b = mesh.positions[t[1]], &c = mesh.positions[t[2]];
        Vec3 n = glm::cross(b - a, c - a);
        const double len = glm::length(n);
        n = len > 0.0 && std::isfinite(len) ? n / len : Vec3(0.0);
        for (int i = 0; i < 3; ++i) out.put_f32(n[i]);
        for (const Vec3* p : {&a, &b, &c})
            for (int i = 0; i < 3; ++i) out.put_f32((*p)[i]);
        out.put_le(0, 2);
    }
}

/// Writes `mesh` (validated by the caller) in the format of the extension.
void write_checked(const std::string& path, const std::string& ext, const MeshOut& mesh) {
    io::write_atomically(path, [&](std::FILE* f) {
        if (ext == "obj")
            write_obj(f, mesh);
        else if (ext == "off")
            write_off(f, mesh);
        else if (ext == "ply")
            write_ply(f, mesh);
        else
            write_stl(f, mesh);
    });
}

/// The extension of `path` if a writer has it, else fails naming `path`.
std::string writable_extension(const std::string& path) {
    const std::string ext = io::extension_of(path);
    if (ext != "obj" && ext != "off" && ext != "ply" && ext != "stl")
        io::fail(path, "cannot write format '" + ext + "' (expected .obj, .off, .ply or .stl)");
    return ext;
}

}  // namespace

void write_mesh(const std::string& path, const Mesh& mesh) {
    const std::string ext = writable_extension(path);
    validate_mesh(mesh, path);
    write_checked(path, ext, MeshOut::of(mesh));
}

void write_mesh(const std::string& path, const SubdividedMesh& sub) {
    const std::string ext = writable_extension(path);
    io::validate_subdivided(sub, path);
    write_checked(path, ext, MeshOut::of(sub));
}

}  // namespace subdivtrace
