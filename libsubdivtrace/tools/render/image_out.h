#pragma once
// Writing rendered images. OpenImageIO lives in a separate module
// (image_module/) loaded on the first write, so a process that writes no
// image never maps its libraries (the library itself stays free of it).

#include <string>
#include <vector>

#include "render/render_loop.h"

namespace subdivtrace::tools {

/// Writes the image (8-bit sRGB for .png/.jpg/.tga/.ppm, float otherwise).
/// Writes to a temporary name and renames, so a failure leaves no partial
/// file; throws std::runtime_error "<path>: <reason>" (also when the image
/// module cannot be loaded: the reason lists where it was looked for).
void write_image(const std::string& path, const Image& image);

/// Where write_image looks for the image module, in order: the
/// SUBDIVTRACE_IMAGE_MODULE environment variable (a file), the executable's
/// directory (the build tree puts it there), <executable>/../<libdir>/subdivtrace
/// (an installed or relocated prefix), the configured prefix's <libdir>/subdivtrace.
std::vector<std::string> image_module_candidates();

/// Throws std::runtime_error "<path>: ..." like write_image if no candidate
/// file exists, without loading the module: a render can fail before it
/// starts rather than after it has traced every pixel.
void check_image_module(const std::string& path);

}  // namespace subdivtrace::tools
