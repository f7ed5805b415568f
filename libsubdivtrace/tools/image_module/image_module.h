#pragma once
// The C interface between the renderers and the image module: a shared
// module, built against OpenImageIO, that the renderers dlopen() only when
// they write an image (render/image_out.cpp), so no other command loads
// OpenImageIO's ~260 shared libraries.

#include <cstddef>

extern "C" {

/// Name of the module's file (found next to the executable, then in the
/// install prefix's library directory).
#define SUBDIVTRACE_IMAGE_MODULE_FILE "libsubdivtrace_image.so"
/// The symbol render/image_out.cpp looks up.
#define SUBDIVTRACE_IMAGE_WRITE_SYMBOL "subdivtrace_image_write"

/// Writes width x height RGB pixels (linear floats, row 0 at the top) to
/// `path`, choosing the format by its name: 8-bit sRGB for .png/.jpg/.tga/
/// .ppm, float for .exr/.hdr/.tif. Writes to a temporary name and renames.
/// Returns 0 on success; otherwise writes a message of at most error_size
/// bytes (NUL-terminated) to `error` and returns nonzero.
int subdivtrace_image_write(const char* path, int width, int height, const float* rgb,
                            char* error, std::size_t error_size);

using subdivtrace_image_write_fn = int (*)(const char*, int, int, const float*, char*,
                                           std::size_t);
}
