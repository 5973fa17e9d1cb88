#include "overlay.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "mvr/core/stereo_surfaces.h"

namespace mvr::viewer {
namespace {

void fillRect(Image& image, int x0, int y0, int x1, int y1, Rgba8 c) {
    x0 = std::max(x0, 0);
    y0 = std::max(y0, 0);
    x1 = std::min(x1, image.width);
    y1 = std::min(y1, image.height);
    for (int y = y0; y < y1; ++y) {
        std::uint8_t* p = image.row(y) + std::size_t(x0) * 4;
        for (int x = x0; x < x1; ++x, p += 4) {
            p[0] = c.r;
            p[1] = c.g;
            p[2] = c.b;
        }
    }
}

}  // namespace

// The HUD is 2D at the screen's depth (zero parallax): the library's text (stereo_surfaces.h),
// drawn at the same pixels in every eye, without a depth test.
glm::ivec2 textSize(std::string_view text, int scale) { return mvr::textSize(text, scale); }

void drawText(Image& image, int x, int y, std::string_view text, Rgba8 color, int scale) {
    mvr::drawText(image, x, y, text, color, scale);
}

void darkenRect(Image& image, int x0, int y0, int x1, int y1, float keep) {
    x0 = std::max(x0, 0);
    y0 = std::max(y0, 0);
    x1 = std::min(x1, image.width);
    y1 = std::min(y1, image.height);
    const int k = int(std::lround(std::clamp(keep, 0.0f, 1.0f) * 256.0f));
    for (int y = y0; y < y1; ++y) {
        std::uint8_t* p = image.row(y) + std::size_t(x0) * 4;
        for (int x = x0; x < x1; ++x, p += 4) {
            for (int ch = 0; ch < 3; ++ch) p[ch] = std::uint8_t((p[ch] * k) >> 8);
        }
    }
}

void drawCrosshair(Image& image, glm::vec2 center, int arm, Rgba8 color) {
    const int cx = int(std::floor(center.x));
    const int cy = int(std::floor(center.y));
    const int gap = std::max(2, arm / 3);
    const Rgba8 outline{0, 0, 0, 255};
    // Outline first (1 pixel around each 2-pixel-wide arm), then the arms, then a centre dot.
    for (int pass = 0; pass < 2; ++pass) {
        const int o = pass == 0 ? 1 : 0;
        const Rgba8 c = pass == 0 ? outline : color;
        fillRect(image, cx - arm - o, cy - 1 - o, cx - gap + o, cy + 1 + o, c);  // left
        fillRect(image, cx + gap - o, cy - 1 - o, cx + arm + o, cy + 1 + o, c);  // right
        fillRect(image, cx - 1 - o, cy - arm - o, cx + 1 + o, cy - gap + o, c);  // up
        fillRect(image, cx - 1 - o, cy + gap - o, cx + 1 + o, cy + arm + o, c);  // down
        fillRect(image, cx - 1 - o, cy - 1 - o, cx + 1 + o, cy + 1 + o, c);      // dot
    }
}

}  // namespace mvr::viewer
