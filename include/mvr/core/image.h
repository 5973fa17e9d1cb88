// mvr/core/image.h — RGBA8 color images and float depth images (PNG files: mvr/io/png.h).
//
// Conventions: row 0 is the TOP row of the picture (as in PNG files); pixel (x, y) is at
// index y * width + x. Color is RGBA8, 4 bytes per pixel, non-premultiplied, values as
// rendered (mvr's lighting writes its linear result straight to 8 bits; no sRGB encode).
// Depth is window-space depth in [0, 1] (GL convention: 0 = near plane, 1 = far plane, the
// clear value); a pixel that nothing covered holds 1.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <memory_resource>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "mvr/core/status.h"

namespace mvr {

struct Rgba8 {
    std::uint8_t r = 0, g = 0, b = 0, a = 255;
    friend bool operator==(const Rgba8&, const Rgba8&) = default;
};

/// An RGBA8 image, row 0 at the top.
struct Image {
    int width = 0;
    int height = 0;
    /// width * height * 4 bytes. A pmr vector so that a caller may hand a backend the memory
    /// the pixels go to (OutputBlock, render.h: zero copy out of a render); by default it is
    /// the global heap, as a std::vector's.
    std::pmr::vector<std::uint8_t> rgba;

    Image() = default;
    Image(int w, int h, Rgba8 fill = {0, 0, 0, 255});
    /// Reallocates as w×h (bytes zero) from `memory` (nullptr: the default resource), building
    /// the vector anew so that it keeps `memory` (assignment would keep the old allocator).
    void reset(int w, int h, std::pmr::memory_resource* memory);
    /// For an image about to be overwritten whole: kept as it is when it already is w×h on the
    /// heap (a backend's renderInto frame after frame: no allocation, no page faults), else
    /// reset(w, h, memory).
    void reuseOrReset(int w, int h, std::pmr::memory_resource* memory);

    bool empty() const { return width <= 0 || height <= 0; }
    Rgba8 at(int x, int y) const;
    void set(int x, int y, Rgba8 c);
    std::uint8_t* row(int y) { return rgba.data() + static_cast<std::size_t>(y) * width * 4; }
    const std::uint8_t* row(int y) const {
        return rgba.data() + static_cast<std::size_t>(y) * width * 4;
    }
    friend bool operator==(const Image&, const Image&) = default;
};

/// A float depth image, row 0 at the top, window depth in [0, 1].
struct DepthImage {
    int width = 0;
    int height = 0;
    std::pmr::vector<float> depth;  ///< width * height values (pmr: see Image::rgba)

    DepthImage() = default;
    DepthImage(int w, int h, float fill = 1.0f)
        : width(w), height(h), depth(static_cast<std::size_t>(w) * h, fill) {}
    float at(int x, int y) const { return depth[static_cast<std::size_t>(y) * width + x]; }
    /// Reallocates as w×h filled with `fill`, from `memory` (see Image::reset).
    void reset(int w, int h, float fill, std::pmr::memory_resource* memory);
    /// As Image::reuseOrReset (a reset fills with 1, the far plane).
    void reuseOrReset(int w, int h, std::pmr::memory_resource* memory);
    friend bool operator==(const DepthImage&, const DepthImage&) = default;
};

/// Per-pixel comparison of two images of the same size.
struct ImageDiff {
    int maxDelta = 0;          ///< largest absolute channel difference (0..255)
    double meanDelta = 0.0;    ///< mean absolute channel difference over all RGB channels
    long differingPixels = 0;  ///< pixels whose RGB differ by more than the threshold given
    int worstX = -1, worstY = -1;
    /// Peak signal-to-noise ratio over the RGB channels, dB (+inf when the images are equal).
    double psnr = 0.0;
    long pixels = 0;  ///< width · height
    double percentDiffering() const {
        return pixels ? 100.0 * double(differingPixels) / double(pixels) : 0.0;
    }
};

/// Compares RGB channels (alpha ignored). Precondition: same size (else maxDelta = 256).
ImageDiff compareImages(const Image& a, const Image& b, int threshold = 0);

}  // namespace mvr
