// Mesh files in and out (mesh_io.h).
//
// The readers are our own, small and strict, rather than OpenMesh's: OpenMesh 9
// reserves memory from header counts before reading (an OFF or PLY header that
// claims 4e9 vertices ends in std::bad_alloc), drops faces it cannot add to its
// half-edge structure (non-manifold edges, bad indices, vertices that failed to
// parse) with only a line on std::cerr and still reports success, and accepts
// empty or truncated STL files as meshes without faces. Here every claimed count
// is checked against the bytes that follow before anything is reserved, every
// read is bounds-checked, and every problem becomes a MeshError naming the file.
#include "subdivtrace/mesh_io.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string_view>

#include <unistd.h>

#include <glm/geometric.hpp>

namespace subdivtrace {

namespace {

constexpr std::int64_t k_max_count = 0xFFFFFFFFll;  // indices are 32-bit

[[noreturn]] void fail(const std::string& path, const std::string& reason) {
    throw MeshError(path + ": " + reason);
}

std::string lower(std::string s) {
    for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

std::string extension_of(const std::string& path) {
    const std::size_t slash = path.find_last_of("/\\");
    const std::size_t dot = path.find_last_of('.');
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
    return lower(path.substr(dot + 1));
}

bool equals_nocase(std::string_view a, std::string_view b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i)
        if (std::tolower(static_cast<unsigned char>(a[i])) !=
            std::tolower(static_cast<unsigned char>(b[i])))
            return false;
    return true;
}

std::string quoted(std::string_view word) {
    std::string s(word.substr(0, 40));
    for (char& c : s)
        if (!std::isprint(static_cast<unsigned char>(c))) c = '?';
    return "'" + s + (word.size() > 40 ? "...'" : "'");
}

std::string format_number(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    return buf;
}

// ---------------------------------------------------------------------------
// Polygons as parsed, before triangulation.

struct Polygons {
    std::vector<Vec3> positions;
    std::vector<Vec3> normals;
    std::vector<Vec2> uvs;
    std::vector<std::uint32_t> sizes;  // corners per polygon
    std::vector<std::int64_t> v;       // corner vertex indices (0-based)
    std::vector<std::int64_t> vn;      // empty or one per corner
    std::vector<std::int64_t> vt;      // empty or one per corner
};

/// Fan-triangulates and hands over to mesh_from_arrays, which checks ranges and
/// values, welds coincident vertices and drops triangles that repeat a vertex.
Mesh finish(Polygons& in, const std::string& path, std::vector<std::string>* warnings,
            const WeldOptions& weld, WeldReport* report) {
    MeshArrays a;
    a.positions = std::move(in.positions);
    a.normals = std::move(in.normals);
    a.uvs = std::move(in.uvs);
    const bool has_n = !a.normals.empty() && in.vn.size() == in.v.size();
    const bool has_t = !a.uvs.empty() && in.vt.size() == in.v.size();
    if (!has_n) a.normals.clear();
    if (!has_t) a.uvs.clear();
    std::size_t polygons = 0, largest = 0, corner = 0;
    for (std::uint32_t k : in.sizes) {
        if (k > 3) {
            ++polygons;
            largest = std::max<std::size_t>(largest, k);
        }
        for (std::uint32_t i = 1; i + 1 < k; ++i) {
            const std::size_t c0 = corner, c1 = corner + i, c2 = corner + i + 1;
            a.face_indices.push_back({in.v[c0], in.v[c1], in.v[c2]});
            if (has_n) a.normal_indices.push_back({in.vn[c0], in.vn[c1], in.vn[c2]});
            if (has_t) a.uv_indices.push_back({in.vt[c0], in.vt[c1], in.vt[c2]});
        }
        corner += k;
    }
    if (polygons > 0 && warnings)
        warnings->push_back(path + ": fan-triangulated " + std::to_string(polygons) +
                            " polygon(s) with up to " + std::to_string(largest) + " corners into " +
                            std::to_string(a.face_indices.size()) + " triangles in all");
    return mesh_from_arrays(a, path, warnings, weld, report);
}

// ---------------------------------------------------------------------------
// A cursor over text. The file buffer is a std::string, so it is
// NUL-terminated and strtod/strtoll never read past it.

struct Cursor {
    const char* p;
    const char* end;
    std::size_t line = 1;

