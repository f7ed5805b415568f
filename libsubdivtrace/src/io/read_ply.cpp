// PLY reader (readers.h): ASCII, binary little and big endian.
#include "io/readers.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <initializer_list>

#include "io/io_util.h"
#include "io/text_cursor.h"
#include "huge_pages.h"

namespace subdivtrace::io {

namespace {

enum class PlyType { i8, u8, i16, u16, i32, u32, f32, f64 };

bool ply_type(std::string_view name, PlyType& t) {
    static const std::pair<const char*, PlyType> names[] = {
        {"char", PlyType::i8},    {"int8", PlyType::i8},     {"uchar", PlyType::u8},
        {"uint8", PlyType::u8},   {"short", PlyType::i16},   {"int16", PlyType::i16},
        {"ushort", PlyType::u16}, {"uint16", PlyType::u16},  {"int", PlyType::i32},
        {"int32", PlyType::i32},  {"uint", PlyType::u32},    {"uint32", PlyType::u32},
        {"float", PlyType::f32},  {"float32", PlyType::f32}, {"double", PlyType::f64},
        {"float64", PlyType::f64}};
    for (const auto& n : names)
        if (name == n.first) {
            t = n.second;
            return true;
        }
    return false;
}

std::int64_t ply_size(PlyType t) {
    switch (t) {
        case PlyType::i8:
        case PlyType::u8: return 1;
        case PlyType::i16:
        case PlyType::u16: return 2;
        case PlyType::i32:
        case PlyType::u32:
        case PlyType::f32: return 4;
        case PlyType::f64: return 8;
    }
    return 1;
}

struct PlyProperty {
    std::string name;
    PlyType type = PlyType::f32;
    bool is_list = false;
    PlyType count_type = PlyType::u8;
};

struct PlyElement {
    std::string name;
    std::int64_t count = 0;
    std::vector<PlyProperty> props;
};

/// Reads PLY values, ASCII or binary, bounds-checked.
class PlyValues {
public:
    PlyValues(const std::string& path, const char* p, const char* end, int format)
        : path_(path), cur_{p, end}, format_(format) {}

    void set_context(const std::string& element, std::int64_t index) {
        element_ = &element;
        index_ = index;
    }

    double read(PlyType t) {
        if (format_ == 0) return read_ascii();
        const std::int64_t n = ply_size(t);
        if (cur_.end - cur_.p < n) truncated();
        unsigned char b[8];
        std::memcpy(b, cur_.p, static_cast<std::size_t>(n));
        cur_.p += n;
        const bool little = format_ == 1;
        std::uint64_t u = 0;
        for (std::int64_t i = 0; i < n; ++i)
            u |= std::uint64_t(b[little ? i : n - 1 - i]) << (8 * i);
        switch (t) {
            case PlyType::i8: return static_cast<std::int8_t>(u);
            case PlyType::u8: return static_cast<std::uint8_t>(u);
            case PlyType::i16: return static_cast<std::int16_t>(u);
            case PlyType::u16: return static_cast<std::uint16_t>(u);
            case PlyType::i32: return static_cast<std::int32_t>(u);
            case PlyType::u32: return static_cast<std::uint32_t>(u);
            case PlyType::f32: {
                const std::uint32_t u32 = static_cast<std::uint32_t>(u);
                float f;
                std::memcpy(&f, &u32, 4);
                return f;
            }
            case PlyType::f64: {
                double d;
                std::memcpy(&d, &u, 8);
                return d;
            }
        }
        return 0.0;
    }

