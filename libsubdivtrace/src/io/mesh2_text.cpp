// POV-Ray mesh2 text and identifiers (mesh_io.h).
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <stdexcept>

#include "io/io_util.h"
#include "io/mesh_out.h"
#include "subdivtrace/mesh_io.h"

namespace subdivtrace {

bool is_pov_identifier(const std::string& text) {
    if (text.empty() || text.size() > 40 || !std::isalpha(static_cast<unsigned char>(text[0])))
        return false;
    for (char c : text)
        if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_')) return false;
    return true;
}

std::string pov_identifier(const std::string& text) {
    std::string id;
    for (char c : text) {
        const auto u = static_cast<unsigned char>(c);
        id += (u < 128 && (std::isalnum(u) || c == '_')) ? c : '_';
    }
    if (id.empty() || !std::isalpha(static_cast<unsigned char>(id[0]))) id = "Mesh_" + id;
    id[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(id[0])));
    if (id.size() > 40) id.resize(40);
    return id;
}

namespace {

void require_identifier(const std::string& ident) {
    if (!is_pov_identifier(ident)) throw std::invalid_argument("not a POV-Ray identifier: '" + ident + "'");
}

/// The mesh2 text of `mesh`, handed to `append(const char*, std::size_t)`
/// piece by piece (into a string, or through a buffer into a file).
template <class Append>
void emit_mesh2(const io::MeshOut& mesh, const std::string& ident, Append&& append) {
    io::Dedup<Vec3, 3> normals;
    io::Dedup<Vec2, 2> uvs;
    std::vector<std::uint32_t> ni, ti;
    const std::size_t corners = 3 * mesh.triangles.size();
    if (mesh.has_normals()) {
        ni.reserve(corners);
        for (std::size_t c = 0; c < corners; ++c) ni.push_back(normals.add(mesh.normal(c)));
    }
    for (const Vec2& t : mesh.corner_uvs) ti.push_back(uvs.add(t));

    char buf[128];
    auto emit = [&](const char* fmt, auto... args) {
        const int n = std::snprintf(buf, sizeof buf, fmt, args...);
        append(buf, static_cast<std::size_t>(std::min<int>(n, static_cast<int>(sizeof buf) - 1)));
    };
    auto text = [&](const std::string& t) { append(t.data(), t.size()); };
    emit("// subdivtrace: %zu vertices, %zu triangles\n", mesh.positions.size(), mesh.triangles.size());
    text("#declare " + ident + " = mesh2 {\n");
    auto section = [&](const char* name, std::size_t count, auto&& item) {
        emit("  %s {\n    %zu", name, count);
        for (std::size_t i = 0; i < count; ++i) {
            append(",\n    ", 6);
            item(i);
        }
        append("\n  }\n", 5);
    };
    section("vertex_vectors", mesh.positions.size(), [&](std::size_t i) {
        const Vec3& p = mesh.positions[i];
        emit("<%.17g, %.17g, %.17g>", p.x, p.y, p.z);
    });
    if (mesh.has_normals())
        section("normal_vectors", normals.values.size(), [&](std::size_t i) {
            const Vec3& n = normals.values[i];
            emit("<%.17g, %.17g, %.17g>", n.x, n.y, n.z);
        });
    if (mesh.has_uvs())
        section("uv_vectors", uvs.values.size(),
                [&](std::size_t i) { emit("<%.17g, %.17g>", uvs.values[i].x, uvs.values[i].y); });
    const std::size_t nt = mesh.triangles.size();
    section("face_indices", nt, [&](std::size_t i) {
        const Triangle& t = mesh.triangles[i];
        emit("<%u, %u, %u>", t[0], t[1], t[2]);
    });
    if (mesh.has_normals())
        section("normal_indices", nt, [&](std::size_t i) {
            emit("<%u, %u, %u>", ni[3 * i], ni[3 * i + 1], ni[3 * i + 2]);
        });
    if (mesh.has_uvs())
        section("uv_indices", nt, [&](std::size_t i) {
            emit("<%u, %u, %u>", ti[3 * i], ti[3 * i + 1], ti[3 * i + 2]);
        });
    append("}\n", 2);
}

/// emit_mesh2 into `path` through a buffer of 1 MB (temporary file +
/// rename): the whole text in memory first had been about 100 bytes a
/// triangle at its peak.
void write_mesh2_file(const std::string& path, const io::MeshOut& mesh, const std::string& ident) {
    io::write_atomically(path, [&](std::FILE* f) {
        std::string buffer;
        constexpr std::size_t k_flush = std::size_t{1} << 20;
        buffer.reserve(k_flush + 256);
        emit_mesh2(mesh, ident, [&](const char* p, std::size_t n) {
            buffer.append(p, n);
            if (buffer.size() >= k_flush) {
                std::fwrite(buffer.data(), 1, buffer.size(), f);
                buffer.clear();
            }
        });
        std::fwrite(buffer.data(), 1, buffer.size(), f);
    });
}

}  // namespace

std::string mesh2_text(const Mesh& mesh, const std::string& ident) {
    require_identifier(ident);
    validate_mesh(mesh, "mesh2 " + ident);
    std::string out;
    out.reserve(80 * mesh.positions.size() + 40 * mesh.triangles.size() * 3);
    emit_mesh2(io::MeshOut::of(mesh), ident, [&](const char* p, std::size_t n) { out.append(p, n); });
    return out;
}

void write_mesh2(const std::string& path, const Mesh& mesh, const std::string& ident) {
    require_identifier(ident);
    validate_mesh(mesh, "mesh2 " + ident);
    write_mesh2_file(path, io::MeshOut::of(mesh), ident);
}

void write_mesh2(const std::string& path, const SubdividedMesh& sub, const std::string& ident) {
    require_identifier(ident);
    io::validate_subdivided(sub, "mesh2 " + ident);
    write_mesh2_file(path, io::MeshOut::of(sub), ident);
}

}  // namespace subdivtrace
