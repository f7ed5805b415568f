// The text cursor and number parsers of the text readers (text_cursor.h).
#include "io/text_cursor.h"

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <limits>

#include "io/io_util.h"

namespace subdivtrace::io {

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

bool read_double(Cursor& c, double& value) {
    c.skip_inline();
    if (c.eof() || *c.p == '\n') return false;
    const char* e = parse_double(c.p, c.end, value);
    if (!e || e == c.p || (e < c.end && !Cursor::space(*e))) return false;
    c.p = e;
    return true;
}

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

double expect_double_any(Cursor& c, const std::string& path, const char* what, bool hash) {
    c.skip_all(hash);
    return expect_double(c, path, what);
}

Vec3 expect_vec3(Cursor& c, const std::string& path, const char* what) {
    Vec3 v;
    for (int k = 0; k < 3; ++k) v[k] = expect_double(c, path, what);
    return v;
}

Vec3 expect_vec3_any(Cursor& c, const std::string& path, const char* what, bool hash) {
    Vec3 v;
    for (int k = 0; k < 3; ++k) v[k] = expect_double_any(c, path, what, hash);
    return v;
}

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

}  // namespace subdivtrace::io
