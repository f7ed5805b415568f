// libFuzzer harness of one mesh reader (src/io/read_<format>.cpp), built once
// per format with SUBDIVTRACE_FUZZ_FORMAT = "obj", "off", "ply" or "stl"
// (tests/fuzz/CMakeLists.txt). Any input must give either a Mesh that
// satisfies validate_mesh, or a MeshError naming the file: any other exception,
// a crash, a sanitizer report or a hang is a bug.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "io/readers.h"
#include "subdivtrace/mesh.h"

using namespace subdivtrace;

namespace {

const std::string k_ext = SUBDIVTRACE_FUZZ_FORMAT;
const std::string k_path = "fuzz." + k_ext;

[[noreturn]] void broken(const char* what, const std::string& detail) {
    std::fprintf(stderr, "invariant broken: %s: %s\n", what, detail.c_str());
    std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string bytes(reinterpret_cast<const char*>(data), size);
    for (const bool weld : {true, false}) {
        std::vector<std::string> warnings;
        Mesh mesh;
        try {
            io::Polygons polygons = io::read_polygons(k_ext, k_path, bytes, &warnings);
            mesh = io::mesh_from_polygons(polygons, k_path, &warnings, WeldOptions{weld, 0.0},
                                          nullptr);
        } catch (const MeshError& e) {
            // The message names the file.
            if (std::string(e.what()).rfind(k_path + ": ", 0) != 0) broken("message", e.what());
            continue;
        }
        try {
            validate_mesh(mesh, k_path);
        } catch (const MeshError& e) {
            broken("validate_mesh after a successful read", e.what());
        }
        for (const std::string& w : warnings)
            if (w.rfind(k_path + ": ", 0) != 0) broken("warning", w);
    }
    return 0;
}
