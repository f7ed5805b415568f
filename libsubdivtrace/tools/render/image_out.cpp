#include "render/image_out.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>

#include <OpenImageIO/imageio.h>

namespace subdivtrace::tools {

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

}  // namespace

void write_image(const std::string& path, const Image& image) {
    const std::string temp = path + ".partial";
    auto out = OIIO::ImageOutput::create(path);
    if (!out) throw std::runtime_error(path + ": no image format for this file name");
    const bool as_float = wants_float(path);
    OIIO::ImageSpec spec(image.width, image.height, 3,
                         as_float ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8);
    // Open the temporary file with the writer chosen for the real name.
    if (!out->open(temp, spec)) throw std::runtime_error(path + ": " + out->geterror());
    bool ok;
    if (as_float) {
        ok = out->write_image(OIIO::TypeDesc::FLOAT, image.rgb.data());
    } else {
        std::vector<unsigned char> bytes(image.rgb.size());
        std::transform(image.rgb.begin(), image.rgb.end(), bytes.begin(), to_srgb8);
        ok = out->write_image(OIIO::TypeDesc::UINT8, bytes.data());
    }
    ok = out->close() && ok;
    if (!ok || std::rename(temp.c_str(), path.c_str()) != 0) {
        std::remove(temp.c_str());
        throw std::runtime_error(path + ": could not write the image");
    }
}

}  // namespace subdivtrace::tools
