#pragma once
// Helpers shared by the mesh readers and writers (src/io/): errors naming the
// file, file and extension handling, the size checks against header counts.

#include <cstdint>
#include <cstdio>
#include <functional>
#include <map>
#include <array>
#include <string>
#include <string_view>
#include <vector>

#include "subdivtrace/mesh.h"

namespace subdivtrace::io {

/// Largest element count a header may claim: indices are 32-bit.
constexpr std::int64_t k_max_count = 0xFFFFFFFFll;

/// Throws MeshError("<path>: <reason>").
[[noreturn]] void fail(const std::string& path, const std::string& reason);

/// ASCII lower case.
std::string lower(std::string s);
/// The lower-case extension of `path` without the dot ("" if none).
std::string extension_of(const std::string& path);
/// Case-insensitive ASCII comparison.
bool equals_nocase(std::string_view a, std::string_view b);
/// `word` in single quotes for a message: at most 40 characters, unprintable
/// ones as '?'.
std::string quoted(std::string_view word);
/// %.17g.
std::string format_number(double v);

/// The whole file; fails naming `path` if it cannot be opened or read, is
/// not a regular file, or is empty.
std::string read_file(const std::string& path);

/// True if `needed` (a count times a minimum size per element) cannot fit in
/// `available` bytes, computed without overflow.
bool exceeds(std::int64_t count, std::int64_t bytes_each, std::int64_t available);

/// Writes through `body` into a temporary file beside `path`, then renames it;
/// on any failure the temporary file is removed and MeshError names `path`.
void write_atomically(const std::string& path, const std::function<void(std::FILE*)>& body);

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

}  // namespace subdivtrace::io
