#include "overlay.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wsign-compare"
#include <stb_easy_font.h>
#pragma GCC diagnostic pop

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

// One stb_easy_font vertex: x, y, z as floats and an RGBA colour (16 bytes).
struct EasyFontVertex {
    float x, y, z;
    unsigned char color[4];
};

}  // namespace

glm::ivec2 textSize(std::string_view text, int scale) {
    std::string s(text);
    // stb_easy_font_height() counts 12 pixels per line break plus the last line's glyph height.
    return {stb_easy_font_width(s.data()) * scale, stb_easy_font_height(s.data()) * scale};
}

void drawText(Image& image, int x, int y, std::string_view text, Rgba8 color, int scale) {
    if (text.empty() || image.empty()) return;
    std::string s(text);
    // ~270 bytes of vertices per character at most (stb_easy_font's README); quads are axis
    // aligned rectangles (4 vertices: top-left, top-right, bottom-right, bottom-left).
    std::vector<EasyFontVertex> vertices(s.size() * 64 + 64);
    unsigned char rgba[4] = {color.r, color.g, color.b, color.a};
    const int quads = stb_easy_font_print(0.0f, 0.0f, s.data(), rgba, vertices.data(),
                                          int(vertices.size() * sizeof(EasyFontVertex)));
    for (int q = 0; q < quads; ++q) {
        const EasyFontVertex& a = vertices[std::size_t(q) * 4];
        const EasyFontVertex& c = vertices[std::size_t(q) * 4 + 2];
        fillRect(image, x + int(std::lround(a.x * scale)), y + int(std::lround(a.y * scale)),
                 x + int(std::lround(c.x * scale)), y + int(std::lround(c.y * scale)), color);
    }
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