    /// Bytes left, for checks of claimed list lengths.
    std::int64_t remaining() const { return cur_.end - cur_.p; }
    std::string where() const {
        return "element '" + (element_ ? *element_ : std::string("?")) + "' " +
               std::to_string(index_) + ": ";
    }

private:
    [[noreturn]] void truncated() const {
        fail(path_, "unexpected end of file in " + where() + "(truncated?)");
    }
    double read_ascii() {
        cur_.skip_all(false);
        if (cur_.eof()) truncated();
        double v = 0.0;
        if (!read_double(cur_, v)) {
            Cursor probe = cur_;
            fail(path_, "line " + std::to_string(cur_.line) + ": expected a number in " + where() +
                            "got " + quoted(probe.word()));
        }
        return v;
    }

    const std::string& path_;
    Cursor cur_;
    int format_;  // 0 ascii, 1 little endian, 2 big endian
    const std::string* element_ = nullptr;
    std::int64_t index_ = 0;
};


}  // namespace

Polygons read_ply(const std::string& path, const std::string& data,
              std::vector<std::string>* warnings) {
    // Parse the header line by line.
    Cursor c{data.data(), data.data() + data.size()};
    if (lower(std::string(c.word())) != "ply" || !c.at_line_end(false))
        fail(path, "not a PLY file (missing 'ply' on the first line)");
    c.skip_line();
    if (data.find("end_header") == std::string::npos)
        fail(path, "missing 'end_header' (truncated header?)");
    int format = -1;
    std::vector<PlyElement> elements;
    std::size_t skipped_lines = 0;
    std::string first_skipped;
    bool header_done = false;
    while (!c.eof()) {
        const std::string_view kw = c.word();
        if (kw == "format") {
            const std::string_view f = c.word();
            if (f == "ascii")
                format = 0;
            else if (f == "binary_little_endian")
                format = 1;
            else if (f == "binary_big_endian")
                format = 2;
            else
                fail(path, c.where() + "unknown PLY format " + quoted(f));
        } else if (kw == "element") {
            PlyElement e;
            e.name = std::string(c.word());
            const std::string_view n = c.word();
            char* endp = nullptr;
            const std::string ns(n);
            errno = 0;
            e.count = std::strtoll(ns.c_str(), &endp, 10);
            if (ns.empty() || *endp != '\0' || errno == ERANGE || e.count < 0)
                fail(path, c.where() + "bad element count " + quoted(n));
            if (e.count > k_max_count)
                fail(path, c.where() + "header claims " + ns + " " + e.name +
                               " elements (more than 2^32 - 1)");
            elements.push_back(e);
        } else if (kw == "property") {
            if (elements.empty()) fail(path, c.where() + "property before any element");
            PlyProperty p;
            std::string_view t = c.word();
            if (t == "list") {
                p.is_list = true;
                if (!ply_type(c.word(), p.count_type))
                    fail(path, c.where() + "unknown list count type");
                t = c.word();
            }
            if (!ply_type(t, p.type)) fail(path, c.where() + "unknown property type " + quoted(t));
            p.name = std::string(c.word());
            elements.back().props.push_back(p);
        } else if (kw == "end_header") {
            c.skip_line();
            header_done = true;
            break;
        } else if (!(kw == "comment" || kw == "obj_info" || kw.empty())) {
            // Exporters write other lines (assimp once wrote its banner without
            // "comment"). Only element/property/format lines shape the data, so
            // any other line is skipped; one that looks like a misspelt layout
            // line would leave the data ambiguous.
            const std::string k = lower(std::string(kw));
            for (const char* layout : {"elem", "prop", "format", "end_header", "list"})
                if (k.compare(0, std::strlen(layout), layout) == 0)
                    fail(path, c.where() + "unknown header line starting with " + quoted(kw) +
                                   " (a misspelt element, property or format line?)");
            if (skipped_lines++ == 0) first_skipped = c.where() + quoted(kw);
        }
        c.skip_line();
    }
    if (!header_done) fail(path, "missing 'end_header' (truncated header?)");
    if (format < 0) fail(path, "missing 'format' line in header");
    if (skipped_lines > 0 && warnings)
        warnings->push_back(path + ": skipped " + std::to_string(skipped_lines) +
                            " non-standard PLY header line(s) (first: " + first_skipped + ")");

    // Locate the properties we use.
    const PlyElement* vertex = nullptr;
    const PlyElement* face = nullptr;
    for (const PlyElement& e : elements) {
        if (e.name == "vertex") vertex = &e;
        if (e.name == "face") face = &e;
    }
    if (!vertex) fail(path, "no 'vertex' element in header");
    if (!face || face->count == 0) fail(path, "no faces (no 'face' element or count 0)");
    auto find = [](const PlyElement& e, std::initializer_list<const char*> names) -> int {
        for (const char* n : names)
            for (std::size_t i = 0; i < e.props.size(); ++i)
                if (e.props[i].name == n) return static_cast<int>(i);
        return -1;
    };
    const int px = find(*vertex, {"x"}), py = find(*vertex, {"y"}), pz = find(*vertex, {"z"});
    if (px < 0 || py < 0 || pz < 0) fail(path, "vertex element lacks x, y or z");
    const int pnx = find(*vertex, {"nx"}), pny = find(*vertex, {"ny"}), pnz = find(*vertex, {"nz"});
    const int pu = find(*vertex, {"u", "s", "texture_u", "texture_s"});
    const int pv = find(*vertex, {"v", "t", "texture_v", "texture_t"});
    const int pfi = find(*face, {"vertex_indices", "vertex_index"});
    if (pfi < 0 || !face->props[static_cast<std::size_t>(pfi)].is_list)
        fail(path, "face element has no 'vertex_indices' list");
    const int pft = find(*face, {"texcoord"});
    for (int i : {px, py, pz, pnx, pny, pnz, pu, pv})
        if (i >= 0 && vertex->props[static_cast<std::size_t>(i)].is_list)
            fail(path, "vertex property " + vertex->props[static_cast<std::size_t>(i)].name +
                           " is a list");
    const bool has_normals = pnx >= 0 && pny >= 0 && pnz >= 0;
    const bool has_vertex_uv = pu >= 0 && pv >= 0;
    const bool has_face_uv = pft >= 0 && face->props[static_cast<std::size_t>(pft)].is_list;

    // Before reading: can the bytes after the header hold what it claims?
    const std::int64_t available = c.end - c.p;
    std::int64_t needed = 0;
    for (const PlyElement& e : elements) {
        std::int64_t each = 0;
        for (std::size_t i = 0; i < e.props.size(); ++i) {
            const PlyProperty& p = e.props[i];
            const bool face_list = &e == face && static_cast<int>(i) == pfi;
            if (format == 0)
                each += 2 + (face_list ? 6 : 0);
            else if (p.is_list)
                each += ply_size(p.count_type) + (face_list ? 3 * ply_size(p.type) : 0);
            else
                each += ply_size(p.type);
        }
        if (exceeds(e.count, each, available + 1) || needed + e.count * each > available + 1)
            fail(path, "header claims " + std::to_string(e.count) + " '" + e.name +
                           "' elements, but only " + std::to_string(available) +
                           " bytes follow the header (truncated file or bad header)");
        needed += e.count * each;
    }

    // Read the elements in order.
    PlyValues in(path, c.p, c.end, format);
    Polygons m;
    std::vector<double> row;
    std::vector<double> list_uv;
    for (const PlyElement& e : elements) {
        const bool is_vertex = &e == vertex, is_face = &e == face;
        // Room for what the header announces (checked against the file's
        // size above), allocated once on huge pages (huge_pages.h); a face
        // list is reserved for triangles.
        const auto count = static_cast<std::size_t>(e.count);
        if (is_vertex) {
            detail::reserve_huge(m.positions, count);
            if (has_normals) detail::reserve_huge(m.normals, count);
            if (has_vertex_uv) detail::reserve_huge(m.uvs, count);
        }
        if (is_face) {
            detail::reserve_huge(m.sizes, count);
            // Each corner takes a byte of the file at least.
            detail::reserve_huge(m.v, std::min(3 * count, static_cast<std::size_t>(in.remaining() + 1)));
        }
        // An element without properties holds no bytes, whatever its count:
        // nothing to read, and counting to 4e8 would hang (found by fuzzing).
        if (e.props.empty()) continue;
        for (std::int64_t n = 0; n < e.count; ++n) {
            in.set_context(e.name, n);
            row.assign(e.props.size(), 0.0);
            for (std::size_t i = 0; i < e.props.size(); ++i) {
                const PlyProperty& p = e.props[i];
                if (!p.is_list) {
                    row[i] = in.read(p.type);
                    continue;
                }
                const double count = in.read(p.count_type);
                const std::int64_t item = format == 0 ? 2 : ply_size(p.type);
                // Compared as a double first: a float count type can hold 1e30,
                // which no integer conversion survives (found by fuzzing).
                if (!(count >= 0) || count != std::floor(count) ||
                    count > static_cast<double>(in.remaining() + 1) ||
                    exceeds(static_cast<std::int64_t>(count), item, in.remaining() + 1))
                    fail(path, in.where() + "list '" + p.name + "' claims " + format_number(count) +
                                   " items, more than the file holds (truncated?)");
                const auto k = static_cast<std::int64_t>(count);
                const bool corners = is_face && static_cast<int>(i) == pfi;
                const bool uvs = is_face && static_cast<int>(i) == pft && has_face_uv;
                if (corners && k < 3)
                    fail(path, in.where() + "face with " + std::to_string(k) +
                                   " corners (at least 3 needed)");
                if (uvs) list_uv.clear();
                for (std::int64_t j = 0; j < k; ++j) {
                    const double v = in.read(p.type);
                    if (corners) {
                        if (!(v >= 0 && v < double(vertex->count)) || v != std::floor(v))
                            fail(path, in.where() + "vertex index " + format_number(v) +
                                           " out of range (" + std::to_string(vertex->count) +
                                           " vertices)");
                        m.v.push_back(static_cast<std::int64_t>(v));
                    } else if (uvs) {
                        list_uv.push_back(v);
                    }
                }
                if (corners) m.sizes.push_back(static_cast<std::uint32_t>(k));
            }
            if (is_vertex) {
                const Vec3 p(row[static_cast<std::size_t>(px)], row[static_cast<std::size_t>(py)],
                             row[static_cast<std::size_t>(pz)]);
                if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
                    fail(path, in.where() + "coordinate is not finite");
                m.positions.push_back(p);
                if (has_normals)
                    m.normals.emplace_back(row[static_cast<std::size_t>(pnx)],
                                           row[static_cast<std::size_t>(pny)],
                                           row[static_cast<std::size_t>(pnz)]);
                if (has_vertex_uv)
                    m.uvs.emplace_back(row[static_cast<std::size_t>(pu)],
                                       row[static_cast<std::size_t>(pv)]);
            }
            if (is_face && has_face_uv) {
                const std::size_t k = m.sizes.back();
                if (list_uv.size() == 2 * k) {
                    for (std::size_t j = 0; j < k; ++j) {
                        m.vt.push_back(static_cast<std::int64_t>(m.uvs.size()));
                        m.uvs.emplace_back(list_uv[2 * j], list_uv[2 * j + 1]);
                    }
                } else {
                    fail(path, in.where() + "texcoord list has " + std::to_string(list_uv.size()) +
                                   " values, expected " + std::to_string(2 * k));
                }
            }
        }
    }
    if (has_normals) m.vn = m.v;
    if (has_vertex_uv && !has_face_uv) m.vt = m.v;
    if (has_vertex_uv && has_face_uv && warnings)
        warnings->push_back(path + ": both vertex and face texture coordinates; using the face's");
    return m;
}

}  // namespace subdivtrace::io
