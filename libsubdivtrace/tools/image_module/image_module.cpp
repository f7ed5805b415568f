// The image module: OpenImageIO behind a C function (image_module.h).
#include "image_module/image_module.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include <OpenImageIO/imageio.h>

namespace {

unsigned char to_srgb8(float linear) {
    const float c = std::clamp(linear, 0.0f, 1.0f);
    const float s = c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
    return static_cast<unsigned char>(std::lround(s * 255.0f));
}

bool wants_float(const std::string& path) {
    const auto dot = path.find_last_of('.');
    const std::string ext = dot == std::string::npos ? "" : path.substr(dot + 1);
    return ext == "exr" || ext == "hdr" || ext == "tif" || ext == "tiff";
}

int fail(const std::string& message, char* error, std::size_t error_size) {
    if (error_size > 0) {
        const std::size_t n = std::min(message.size(), error_size - 1);
        std::memcpy(error, message.data(), n);
        error[n] = '\0';
    }
    return 1;
}

}  // namespace

extern "C" __attribute__((visibility("default"))) int subdivtrace_image_write(
    const char* path_c, int width, int height, const float* rgb, char* error,
    std::size_t error_size) {
    try {
        const std::string path = path_c;
        const std::string temp = path + ".partial";
        auto out = OIIO::ImageOutput::create(path);
        if (!out) return fail("no image format for this file name", error, error_size);
        const bool as_float = wants_float(path);
        OIIO::ImageSpec spec(width, height, 3,
                             as_float ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8);
        // Open the temporary file with the writer chosen for the real name.
        if (!out->open(temp, spec)) return fail(out->geterror(), error, error_size);
        bool ok;
        const std::size_t n = static_cast<std::size_t>(width) * height * 3;
        if (as_float) {
            ok = out->write_image(OIIO::TypeDesc::FLOAT, rgb);
        } else {
            std::vector<unsigned char> bytes(n);
            std::transform(rgb, rgb + n, bytes.begin(), to_srgb8);
            ok = out->write_image(OIIO::TypeDesc::UINT8, bytes.data());
        }
        ok = out->close() && ok;
        if (!ok || std::rename(temp.c_str(), path.c_str()) != 0) {
            std::remove(temp.c_str());
            return fail("could not write the image", error, error_size);
        }
        return 0;
    } catch (const std::exception& e) {
        return fail(e.what(), error, error_size);
    }
}