    bool eof() const { return p >= end; }
    static bool inline_space(char c) {
        return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v';
    }
    static bool space(char c) { return inline_space(c) || c == '\n' || c == '\0'; }
    void skip_inline() {
        while (p < end && inline_space(*p)) ++p;
    }
    /// Skips white space, newlines and (if `hash`) '#' comments.
    void skip_all(bool hash) {
        for (;;) {
            skip_inline();
            if (p < end && *p == '\n') {
                ++p;
                ++line;
            } else if (hash && p < end && *p == '#') {
                while (p < end && *p != '\n') ++p;
            } else {
                return;
            }
        }
    }
    bool at_line_end(bool hash) {
        skip_inline();
        return p >= end || *p == '\n' || (hash && *p == '#');
    }
    void skip_line() {
        while (p < end && *p != '\n') ++p;
        if (p < end) {
            ++p;
            ++line;
        }
    }
    /// The next word on this line (empty at the line's end).
    std::string_view word() {
        skip_inline();
        const char* s = p;
        while (p < end && !space(*p)) ++p;
        return {s, static_cast<std::size_t>(p - s)};
    }
    std::string where() const { return "line " + std::to_string(line) + ": "; }
};

/// Parses a decimal number (also "nan", "inf") independently of the C locale,
/// unlike strtod. Literals beyond the double range give +-inf (and are then
/// rejected as non-finite) or 0 (underflow). Returns the end, or nullptr.
const char* parse_double(const char* p, const char* end, double& value) {
    const char* s = p;
    if (s < end && *s == '+') {
        ++s;
        if (s < end && *s == '-') return nullptr;
    }
    const std::from_chars_result r = std::from_chars(s, end, value, std::chars_format::general);
    if (r.ec == std::errc::invalid_argument) return nullptr;
    if (r.ec == std::errc::result_out_of_range) {
        const std::string_view text(s, static_cast<std::size_t>(r.ptr - s));
        const std::size_t e = text.find_first_of("eE");
        const bool underflow =
            e != std::string_view::npos && e + 1 < text.size() && text[e + 1] == '-';
        const double sign = text[0] == '-' ? -1.0 : 1.0;
        value = underflow ? sign * 0.0 : sign * std::numeric_limits<double>::infinity();
    }
    return r.ptr;
}

/// Reads a number at the cursor (same line). False if there is none.
bool read_double(Cursor& c, double& value) {
    c.skip_inline();
    if (c.eof() || *c.p == '\n') return false;
    const char* e = parse_double(c.p, c.end, value);
    if (!e || e == c.p || (e < c.end && !Cursor::space(*e))) return false;
    c.p = e;
    return true;
}

/// A coordinate-like value that must be finite; fails with the line number.
double expect_double(Cursor& c, const std::string& path, const char* what) {
    double v = 0.0;
    c.skip_inline();
    if (c.eof()) fail(path, c.where() + "unexpected end of file in " + what + " (truncated?)");
    const char* start = c.p;
    if (!read_double(c, v)) {
        if (*c.p == '\n') fail(path, c.where() + "too few values in " + what);
        Cursor probe = c;
        probe.p = start;
        fail(path, c.where() + "expected a number in " + what + ", got " + quoted(probe.word()));
    }
    if (!std::isfinite(v))
        fail(path,
             c.where() + "non-finite value in " + what + " (" + std::string(start, c.p) + ")");
    return v;
}

/// Like expect_double but first skips newlines and comments (free-form formats).
double expect_double_any(Cursor& c, const std::string& path, const char* what, bool hash) {
    c.skip_all(hash);
    return expect_double(c, path, what);
}

/// An integer at the cursor, anywhere after blank lines/comments.
std::int64_t expect_int_any(Cursor& c, const std::string& path, const char* what, bool hash) {
    c.skip_all(hash);
    if (c.eof()) fail(path, c.where() + "unexpected end of file in " + what + " (truncated?)");
    char* e = nullptr;
    errno = 0;
    const long long v = std::strtoll(c.p, &e, 10);
    if (e == c.p || (e < c.end && !Cursor::space(*e))) {
        Cursor probe = c;
        fail(path, c.where() + "expected an integer in " + what + ", got " + quoted(probe.word()));
    }
    if (errno == ERANGE) fail(path, c.where() + "integer out of range in " + what);
    c.p = e;
    return v;
}

std::string read_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) fail(path, std::string("cannot open file (") + std::strerror(errno) + ")");
    in.seekg(0, std::ios::end);
    const std::streamoff size = in.tellg();
    if (size < 0) fail(path, "cannot read file (not a regular file?)");
    in.seekg(0, std::ios::beg);
    std::string data(static_cast<std::size_t>(size), '\0');
    if (size > 0 && !in.read(&data[0], size)) fail(path, "cannot read file (I/O error)");
    if (data.empty()) fail(path, "empty file");
    return data;
}

