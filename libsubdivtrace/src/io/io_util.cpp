// Helpers shared by the mesh readers and writers (io_util.h).
#include "io/io_util.h"

#include <atomic>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>

#include <unistd.h>

#include "huge_pages.h"

namespace subdivtrace::io {

void fail(const std::string& path, const std::string& reason) {
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

std::string read_file(const std::string& path) {
    // A directory opens as a stream on Linux and reports an absurd size.
    std::error_code ec;
    const std::filesystem::file_status st = std::filesystem::status(path, ec);
    if (!ec && std::filesystem::is_directory(st)) fail(path, "is a directory");
    if (!ec && std::filesystem::exists(st) && !std::filesystem::is_regular_file(st))
        fail(path, "not a regular file");
    std::ifstream in(path, std::ios::binary);
    if (!in) fail(path, std::string("cannot open file (") + std::strerror(errno) + ")");
    in.seekg(0, std::ios::end);
    const std::streamoff size = in.tellg();
    if (size < 0) fail(path, "cannot read file (not a regular file?)");
    in.seekg(0, std::ios::beg);
    // Room first, advised onto huge pages before anything writes it: a
    // 100 MB export faulted 25,000 4 kB pages, about 10 us each here
    // (huge_pages.h), where filling it takes a few milliseconds.
    std::string data;
    data.reserve(static_cast<std::size_t>(size));
    detail::advise_huge_pages(data.data(), static_cast<std::size_t>(size));
    data.resize(static_cast<std::size_t>(size));
    if (size > 0 && !in.read(&data[0], size)) fail(path, "cannot read file (I/O error)");
    if (data.empty()) fail(path, "empty file");
    return data;
}

bool exceeds(std::int64_t count, std::int64_t bytes_each, std::int64_t available) {
    return count > 0 && bytes_each > 0 && count > available / bytes_each;
}

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

}  // namespace subdivtrace::io
