#include "render/image_out.h"

#include <dlfcn.h>
#include <unistd.h>

#include <cstdlib>
#include <mutex>
#include <stdexcept>

#include "image_module/image_module.h"

namespace subdivtrace::tools {

namespace {

std::string executable_dir() {
    std::string buf(4096, '\0');
    const ssize_t n = readlink("/proc/self/exe", buf.data(), buf.size() - 1);
    if (n <= 0) return "";
    buf.resize(static_cast<std::size_t>(n));
    const auto slash = buf.find_last_of('/');
    return slash == std::string::npos ? "" : buf.substr(0, slash);
}

/// The module's write function, loaded once; throws with every place tried.
subdivtrace_image_write_fn load_writer() {
    static std::mutex mutex;
    static subdivtrace_image_write_fn writer = nullptr;
    std::lock_guard<std::mutex> lock(mutex);
    if (writer) return writer;
    std::string tried;
    for (const std::string& file : image_module_candidates()) {
        if (access(file.c_str(), F_OK) != 0) {
            tried += "\n  " + file + ": no such file";
            continue;
        }
        void* handle = dlopen(file.c_str(), RTLD_NOW | RTLD_LOCAL);
        if (!handle) {
            const char* e = dlerror();
            tried += "\n  " + file + ": " + (e ? e : "cannot load");
            continue;
        }
        void* symbol = dlsym(handle, SUBDIVTRACE_IMAGE_WRITE_SYMBOL);
        if (!symbol) {
            tried += "\n  " + file + ": no " SUBDIVTRACE_IMAGE_WRITE_SYMBOL;
            dlclose(handle);
            continue;
        }
        writer = reinterpret_cast<subdivtrace_image_write_fn>(symbol);
        return writer;
    }
    throw std::runtime_error("cannot write images: the image module " SUBDIVTRACE_IMAGE_MODULE_FILE
                             " (OpenImageIO) was not found or did not load:" + tried);
}

}  // namespace

std::vector<std::string> image_module_candidates() {
    std::vector<std::string> out;
    if (const char* env = std::getenv("SUBDIVTRACE_IMAGE_MODULE"); env && *env) out.push_back(env);
    const std::string file = SUBDIVTRACE_IMAGE_MODULE_FILE;
    const std::string exe = executable_dir();
    if (!exe.empty()) {
        out.push_back(exe + "/" + file);
        out.push_back(exe + "/../" SUBDIVTRACE_INSTALL_LIBDIR "/subdivtrace/" + file);
    }
    out.push_back(SUBDIVTRACE_INSTALL_FULL_LIBDIR "/subdivtrace/" + file);
    return out;
}

void check_image_module(const std::string& path) {
    std::string tried;
    for (const std::string& file : image_module_candidates()) {
        if (access(file.c_str(), F_OK) == 0) return;
        tried += "\n  " + file + ": no such file";
    }
    throw std::runtime_error(path + ": cannot write images: the image module " SUBDIVTRACE_IMAGE_MODULE_FILE
                             " (OpenImageIO) was not found:" + tried);
}

void write_image(const std::string& path, const Image& image) {
    subdivtrace_image_write_fn write;
    try {
        write = load_writer();
    } catch (const std::exception& e) {
        throw std::runtime_error(path + ": " + e.what());
    }
    char error[512] = "";
    if (write(path.c_str(), image.width, image.height, image.rgb.data(), error, sizeof error) != 0)
        throw std::runtime_error(path + ": " + error);
}

}  // namespace subdivtrace::tools