/// True if `needed` (a count times a minimum size per element) cannot fit in
/// `available` bytes, computed without overflow.
bool exceeds(std::int64_t count, std::int64_t bytes_each, std::int64_t available) {
    return count > 0 && bytes_each > 0 && count > available / bytes_each;
}

// ---------------------------------------------------------------------------
// OBJ

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

Polygons read_obj(const std::string& path, const std::string& data,
              std::vector<std::string>* warnings) {
    Cursor c{data.data(), data.data() + data.size()};
    Polygons m;
    std::vector<std::size_t> poly_line;  // for messages about indices
    std::size_t corners_without_vt = 0, corners_without_vn = 0, ignored_elements = 0;
    std::vector<std::int64_t> vt, vn;

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
            Vec3 p;
            p.x = expect_double(c, path, "vertex");
            p.y = expect_double(c, path, "vertex");
            p.z = expect_double(c, path, "vertex");
            m.positions.push_back(p);
        } else if (kw == "vn") {
            Vec3 n;
            n.x = expect_double(c, path, "normal");
            n.y = expect_double(c, path, "normal");
            n.z = expect_double(c, path, "normal");
            m.normals.push_back(n);
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
                vt.push_back(ref[1] ? resolve(ref[1], m.uvs.size(), "texture") : -1);
                vn.push_back(ref[2] ? resolve(ref[2], m.normals.size(), "normal") : -1);
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
            if (vt[corner] >= 0) check(vt[corner], m.uvs.size(), "texture");
            if (vn[corner] >= 0) check(vn[corner], m.normals.size(), "normal");
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

// ---------------------------------------------------------------------------
// OFF (Princeton/Geomview): [ST][C][N]OFF, counts, vertices, faces.

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
    m.positions.reserve(static_cast<std::size_t>(nv));
    for (std::int64_t i = 0; i < nv; ++i) {
        c.skip_all(true);
        Vec3 p;
        p.x = expect_double_any(c, path, "vertex", true);
        p.y = expect_double_any(c, path, "vertex", true);
        p.z = expect_double_any(c, path, "vertex", true);
        m.positions.push_back(p);
        if (has_normal) {
            Vec3 n;
            n.x = expect_double_any(c, path, "normal", true);
            n.y = expect_double_any(c, path, "normal", true);
            n.z = expect_double_any(c, path, "normal", true);
            m.normals.push_back(n);
        }
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

// ---------------------------------------------------------------------------
// PLY

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
            fail(path, c.where() + "unknown header line starting with " + quoted(kw));
        }
        c.skip_line();
    }
    if (!header_done) fail(path, "missing 'end_header' (truncated header?)");
    if (format < 0) fail(path, "missing 'format' line in header");

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
        if (is_vertex) {
            m.positions.reserve(static_cast<std::size_t>(e.count));
        }
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
                if (!(count >= 0) || count != std::floor(count) ||
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

// ---------------------------------------------------------------------------
// STL: a triangle soup, three vertices per facet (mesh_from_arrays welds them).

Polygons read_stl_binary(const std::string& path, const std::string& data, std::uint32_t n) {
    Polygons m;
    const auto* b = reinterpret_cast<const unsigned char*>(data.data()) + 84;
    auto f32 = [&](std::size_t offset) {
        const std::uint32_t u = std::uint32_t(b[offset]) | std::uint32_t(b[offset + 1]) << 8 |
                                std::uint32_t(b[offset + 2]) << 16 |
                                std::uint32_t(b[offset + 3]) << 24;
        float f;
        std::memcpy(&f, &u, 4);
        return static_cast<double>(f);
    };
    for (std::uint32_t t = 0; t < n; ++t, b += 50) {
        for (int k = 0; k < 3; ++k) {
            const Vec3 p(f32(12 + 12 * k), f32(16 + 12 * k), f32(20 + 12 * k));
            if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
                fail(path, "triangle " + std::to_string(t) + ": coordinate is not finite");
            m.v.push_back(static_cast<std::int64_t>(m.positions.size()));
            m.positions.push_back(p);
        }
        m.sizes.push_back(3);
    }
    if (n == 0) fail(path, "no faces (binary STL with 0 triangles)");
    return m;
}

Polygons read_stl_ascii(const std::string& path, const std::string& data) {
    Cursor c{data.data(), data.data() + data.size()};
    Polygons m;
    auto expect = [&](const char* word) {
        c.skip_all(false);
        if (c.eof())
            fail(path, c.where() + "unexpected end of file, expected '" + word + "' (truncated?)");
        const std::string_view w = c.word();
        if (!equals_nocase(w, word)) {
            if (c.eof())
                fail(path,
                     c.where() + "unexpected end of file, expected '" + word + "' (truncated?)");
            fail(path, c.where() + "expected '" + word + "', got " + quoted(w));
        }
    };
    expect("solid");
    c.skip_line();  // the solid's name
    for (;;) {
        c.skip_all(false);
        if (c.eof())
            fail(path, c.where() + "unexpected end of file, missing 'endsolid' (truncated?)");
        const std::string_view w = c.word();
        if (equals_nocase(w, "endsolid")) {
            c.skip_line();
            c.skip_all(false);
            if (c.eof()) break;
            expect("solid");  // several solids in one file
            c.skip_line();
            continue;
        }
        if (!equals_nocase(w, "facet")) {
            if (c.eof())
                fail(path, c.where() +
                               "unexpected end of file, expected 'facet' or "
                               "'endsolid' (truncated?)");
            fail(path, c.where() + "expected 'facet' or 'endsolid', got " + quoted(w));
        }
        expect("normal");
        for (int i = 0; i < 3; ++i) {  // facet normals are not used (geometry decides)
            double ignored;
            c.skip_all(false);
            if (!read_double(c, ignored)) fail(path, c.where() + "bad facet normal");
        }
        expect("outer");
        expect("loop");
        std::uint32_t k = 0;
        for (;;) {
            c.skip_all(false);
            const char* save = c.p;
            const std::string_view vw = c.word();
            if (!equals_nocase(vw, "vertex")) {
                if (c.eof())
                    fail(path, c.where() + "unexpected end of file inside a facet (truncated?)");
                c.p = save;
                break;
            }
            Vec3 p;
            p.x = expect_double_any(c, path, "vertex", false);
            p.y = expect_double_any(c, path, "vertex", false);
            p.z = expect_double_any(c, path, "vertex", false);
            m.v.push_back(static_cast<std::int64_t>(m.positions.size()));
            m.positions.push_back(p);
            ++k;
        }
        if (c.eof()) fail(path, c.where() + "unexpected end of file inside a facet (truncated?)");
        if (k < 3)
            fail(path, c.where() + "facet with " + std::to_string(k) + " vertices (3 needed)");
        m.sizes.push_back(k);
        expect("endloop");
        expect("endfacet");
    }
    if (m.sizes.empty()) fail(path, "no faces (ASCII STL without facets)");
    return m;
}

Polygons read_stl(const std::string& path, const std::string& data,
              std::vector<std::string>* warnings) {
    const std::uint64_t size = data.size();
    std::uint32_t n = 0;
    if (size >= 84) {
        const auto* b = reinterpret_cast<const unsigned char*>(data.data()) + 80;
        n = std::uint32_t(b[0]) | std::uint32_t(b[1]) << 8 | std::uint32_t(b[2]) << 16 |
            std::uint32_t(b[3]) << 24;
    }
    const std::uint64_t expected = 84 + 50ull * n;
    if (size >= 84 && size == expected) return read_stl_binary(path, data, n);
    std::size_t i = 0;
    while (i < data.size() && std::isspace(static_cast<unsigned char>(data[i]))) ++i;
    if (equals_nocase(std::string_view(data).substr(i, 5), "solid"))
        return read_stl_ascii(path, data);
    if (size < 84)
        fail(path, "not an STL file: too short for binary STL (" + std::to_string(size) +
                       " bytes, the header alone takes 84) and no ASCII 'solid'");
    if (size < expected)
        fail(path, "binary STL header claims " + std::to_string(n) + " triangles (" +
                       std::to_string(expected) + " bytes) but the file has " +
                       std::to_string(size) + " bytes (truncated file or bad header)");
    if (warnings)
        warnings->push_back(path + ": ignored " + std::to_string(size - expected) +
                            " bytes after the last binary STL triangle");
    return read_stl_binary(path, data, n);
}

// ---------------------------------------------------------------------------
// Writing

/// Writes through `body` into a temporary file beside `path`, then renames it.
void write_atomically(const std::string& path, const std::function<void(std::FILE*)>& body) {
    static std::atomic<int> counter{0};
    const std::string tmp =
        path + ".tmp" + std::to_string(::getpid()) + "_" + std::to_string(counter++);
    std::FILE* f = std::fopen(tmp.c_str(), "wb");
    if (!f) fail(path, std::string("cannot write file (") + std::strerror(errno) + ")");
    try {
        body(f);
    } catch (...) {
        std::fclose(f);
        std::remove(tmp.c_str());
        throw;
    }
    const bool write_error = std::ferror(f) != 0;
    const int saved = errno;
    if (std::fclose(f) != 0 || write_error) {
        const int e = write_error ? saved : errno;
        std::remove(tmp.c_str());
        fail(path, std::string("cannot write file (") + std::strerror(e ? e : EIO) + ")");
    }
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
        const int e = errno;
        std::remove(tmp.c_str());
        fail(path, std::string("cannot write file (") + std::strerror(e) + ")");
    }
}

