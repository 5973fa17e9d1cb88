#include "mvr/core/image.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <memory>

#include <fmt/core.h>

namespace mvr {

void Image::reset(int w, int h, std::pmr::memory_resource* memory) {
    std::destroy_at(&rgba);
    std::construct_at(&rgba, memory ? memory : std::pmr::get_default_resource());
    width = w, height = h;
    rgba.resize(static_cast<std::size_t>(w) * h * 4);
}

void Image::reuseOrReset(int w, int h, std::pmr::memory_resource* memory) {
    const bool same =
        !memory && width == w && height == h && rgba.size() == std::size_t(w) * std::size_t(h) * 4;
    if (!same) reset(w, h, memory);
}

void DepthImage::reuseOrReset(int w, int h, std::pmr::memory_resource* memory) {
    const bool same =
        !memory && width == w && height == h && depth.size() == std::size_t(w) * std::size_t(h);
    if (!same) reset(w, h, 1.0f, memory);
}

void DepthImage::reset(int w, int h, float fill, std::pmr::memory_resource* memory) {
    std::destroy_at(&depth);
    std::construct_at(&depth, memory ? memory : std::pmr::get_default_resource());
    width = w, height = h;
    depth.assign(static_cast<std::size_t>(w) * h, fill);
}

Image::Image(int w, int h, Rgba8 fill) : width(w), height(h) {
    rgba.resize(static_cast<std::size_t>(w) * h * 4);
    for (std::size_t i = 0; i < rgba.size(); i += 4) {
        rgba[i] = fill.r;
        rgba[i + 1] = fill.g;
        rgba[i + 2] = fill.b;
        rgba[i + 3] = fill.a;
    }
}

Rgba8 Image::at(int x, int y) const {
    const std::uint8_t* p = rgba.data() + (static_cast<std::size_t>(y) * width + x) * 4;
    return {p[0], p[1], p[2], p[3]};
}

void Image::set(int x, int y, Rgba8 c) {
    std::uint8_t* p = rgba.data() + (static_cast<std::size_t>(y) * width + x) * 4;
    p[0] = c.r;
    p[1] = c.g;
    p[2] = c.b;
    p[3] = c.a;
}

ImageDiff compareImages(const Image& a, const Image& b, int threshold) {
    ImageDiff diff;
    if (a.width != b.width || a.height != b.height) {
        diff.maxDelta = 256;
        return diff;
    }
    double sum = 0.0, squares = 0.0;
    for (int y = 0; y < a.height; ++y) {
        const std::uint8_t* pa = a.row(y);
        const std::uint8_t* pb = b.row(y);
        for (int x = 0; x < a.width; ++x) {
            int worst = 0;
            for (int c = 0; c < 3; ++c) {
                const int d = std::abs(int(pa[x * 4 + c]) - int(pb[x * 4 + c]));
                worst = std::max(worst, d);
                sum += d;
                squares += double(d) * d;
            }
            if (worst > threshold) ++diff.differingPixels;
            if (worst > diff.maxDelta) {
                diff.maxDelta = worst;
                diff.worstX = x;
                diff.worstY = y;
            }
        }
    }
    const double count = double(a.width) * a.height * 3;
    diff.meanDelta = count > 0 ? sum / count : 0.0;
    diff.pixels = long(a.width) * a.height;
    diff.psnr = squares > 0.0 ? 10.0 * std::log10(255.0 * 255.0 * count / squares)
                              : std::numeric_limits<double>::infinity();
    return diff;
}

}  // namespace mvr
