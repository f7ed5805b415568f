// OBJ reader (readers.h): v, vt, vn, f/fo with v, v/vt, v//vn, v/vt/vn corners.
#include "io/readers.h"

#include <cctype>
#include <cstdint>
#include <cstring>
#include <string_view>

#include "io/io_util.h"
#include "io/text_cursor.h"
#include "huge_pages.h"

namespace subdivtrace::io {

namespace {

/// One `f` corner: v, v/vt, v//vn or v/vt/vn. Returns false on a malformed ref.
bool parse_obj_ref(std::string_view w, std::int64_t out[3]) {
    out[0] = out[1] = out[2] = 0;
    std::size_t i = 0;
    for (int part = 0; part < 3; ++part) {
        if (i >= w.size()) return part > 0;
        if (part > 0) {
            if (w[i] != '/') return false;
            ++i;
            if (i < w.size() && w[i] == '/') continue;  // v//vn: empty vt
            if (i >= w.size()) return false;
        }
        const std::size_t start = i;
        if (i < w.size() && (w[i] == '-' || w[i] == '+')) ++i;
        std::int64_t value = 0;
        bool digits = false;
        while (i < w.size() && std::isdigit(static_cast<unsigned char>(w[i]))) {
            if (value > (INT64_MAX - 9) / 10) return false;
            value = value * 10 + (w[i] - '0');
            ++i;
            digits = true;
        }
        if (!digits) return false;
        out[part] = w[start] == '-' ? -value : value;
    }
    return i == w.size();
}


/// How many of each element an OBJ text holds, counted by the first word
/// of each line (a face's corners by the words after `f`), so the reader's
/// arrays are allocated once: grown by doubling, a 100 MB export copied
/// each of them about twice and faulted every fresh page (huge_pages.h).
struct ObjCounts {
    std::size_t positions = 0, normals = 0, uvs = 0, faces = 0, corners = 0;
};

ObjCounts count_obj(std::string_view data) {
    ObjCounts n;
    const char* p = data.data();
    const char* const end = p + data.size();
    while (p < end) {
        while (p < end && (*p == ' ' || *p == '\t')) ++p;
        const char* line_end = static_cast<const char*>(std::memchr(p, '\n', static_cast<std::size_t>(end - p)));
        if (line_end == nullptr) line_end = end;
        const std::size_t length = static_cast<std::size_t>(line_end - p);
        const auto starts = [&](const char* word, std::size_t size) {
            return length > size && std::memcmp(p, word, size) == 0 && (p[size] == ' ' || p[size] == '\t');
        };
        if (starts("v", 1)) ++n.positions;
        else if (starts("vn", 2)) ++n.normals;
        else if (starts("vt", 2)) ++n.uvs;
        else if (starts("f", 1)) {
            ++n.faces;
            // Corners: words after the keyword.
            bool in_word = false;
            for (const char* q = p + 1; q < line_end; ++q) {
                const bool space = *q == ' ' || *q == '\t' || *q == '\r';
                if (!space && !in_word) ++n.corners;
                in_word = !space;
            }
        }
        p = line_end + 1;
    }
    return n;
}

}  // namespace

Polygons read_obj(const std::string& path, const std::string& data,
              std::vector<std::string>* warnings) {
    Cursor c{data.data(), data.data() + data.size()};
    Polygons m;
    std::vector<std::size_t> poly_line;  // for messages about indices
    std::size_t corners_without_vt = 0, corners_without_vn = 0, ignored_elements = 0;
    // Texture and normal references only once a corner has one (most
    // exports have both or neither): -1 for the corners before it.
    std::vector<std::int64_t> vt, vn;
    bool any_vt = false, any_vn = false;
    {
        const ObjCounts n = count_obj(data);
        detail::reserve_huge(m.positions, n.positions);
        detail::reserve_huge(m.normals, n.normals);
        detail::reserve_huge(m.uvs, n.uvs);
        detail::reserve_huge(m.sizes, n.faces);
        detail::reserve_huge(poly_line, n.faces);
        detail::reserve_huge(m.v, n.corners);
        if (n.uvs > 0) detail::reserve_huge(vt, n.corners);
        if (n.normals > 0) detail::reserve_huge(vn, n.corners);
    }

    // Resolve an OBJ index (1-based, or negative = relative to the count so far).
    auto resolve = [&](std::int64_t idx, std::size_t count, const char* what) -> std::int64_t {
        if (idx == 0) fail(path, c.where() + what + " index 0 is invalid (OBJ indices start at 1)");
        if (idx < 0) {
            const std::int64_t r = static_cast<std::int64_t>(count) + idx;
            if (r < 0)
                fail(path, c.where() + "relative " + what + " index " + std::to_string(idx) +
                               " out of range (" + std::to_string(count) + " defined so far)");
            return r;
        }
        return idx - 1;
    };

    while (!c.eof()) {
        if (c.at_line_end(true)) {
            c.skip_line();
            continue;
        }
        const std::string_view kw = c.word();
        if (kw == "v") {
            m.positions.push_back(expect_vec3(c, path, "vertex"));
        } else if (kw == "vn") {
            m.normals.push_back(expect_vec3(c, path, "normal"));
        } else if (kw == "vt") {
            Vec2 t{0.0};
            t.x = expect_double(c, path, "texture coordinate");
            if (!c.at_line_end(true)) t.y = expect_double(c, path, "texture coordinate");
            m.uvs.push_back(t);
        } else if (kw == "f" || kw == "fo") {
            std::uint32_t k = 0;
            std::size_t with_vt = 0, with_vn = 0;
            while (!c.at_line_end(true)) {
                const std::string_view w = c.word();
                std::int64_t ref[3];
                if (!parse_obj_ref(w, ref))
                    fail(path, c.where() + "bad face corner " + quoted(w) +
                                   " (expected v, v/vt, v//vn or v/vt/vn)");
                m.v.push_back(resolve(ref[0], m.positions.size(), "vertex"));
                if (ref[1] && !any_vt) {
                    any_vt = true;
                    vt.assign(m.v.size() - 1, -1);
                }
                if (ref[2] && !any_vn) {
                    any_vn = true;
                    vn.assign(m.v.size() - 1, -1);
                }
                if (any_vt) vt.push_back(ref[1] ? resolve(ref[1], m.uvs.size(), "texture") : -1);
                if (any_vn) vn.push_back(ref[2] ? resolve(ref[2], m.normals.size(), "normal") : -1);
                with_vt += ref[1] != 0;
                with_vn += ref[2] != 0;
                ++k;
            }
            if (k < 3)
                fail(path, c.where() + "face with " + std::to_string(k) +
                               " corner(s) (at least 3 needed)");
            corners_without_vt += k - with_vt;
            corners_without_vn += k - with_vn;
            m.sizes.push_back(k);
            poly_line.push_back(c.line);
        } else if (kw == "l" || kw == "p") {
            ++ignored_elements;
        }
        // Everything else (o, g, s, usemtl, mtllib, vp, ...) has no geometry for us.
        c.skip_line();
    }

    // Positive indices may only be checked once every vertex is known.
    std::size_t corner = 0;
    for (std::size_t f = 0; f < m.sizes.size(); ++f) {
        for (std::uint32_t i = 0; i < m.sizes[f]; ++i, ++corner) {
            auto check = [&](std::int64_t idx, std::size_t count, const char* what) {
                if (idx >= static_cast<std::int64_t>(count))
                    fail(path, "line " + std::to_string(poly_line[f]) + ": " + what + " index " +
                                   std::to_string(idx + 1) + " out of range (" +
                                   std::to_string(count) + " defined)");
            };
            check(m.v[corner], m.positions.size(), "vertex");
            if (any_vt && vt[corner] >= 0) check(vt[corner], m.uvs.size(), "texture");
            if (any_vn && vn[corner] >= 0) check(vn[corner], m.normals.size(), "normal");
        }
    }
    if (m.sizes.empty())
        fail(path,
             "no faces (" + std::to_string(m.positions.size()) + " vertices, but no 'f' lines)");

    // Corner attributes only if every corner has them.
    if (corners_without_vt == 0 && !m.uvs.empty())
        m.vt = std::move(vt);
    else if (corners_without_vt < m.v.size() && warnings)
        warnings->push_back(path + ": " + std::to_string(corners_without_vt) +
                            " face corner(s) have no texture coordinate: UVs ignored");
    if (corners_without_vn == 0 && !m.normals.empty())
        m.vn = std::move(vn);
    else if (corners_without_vn < m.v.size() && warnings)
        warnings->push_back(path + ": " + std::to_string(corners_without_vn) +
                            " face corner(s) have no normal: normals ignored");
    if (ignored_elements > 0 && warnings)
        warnings->push_back(path + ": ignored " + std::to_string(ignored_elements) +
                            " line/point element(s)");
    return m;
}

}  // namespace subdivtrace::io