/// Deduplicates values, giving each distinct one an index in order of appearance.
template <class V, std::size_t N>
struct Dedup {
    std::map<std::array<double, N>, std::uint32_t> index;
    std::vector<V> values;
    std::uint32_t add(const V& v) {
        std::array<double, N> key;
        for (std::size_t i = 0; i < N; ++i) key[i] = v[static_cast<int>(i)] + 0.0;
        auto [it, inserted] = index.emplace(key, static_cast<std::uint32_t>(values.size()));
        if (inserted) values.push_back(v);
        return it->second;
    }
};

void put_le(std::FILE* f, std::uint64_t bits, int bytes) {
    unsigned char b[8];
    for (int i = 0; i < bytes; ++i) b[i] = static_cast<unsigned char>(bits >> (8 * i));
    std::fwrite(b, 1, static_cast<std::size_t>(bytes), f);
}
void put_f64(std::FILE* f, double d) {
    std::uint64_t u;
    std::memcpy(&u, &d, 8);
    put_le(f, u, 8);
}
void put_f32(std::FILE* f, double d) {
    const float x = static_cast<float>(d);
    std::uint32_t u;
    std::memcpy(&u, &x, 4);
    put_le(f, u, 4);
}

void write_obj(std::FILE* f, const Mesh& mesh) {
    std::fprintf(f, "# subdivtrace: %zu vertices, %zu triangles\n", mesh.positions.size(),
                 mesh.triangles.size());
    for (const Vec3& p : mesh.positions) std::fprintf(f, "v %.17g %.17g %.17g\n", p.x, p.y, p.z);
    Dedup<Vec2, 2> uvs;
    Dedup<Vec3, 3> normals;
    std::vector<std::uint32_t> vt, vn;
    for (const Vec2& t : mesh.corner_uvs) vt.push_back(uvs.add(t));
    for (const Vec3& n : mesh.corner_normals) vn.push_back(normals.add(n));
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

void write_off(std::FILE* f, const Mesh& mesh) {
    std::fprintf(f, "OFF\n%zu %zu 0\n", mesh.positions.size(), mesh.triangles.size());
    for (const Vec3& p : mesh.positions) std::fprintf(f, "%.17g %.17g %.17g\n", p.x, p.y, p.z);
    for (const Triangle& t : mesh.triangles) std::fprintf(f, "3 %u %u %u\n", t[0], t[1], t[2]);
}

void write_ply(std::FILE* f, const Mesh& mesh) {
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
                if (seen[v] && normals[v] != mesh.corner_normals[c]) normal_agree[v] = 0;
                if (!seen[v]) normals[v] = mesh.corner_normals[c];
            }
            if (mesh.has_uvs()) {
                if (seen[v] && uvs[v] != mesh.corner_uvs[c]) uv_agree[v] = 0;
                if (!seen[v]) uvs[v] = mesh.corner_uvs[c];
            }
            seen[v] = 1;
        }
    if (mesh.has_normals()) {
        std::vector<Vec3> sum(nv, Vec3(0.0));
        for (std::size_t c = 0; c < mesh.corner_normals.size(); ++c)
            sum[mesh.triangles[c / 3][c % 3]] += mesh.corner_normals[c];
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
    for (std::size_t v = 0; v < nv; ++v) {
        for (int i = 0; i < 3; ++i) put_f64(f, mesh.positions[v][i]);
        if (mesh.has_normals())
            for (int i = 0; i < 3; ++i) put_f64(f, normals[v][i]);
        if (write_uv)
            for (int i = 0; i < 2; ++i) put_f64(f, uvs[v][i]);
    }
    for (const Triangle& t : mesh.triangles) {
        put_le(f, 3, 1);
        for (std::uint32_t v : t) put_le(f, v, 4);
    }
}

