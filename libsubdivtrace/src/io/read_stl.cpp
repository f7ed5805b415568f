// STL reader (readers.h): a triangle soup, three vertices per facet
// (mesh_from_arrays welds them), ASCII or binary.
#include "io/readers.h"

#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "huge_pages.h"
#include "io/io_util.h"
#include "io/text_cursor.h"

namespace subdivtrace::io {

namespace {

Polygons read_stl_binary(const std::string& path, const std::string& data, std::uint32_t n) {
    Polygons m;
    // Sizes known from the header (checked against the file's): allocated
    // once, on huge pages (huge_pages.h).
    detail::reserve_huge(m.positions, 3 * std::size_t{n});
    detail::reserve_huge(m.v, 3 * std::size_t{n});
    detail::reserve_huge(m.sizes, n);
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
            const Vec3 p = expect_vec3_any(c, path, "vertex", false);
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


}  // namespace

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

}  // namespace subdivtrace::io
