// Synthetic views for the composite tests: every pixel of view v at (x, y) has a color that
// names v, x and y, so a composite can be checked pixel by pixel against where it came from.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <unistd.h>

#include "mvr/core/image.h"

namespace mvr::composite::test {

/// Color of view `view` at (x, y): r = x, g = y, b = 10 + 20·view, a = 200 + view (x, y < 256).
inline Rgba8 tag(int view, int x, int y) {
    return {static_cast<std::uint8_t>(x), static_cast<std::uint8_t>(y),
            static_cast<std::uint8_t>(10 + 20 * view), static_cast<std::uint8_t>(200 + view)};
}

inline Image taggedView(int view, int w, int h) {
    Image img(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) img.set(x, y, tag(view, x, y));
    return img;
}

inline std::vector<Image> taggedViews(int n, int w, int h) {
    std::vector<Image> views;
    for (int v = 0; v < n; ++v) views.push_back(taggedView(v, w, h));
    return views;
}

inline Image solid(int w, int h, Rgba8 c) { return Image(w, h, c); }

/// A smooth, JPEG-friendly image (gradients), different per `seed`.
inline Image smoothView(int w, int h, int seed) {
    Image img(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            img.set(x, y,
                    {static_cast<std::uint8_t>(40 + (x * 150) / w + seed * 10),
                     static_cast<std::uint8_t>(60 + (y * 120) / h),
                     static_cast<std::uint8_t>(200 - seed * 30 - (x + y) * 50 / (w + h)), 255});
    return img;
}

/// Largest RGB channel difference (alpha ignored); 256 for different sizes.
inline int maxRgbDelta(const Image& a, const Image& b) {
    if (a.width != b.width || a.height != b.height) return 256;
    int worst = 0;
    for (std::size_t i = 0; i < a.rgba.size(); ++i) {
        if (i % 4 == 3) continue;
        const int d = a.rgba[i] > b.rgba[i] ? a.rgba[i] - b.rgba[i] : b.rgba[i] - a.rgba[i];
        worst = d > worst ? d : worst;
    }
    return worst;
}

/// A fresh empty directory under the system temp folder for one test.
inline std::filesystem::path freshDir(const std::string& name) {
    const auto dir = std::filesystem::temp_directory_path() /
                     ("mvr_composite_test_" + std::to_string(::getpid()) + "_" + name);
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
}

}  // namespace mvr::composite::test