void write_stl(std::FILE* f, const Mesh& mesh) {
    char header[80] = {};
    std::snprintf(header, sizeof header, "subdivtrace binary STL");
    std::fwrite(header, 1, 80, f);
    put_le(f, mesh.triangles.size(), 4);
    for (const Triangle& t : mesh.triangles) {
        const Vec3 &a = mesh.positions[t[0]], &b = mesh.positions[t[1]], &c = mesh.positions[t[2]];
        Vec3 n = glm::cross(b - a, c - a);
        const double len = glm::length(n);
        n = len > 0.0 && std::isfinite(len) ? n / len : Vec3(0.0);
        for (int i = 0; i < 3; ++i) put_f32(f, n[i]);
        for (const Vec3* p : {&a, &b, &c})
            for (int i = 0; i < 3; ++i) put_f32(f, (*p)[i]);
        put_le(f, 0, 2);
    }
}

}  // namespace

Mesh read_mesh(const std::string& path, std::vector<std::string>* warnings,
               const WeldOptions& weld, WeldReport* report) {
    const std::string ext = extension_of(path);
    if (ext != "obj" && ext != "off" && ext != "ply" && ext != "stl")
        fail(path, "unsupported file format '" + ext + "' (expected .obj, .off, .ply or .stl)");
    const std::string data = read_file(path);
    Polygons polygons = ext == "obj"   ? read_obj(path, data, warnings)
                        : ext == "off" ? read_off(path, data)
                        : ext == "ply" ? read_ply(path, data, warnings)
                                       : read_stl(path, data, warnings);
    return finish(polygons, path, warnings, weld, report);
}

