// OFF reader (readers.h): Princeton/Geomview [ST][C][N]OFF, counts, vertices, faces.
#include "io/readers.h"

#include <cstdint>

#include "huge_pages.h"
#include "io/io_util.h"
#include "io/text_cursor.h"

namespace subdivtrace::io {

Polygons read_off(const std::string& path, const std::string& data) {
    Cursor c{data.data(), data.data() + data.size()};
    c.skip_all(true);
    const std::string_view head = c.word();
    if (head.size() < 3 || head.substr(head.size() - 3) != "OFF")
        fail(path, "not an OFF file (first word is " + quoted(head) + ", expected 'OFF')");
    bool has_uv = false, has_normal = false;
    for (std::string_view pre = head.substr(0, head.size() - 3); !pre.empty();) {
        if (pre.substr(0, 2) == "ST") {
            has_uv = true;
            pre.remove_prefix(2);
        } else if (pre[0] == 'C') {
            pre.remove_prefix(1);
        } else if (pre[0] == 'N') {
            has_normal = true;
            pre.remove_prefix(1);
        } else {
            fail(path, "unsupported OFF variant " + quoted(head) +
                           " (supported: OFF, COFF, NOFF, STOFF and combinations)");
        }
    }
    if (!c.at_line_end(true)) {
        Cursor peek = c;
        if (equals_nocase(peek.word(), "BINARY")) fail(path, "binary OFF is not supported");
    }

    const std::int64_t nv = expect_int_any(c, path, "the vertex count", true);
    const std::int64_t nf = expect_int_any(c, path, "the face count", true);
    if (!c.at_line_end(true)) expect_int_any(c, path, "the edge count", true);
    c.skip_line();
    if (nv < 0 || nf < 0) fail(path, "negative count in header");
    if (nv > k_max_count)
        fail(path, "header claims " + std::to_string(nv) + " vertices (more than 2^32 - 1)");
    if (nf > k_max_count)
        fail(path, "header claims " + std::to_string(nf) + " faces (more than 2^32 - 1)");
    // Each value takes at least a digit and a separator.
    const std::int64_t per_vertex = 2 * (3 + (has_normal ? 3 : 0) + (has_uv ? 2 : 0));
    const std::int64_t per_face = 2 * 4;
    const std::int64_t available = (c.end - c.p) + 1;
    if (exceeds(nv, per_vertex, available) || exceeds(nf, per_face, available) ||
        nv * per_vertex + nf * per_face > available)
        fail(path, "header claims " + std::to_string(nv) + " vertices and " + std::to_string(nf) +
                       " faces, but only " + std::to_string(available - 1) +
                       " bytes follow (truncated file or bad header)");
    if (nf == 0) fail(path, "no faces (header says 0)");

    Polygons m;
    // Sizes from the header (checked against the file's above), allocated
    // once on huge pages (huge_pages.h); faces reserved as triangles.
    detail::reserve_huge(m.positions, static_cast<std::size_t>(nv));
    if (has_normal) detail::reserve_huge(m.normals, static_cast<std::size_t>(nv));
    if (has_uv) detail::reserve_huge(m.uvs, static_cast<std::size_t>(nv));
    detail::reserve_huge(m.sizes, static_cast<std::size_t>(nf));
    detail::reserve_huge(m.v, 3 * static_cast<std::size_t>(nf));
    for (std::int64_t i = 0; i < nv; ++i) {
        c.skip_all(true);
        m.positions.push_back(expect_vec3_any(c, path, "vertex", true));
        if (has_normal) m.normals.push_back(expect_vec3_any(c, path, "normal", true));
        if (has_uv) {
            Vec2 t;
            t.x = expect_double_any(c, path, "texture coordinate", true);
            t.y = expect_double_any(c, path, "texture coordinate", true);
            m.uvs.push_back(t);
        }
        c.skip_line();  // colours
    }
    for (std::int64_t f = 0; f < nf; ++f) {
        const std::int64_t k = expect_int_any(c, path, "a face's corner count", true);
        if (k < 3)
            fail(path, c.where() + "face " + std::to_string(f) + " has " + std::to_string(k) +
                           " corners (at least 3 needed)");
        if (exceeds(k, 2, (c.end - c.p) + 1))
            fail(path, c.where() + "face " + std::to_string(f) + " claims " + std::to_string(k) +
                           " corners, more than the file holds (truncated?)");
        for (std::int64_t i = 0; i < k; ++i) {
            const std::int64_t idx = expect_int_any(c, path, "a face", true);
            if (idx < 0 || idx >= nv)
                fail(path, c.where() + "face " + std::to_string(f) + ": vertex index " +
                               std::to_string(idx) + " out of range (" + std::to_string(nv) +
                               " vertices)");
            m.v.push_back(idx);
        }
        m.sizes.push_back(static_cast<std::uint32_t>(k));
        c.skip_line();  // colours
    }
    if (has_normal) m.vn = m.v;
    if (has_uv) m.vt = m.v;
    return m;
}

}  // namespace subdivtrace::io
