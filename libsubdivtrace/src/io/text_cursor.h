#pragma once
// A cursor over the text of a mesh file, with line numbers for messages, and
// the number parsers the text readers (OBJ, OFF, ASCII PLY and STL) share.

#include <cstdint>
#include <string>
#include <string_view>

#include "subdivtrace/mesh.h"

namespace subdivtrace::io {

/// A cursor over text. The file buffer is a std::string, so it is
/// NUL-terminated and strtod/strtoll never read past it.
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
const char* parse_double(const char* p, const char* end, double& value);

/// Reads a number at the cursor (same line). False if there is none.
bool read_double(Cursor& c, double& value);

/// A coordinate-like value that must be finite; fails with the line number.
double expect_double(Cursor& c, const std::string& path, const char* what);

/// Like expect_double but first skips newlines and comments (free-form formats).
double expect_double_any(Cursor& c, const std::string& path, const char* what, bool hash);

/// Three expect_double values on this line (x y z of a vertex or normal).
Vec3 expect_vec3(Cursor& c, const std::string& path, const char* what);

/// Three expect_double_any values (free-form formats).
Vec3 expect_vec3_any(Cursor& c, const std::string& path, const char* what, bool hash);

/// An integer at the cursor, anywhere after blank lines/comments.
std::int64_t expect_int_any(Cursor& c, const std::string& path, const char* what, bool hash);

}  // namespace subdivtrace::io