void write_mesh(const std::string& path, const Mesh& mesh) {
    const std::string ext = extension_of(path);
    if (ext != "obj" && ext != "off" && ext != "ply" && ext != "stl")
        fail(path, "cannot write format '" + ext + "' (expected .obj, .off, .ply or .stl)");
    validate_mesh(mesh, path);
    write_atomically(path, [&](std::FILE* f) {
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

std::string mesh2_text(const Mesh& mesh, const std::string& ident) {
    if (!is_pov_identifier(ident))
        throw std::invalid_argument("not a POV-Ray identifier: '" + ident + "'");
    validate_mesh(mesh, "mesh2 " + ident);
    Dedup<Vec3, 3> normals;
    Dedup<Vec2, 2> uvs;
    std::vector<std::uint32_t> ni, ti;
    for (const Vec3& n : mesh.corner_normals) ni.push_back(normals.add(n));
    for (const Vec2& t : mesh.corner_uvs) ti.push_back(uvs.add(t));

    std::string out;
    out.reserve(80 * mesh.positions.size() + 40 * mesh.triangles.size() * 3);
    char buf[128];
    auto emit = [&](const char* fmt, auto... args) {
        std::snprintf(buf, sizeof buf, fmt, args...);
        out += buf;
    };
    emit("// subdivtrace: %zu vertices, %zu triangles\n", mesh.positions.size(),
         mesh.triangles.size());
    out += "#declare " + ident + " = mesh2 {\n";
    auto section = [&](const char* name, std::size_t count, auto&& item) {
        emit("  %s {\n    %zu", name, count);
        for (std::size_t i = 0; i < count; ++i) {
            out += ",\n    ";
            item(i);
        }
        out += "\n  }\n";
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
    out += "}\n";
    return out;
}

void write_mesh2(const std::string& path, const Mesh& mesh, const std::string& ident) {
    const std::string text = mesh2_text(mesh, ident);
    write_atomically(path, [&](std::FILE* f) { std::fwrite(text.data(), 1, text.size(), f); });
}

}  // namespace subdivtrace
