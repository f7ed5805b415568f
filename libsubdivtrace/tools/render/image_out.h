#pragma once
// Writing rendered images with OpenImageIO (the library itself stays free of it).

#include <string>

#include "render/render_loop.h"

namespace subdivtrace::tools {

/// Writes the image (8-bit sRGB for .png/.jpg/.tga/.ppm, float otherwise).
/// Writes to a temporary name and renames, so a failure leaves no partial
/// file; throws std::runtime_error "<path>: <reason>".
void write_image(const std::string& path, const Image& image);

}  // namespace subdivtrace::tools
