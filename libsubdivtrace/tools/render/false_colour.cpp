#include "render/false_colour.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace subdivtrace::tools {

namespace {

struct NamedColour {
    const char* name;
    double r, g, b;
};

// Levels 0..9, then white for anything deeper.
const NamedColour k_level_colours[] = {
    {"dark blue", 0.10, 0.15, 0.75}, {"blue", 0.15, 0.45, 1.00},
    {"cyan", 0.10, 0.85, 0.90},      {"green", 0.20, 0.80, 0.25},
    {"yellow-green", 0.65, 0.90, 0.15}, {"yellow", 1.00, 0.90, 0.10},
    {"orange", 1.00, 0.55, 0.05},    {"red", 0.95, 0.15, 0.10},
    {"magenta", 0.90, 0.20, 0.80},   {"purple", 0.55, 0.20, 0.85},
};
constexpr int k_named_levels = sizeof(k_level_colours) / sizeof(k_level_colours[0]);

Vec3 hsv_to_rgb(double h, double s, double v) {
    const double k[3] = {5.0, 3.0, 1.0};
    double rgb[3];
    for (int c = 0; c < 3; ++c) {
        const double x = std::fmod(k[c] + h * 6.0, 6.0);
        rgb[c] = v - v * s * std::max(0.0, std::min({x, 4.0 - x, 1.0}));
    }
    return Vec3(rgb[0], rgb[1], rgb[2]);
}

}  // namespace

std::optional<ColorBy> parse_color_by(const std::string& name) {
    if (name == "level") return ColorBy::level;
    if (name == "face") return ColorBy::face;
    if (name == "error") return ColorBy::error;
    return std::nullopt;
}

int error_bin(double bound_px) {
    if (!(bound_px >= 1.0 / 64.0)) return 0;  // NaN lands here too, never indexes out
    const int bin = static_cast<int>(std::floor(std::log2(bound_px))) + 7;
    return std::clamp(bin, 1, 9);
}

std::string error_bin_range(int bin) {
    char text[64];
    if (bin <= 0) return "[0, 1/64) px";
    if (bin >= 9) return "[4, inf) px";
    // Powers of two, below one as fractions: [1/64, 1/32) .. [2, 4).
    const auto name = [](int e) {
        return e >= 0 ? std::to_string(1 << e) : "1/" + std::to_string(1 << -e);
    };
    std::snprintf(text, sizeof text, "[%s, %s) px", name(bin - 7).c_str(), name(bin - 6).c_str());
    return text;
}

void PixelTally::add(const PixelTally& other) {
    if (level_pixels.size() < other.level_pixels.size())
        level_pixels.resize(other.level_pixels.size(), 0);
    for (std::size_t k = 0; k < other.level_pixels.size(); ++k)
        level_pixels[k] += other.level_pixels[k];
    for (const auto& [face, pixels] : other.face_pixels) face_pixels[face] += pixels;
    if (error_pixels.size() < other.error_pixels.size())
        error_pixels.resize(other.error_pixels.size(), 0);
    for (std::size_t k = 0; k < other.error_pixels.size(); ++k)
        error_pixels[k] += other.error_pixels[k];
}

Vec3 level_colour(int level) {
    if (level < 0) level = 0;
    if (level >= k_named_levels) return Vec3(1.0);
    const NamedColour& c = k_level_colours[level];
    return Vec3(c.r, c.g, c.b);
}

const char* level_colour_name(int level) {
    if (level < 0) level = 0;
    return level >= k_named_levels ? "white" : k_level_colours[level].name;
}

Vec3 face_colour(std::uint32_t face) {
    // Hash the id (a 32-bit mix, as in splitmix), then spread hue by the golden ratio.
    std::uint32_t h = face * 0x9e3779b9u;
    h ^= h >> 16;
    h *= 0x85ebca6bu;
    h ^= h >> 13;
    const double hue = std::fmod(h * 0.6180339887498949 / 4294967296.0 * 7.0, 1.0);
    const double saturation = 0.55 + 0.4 * ((h >> 8) & 0xff) / 255.0;
    const double value = 0.7 + 0.3 * ((h >> 16) & 0xff) / 255.0;
    return hsv_to_rgb(hue, saturation, value);
}

std::string legend(ColorBy mode, const PixelTally& tally) {
    std::string out;
    char line[200];
    std::uint64_t total = 0;
    for (std::uint64_t n : tally.level_pixels) total += n;
    if (mode == ColorBy::level) {
        out += "colour by level of the leaf hit (pixels of camera rays that hit):\n";
        double weighted = 0.0;
        for (std::size_t k = 0; k < tally.level_pixels.size(); ++k) {
            const std::uint64_t n = tally.level_pixels[k];
            weighted += static_cast<double>(k) * n;
            if (n == 0) continue;
            const Vec3 c = level_colour(static_cast<int>(k));
            std::snprintf(line, sizeof line,
                          "  level %2zu: %-12s (rgb %.2f %.2f %.2f) %10llu pixels %5.1f%%\n", k,
                          level_colour_name(static_cast<int>(k)), c.x, c.y, c.z,
                          static_cast<unsigned long long>(n), total ? 100.0 * n / total : 0.0);
            out += line;
        }
        std::snprintf(line, sizeof line, "  mean level: %.3f over %llu pixels\n",
                      total ? weighted / total : 0.0, static_cast<unsigned long long>(total));
        out += line;
    } else if (mode == ColorBy::error) {
        out += "colour by the hit's certified bound on its distance to the surface, in pixels:\n";
        for (std::size_t k = 0; k < tally.error_pixels.size(); ++k) {
            const std::uint64_t n = tally.error_pixels[k];
            if (n == 0) continue;
            const Vec3 c = level_colour(static_cast<int>(k));
            std::snprintf(line, sizeof line, "  %-16s %-12s (rgb %.2f %.2f %.2f) %10llu pixels %5.1f%%\n",
                          error_bin_range(static_cast<int>(k)).c_str(),
                          level_colour_name(static_cast<int>(k)), c.x, c.y, c.z,
                          static_cast<unsigned long long>(n), total ? 100.0 * n / total : 0.0);
            out += line;
        }
    } else if (mode == ColorBy::face) {
        std::snprintf(line, sizeof line,
                      "colour by base face (hue from a hash of the face id): %zu faces seen "
                      "in %llu pixels\n",
                      tally.face_pixels.size(), static_cast<unsigned long long>(total));
        out += line;
        std::vector<std::pair<std::uint64_t, std::uint32_t>> by_size;
        for (const auto& [face, pixels] : tally.face_pixels) by_size.emplace_back(pixels, face);
        std::sort(by_size.begin(), by_size.end(),
                  [](const auto& a, const auto& b) { return a.first != b.first ? a.first > b.first
                                                                            : a.second < b.second; });
        const std::size_t shown = std::min<std::size_t>(by_size.size(), 10);
        for (std::size_t k = 0; k < shown; ++k) {
            const Vec3 c = face_colour(by_size[k].second);
            std::snprintf(line, sizeof line, "  face %8u: (rgb %.2f %.2f %.2f) %10llu pixels\n",
                          by_size[k].second, c.x, c.y, c.z,
                          static_cast<unsigned long long>(by_size[k].first));
            out += line;
        }
        if (by_size.size() > shown) {
            std::snprintf(line, sizeof line, "  ... and %zu more faces\n", by_size.size() - shown);
            out += line;
        }
    }
    return out;
}

}  // namespace subdivtrace::tools
