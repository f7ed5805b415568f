#pragma once
// False colours for `render --color-by` (the paper's Fig. 2): each pixel takes
// the colour of the level of the leaf its camera ray hit, or of the base
// triangle that leaf came from, shaded by the headlight so the shape stays
// readable; the legend says which colour is which and how many pixels had it.

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "subdivtrace/mesh.h"

namespace subdivtrace::tools {

enum class ColorBy {
    shading,  ///< the normal render: albedo, headlight, point light, shadows
    level,    ///< one colour per subdivision level of the leaf hit
    face,     ///< one colour per base triangle (a hash of its id)
    error,    ///< the hit's certified bound in pixels (Hit::surface_error_px), binned
};

/// "level" | "face" | "error"; nullopt for anything else.
std::optional<ColorBy> parse_color_by(const std::string& name);

/// Pixels per level (index = level) and per base face, of the camera rays that hit.
struct PixelTally {
    std::vector<std::uint64_t> level_pixels;
    std::map<std::uint32_t, std::uint64_t> face_pixels;  ///< only with ColorBy::face
    std::vector<std::uint64_t> error_pixels;  ///< per error_bin, only with ColorBy::error
    void add(const PixelTally& other);
};

/// Bins of the certified bound in pixels: 0 below 1/64 px, then one per
/// doubling, 9 at 4 px and above.
int error_bin(double bound_px);
/// Bin `bin`'s range as text, e.g. "[0.25, 0.5) px".
std::string error_bin_range(int bin);

/// The colour of `level`: a ramp from blue (0) through green and yellow to
/// red and magenta (about 8), then white; named in the legend.
Vec3 level_colour(int level);
/// The name of level_colour(level), for the legend.
const char* level_colour_name(int level);
/// The colour of base face `face`: a well-spread hue from a hash of the id,
/// so neighbouring faces (consecutive ids) differ.
Vec3 face_colour(std::uint32_t face);

/// The legend printed by `render --color-by`: for levels, one line per level
/// with its colour and pixel count and the pixel-weighted mean level; for
/// faces, the number of faces seen and the largest ones.
std::string legend(ColorBy mode, const PixelTally& tally);

}  // namespace subdivtrace::tools
