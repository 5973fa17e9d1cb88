// Sky at infinity, floating window, letterbox and 2D at depth (mvr/core/stereo_surfaces.h).
#include "mvr/core/stereo_surfaces.h"

#include "mvr/core/angular_aa.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>

#include <fmt/core.h>
#include <glm/gtc/matrix_access.hpp>

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wunused-parameter"
#pragma GCC diagnostic ignored "-Wunused-but-set-variable"
#pragma GCC diagnostic ignored "-Wdouble-promotion"
#pragma GCC diagnostic ignored "-Wimplicit-fallthrough"
#include <stb_easy_font.h>
#pragma GCC diagnostic pop

namespace mvr {
namespace {

constexpr float kPi = 3.14159265358979323846f;

Status checkSizes(const std::vector<Image>& color, const std::vector<DepthImage>& depth,
                  const Rig& rig, bool needDepth) {
    if (int(color.size()) != rig.viewCount())
        return usageError(
            fmt::format("{} color images for a rig of {} views", color.size(), rig.viewCount()));
    if (!needDepth && depth.empty()) return {};
    if (depth.size() != color.size())
        return usageError(fmt::format("{} depth images for {} views", depth.size(), color.size()));
    for (std::size_t v = 0; v < color.size(); ++v) {
        if (depth[v].width != color[v].width || depth[v].height != color[v].height)
            return usageError(fmt::format("view {}: depth image size differs from color", v));
    }
    return {};
}

glm::vec3 texel(const Image& im, int x, int y) {
    const std::uint8_t* p = im.rgba.data() + (std::size_t(y) * im.width + x) * 4;
    return glm::vec3(p[0], p[1], p[2]) / 255.0f;
}

// Bilinear at continuous (u, v) in pixels of the rectangle [x0, x0 + w) × [y0, y0 + h);
// `wrapX` wraps columns (equirect longitude), else clamps.
glm::vec3 bilinear(const Image& im, int x0, int y0, int w, int h, float u, float v, bool wrapX) {
    const float fx = u - 0.5f, fy = v - 0.5f;
    const int ix = int(std::floor(fx)), iy = int(std::floor(fy));
    const float tx = fx - float(ix), ty = fy - float(iy);
    auto cx = [&](int x) { return wrapX ? ((x % w) + w) % w : std::clamp(x, 0, w - 1); };
    auto cy = [&](int y) { return std::clamp(y, 0, h - 1); };
    const glm::vec3 a = texel(im, x0 + cx(ix), y0 + cy(iy));
    const glm::vec3 b = texel(im, x0 + cx(ix + 1), y0 + cy(iy));
    const glm::vec3 c = texel(im, x0 + cx(ix), y0 + cy(iy + 1));
    const glm::vec3 d = texel(im, x0 + cx(ix + 1), y0 + cy(iy + 1));
    return glm::mix(glm::mix(a, b, tx), glm::mix(c, d, tx), ty);
}

Rgba8 toRgba8(glm::vec3 c, std::uint8_t alpha) {
    auto q = [](float f) { return std::uint8_t(std::lround(std::clamp(f, 0.0f, 1.0f) * 255.0f)); };
    return {q(c.x), q(c.y), q(c.z), alpha};
}

Status needsDepth(const char* feature, const RenderOutput& out) {
    if (!out.depth.empty()) return {};
    return unsupportedError(fmt::format("{} needs a depth buffer; method {} returns none", feature,
                                        out.method.empty() ? "(unknown)" : out.method));
}

// stb_easy_font vertex: x, y, z as floats and an RGBA color (16 bytes).
struct EasyFontVertex {
    float x, y, z;
    unsigned char color[4];
};

std::optional<float> parseFloat(std::string_view s) {
    while (!s.empty() && s.front() == ' ') s.remove_prefix(1);
    while (!s.empty() && s.back() == ' ') s.remove_suffix(1);
    float f = 0.0f;
    auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), f);
    if (ec != std::errc() || ptr != s.data() + s.size() || !std::isfinite(f)) return std::nullopt;
    return f;
}

}  // namespace

// ---- sky (loadSky(): scene_io.cpp) ------------------------------------------------------------

CubeCrossPoint cubeCrossPoint(glm::vec3 d) {
    const glm::vec3 a = glm::abs(d);
    CubeCrossPoint c;
    if (a.x >= a.y && a.x >= a.z) {
        c.row = 1;
        if (d.x > 0) {
            c.col = 2, c.u = d.z / a.x;
        } else {
            c.col = 0, c.u = -d.z / a.x;
        }
        c.v = -d.y / a.x;
    } else if (a.y >= a.z) {
        c.col = 1, c.u = d.x / a.y;
        if (d.y > 0) {
            c.row = 0, c.v = -d.z / a.y;
        } else {
            c.row = 2, c.v = d.z / a.y;
        }
    } else {
        c.row = 1;
        if (d.z < 0) {
            c.col = 1, c.u = d.x / a.z;
        } else {
            c.col = 3, c.u = -d.x / a.z;
        }
        c.v = -d.y / a.z;
    }
    return c;
}

glm::vec3 skyColor(const Sky& sky, glm::vec3 dir) {
    const glm::vec3 d = glm::normalize(dir);
    switch (sky.kind) {
        case Sky::Kind::Gradient: {
            if (d.y >= 0.0f) return glm::mix(sky.horizon, sky.zenith, std::sqrt(d.y));
            return glm::mix(sky.horizon, sky.ground, std::sqrt(std::min(1.0f, -d.y * 4.0f)));
        }
        case Sky::Kind::Equirect: {
            const float lon = std::atan2(d.x, -d.z);
            const float lat = std::asin(std::clamp(d.y, -1.0f, 1.0f));
            const float u = (0.5f + lon / (2.0f * kPi)) * float(sky.image.width);
            const float v = (0.5f - lat / kPi) * float(sky.image.height);
            return bilinear(sky.image, 0, 0, sky.image.width, sky.image.height, u, v, true);
        }
        case Sky::Kind::CubeCross: {
            const int s = sky.image.width / 4;
            const CubeCrossPoint c = cubeCrossPoint(d);
            return bilinear(sky.image, c.col * s, c.row * s, s, s, (c.u + 1.0f) * 0.5f * float(s),
                            (c.v + 1.0f) * 0.5f * float(s), false);
        }
    }
    return sky.horizon;
}

glm::vec3 viewRayDirection(const View& view, glm::vec2 pixel, int width, int height) {
    const glm::vec2 ndc(2.0f * pixel.x / float(width) - 1.0f,
                        1.0f - 2.0f * pixel.y / float(height));
    const glm::vec4 farView = glm::inverse(view.clipFromView) * glm::vec4(ndc, 1.0f, 1.0f);
    const glm::vec3 dirView = glm::vec3(farView) / farView.w;  // the eye is the view's origin
    return glm::mat3(glm::inverse(view.viewFromWorld)) * dirView;
}

Status drawSky(const Sky& sky, const Rig& rig, std::vector<Image>& color,
               const std::vector<DepthImage>& depth) {
    if (Status s = checkSizes(color, depth, rig, true); !s) return s;
    for (std::size_t v = 0; v < color.size(); ++v) {
        Image& im = color[v];
        const View& view = rig.views[v];
        const glm::mat4 invClip = glm::inverse(view.clipFromView);
        const glm::mat3 worldFromView = glm::mat3(glm::inverse(view.viewFromWorld));
        for (int y = 0; y < im.height; ++y) {
            std::uint8_t* p = im.row(y);
            for (int x = 0; x < im.width; ++x, p += 4) {
                if (depth[v].at(x, y) < 1.0f) continue;
                const glm::vec2 ndc(2.0f * (float(x) + 0.5f) / float(im.width) - 1.0f,
                                    1.0f - 2.0f * (float(y) + 0.5f) / float(im.height));
                const glm::vec4 f = invClip * glm::vec4(ndc, 1.0f, 1.0f);
                const Rgba8 c = toRgba8(skyColor(sky, worldFromView * (glm::vec3(f) / f.w)), p[3]);
                p[0] = c.r, p[1] = c.g, p[2] = c.b;
            }
        }
    }
    return {};
}

// ---- floating window and letterbox -------------------------------------------------------------

float eyeDistance(const View& view, float depth) {
    // z_clip = A·z + B, w_clip = −z, ndc = z_clip / w_clip  →  w = B / (ndc + A).
    const float a = view.clipFromView[2][2], b = view.clipFromView[3][2];
    return b / ((2.0f * depth - 1.0f) + a);
}

float windowDepth(const View& view, float w) {
    const float a = view.clipFromView[2][2], b = view.clipFromView[3][2];
    return ((a * -w + b) / w) * 0.5f + 0.5f;
}

Result<std::vector<WindowStrips>> floatingWindowStrips(const Rig& rig,
                                                       const std::vector<DepthImage>& depth) {
    if (int(depth.size()) != rig.viewCount())
        return usageError(
            fmt::format("{} depth images for a rig of {} views", depth.size(), rig.viewCount()));
    float smin = std::numeric_limits<float>::max(), smax = -smin;
    for (int v = 0; v < rig.viewCount(); ++v) {
        if (!rig.views[v].clipShear)
            return unsupportedError(fmt::format(
                "--floating-window needs an off-axis rig (views differing by a clip shear); "
                "a {} rig's views do not",
                rigKindName(rig.kind)));
        smin = std::min(smin, rig.views[v].clipShear->x);
        smax = std::max(smax, rig.views[v].clipShear->x);
    }
    const float c = rig.convergence;
    std::vector<WindowStrips> strips(depth.size());
    for (int v = 0; v < rig.viewCount(); ++v) {
        const View& view = rig.views[v];
        const DepthImage& d = depth[v];
        const float width = float(d.width);
        const float kl = width * (smax - view.clipShear->x) * 0.5f;
        const float kr = width * (view.clipShear->x - smin) * 0.5f;
        float nearL = std::numeric_limits<float>::max(), nearR = nearL;
        for (int y = 0; y < d.height; ++y) {
            for (int x = 0; x < d.width; ++x) {
                const float z = d.at(x, y);
                if (z >= 1.0f) continue;
                const float w = eyeDistance(view, z);
                if (!(w > 0.0f) || w >= c) continue;
                const float k = c / w - 1.0f;
                const float cx = float(x) + 0.5f;
                if (cx < kl * k) nearL = std::min(nearL, w);
                if (width - cx < kr * k) nearR = std::min(nearR, w);
            }
        }
        auto columns = [&](float k, float w) {
            return std::clamp(int(std::ceil(k * (c / w - 1.0f) - 0.5f)), 0, d.width);
        };
        WindowStrips& s = strips[v];
        if (nearL < std::numeric_limits<float>::max())
            s.left = columns(kl, nearL), s.nearestLeft = nearL;
        if (nearR < std::numeric_limits<float>::max())
            s.right = columns(kr, nearR), s.nearestRight = nearR;
    }
    return strips;
}

Result<std::vector<WindowStrips>> applyFloatingWindow(const Rig& rig, std::vector<Image>& color,
                                                      const std::vector<DepthImage>& depth) {
    if (Status s = checkSizes(color, depth, rig, true); !s) return s;
    auto strips = floatingWindowStrips(rig, depth);
    if (!strips) return strips.status();
    for (std::size_t v = 0; v < color.size(); ++v) {
        Image& im = color[v];
        const WindowStrips& s = (*strips)[v];
        for (int y = 0; y < im.height; ++y) {
            std::uint8_t* row = im.row(y);
            for (int x = 0; x < im.width; ++x) {
                if (x >= s.left && x < im.width - s.right) continue;
                row[x * 4] = row[x * 4 + 1] = row[x * 4 + 2] = 0;
            }
        }
    }
    return strips;
}

int letterboxRows(int height, float percent) {
    return std::clamp(int(std::lround(double(percent) / 100.0 * height)), 0, height / 2);
}

Status drawLetterbox(const Rig& rig, std::vector<Image>& color, std::vector<DepthImage>& depth,
                     float percent) {
    if (!(percent > 0.0f && percent < 50.0f))
        return usageError(
            fmt::format("--letterbox {}: must be in (0, 50) percent of the height", percent));
    if (Status s = checkSizes(color, depth, rig, true); !s) return s;
    for (std::size_t v = 0; v < color.size(); ++v) {
        Image& im = color[v];
        DepthImage& d = depth[v];
        const float band = windowDepth(rig.views[v], rig.convergence);
        const int rows = letterboxRows(im.height, percent);
        for (int y = 0; y < im.height; ++y) {
            if (y >= rows && y < im.height - rows) continue;
            std::uint8_t* p = im.row(y);
            for (int x = 0; x < im.width; ++x, p += 4) {
                float& z = d.depth[std::size_t(y) * d.width + x];
                if (z < band) continue;  // out of the screen: overdraws the band
                p[0] = p[1] = p[2] = 0;
                z = band;
            }
        }
    }
    return {};
}

// ---- 2D at depth ---------------------------------------------------------------------------

glm::ivec2 textSize(std::string_view text, int scale) {
    std::string s(text);
    return {stb_easy_font_width(s.data()) * scale, stb_easy_font_height(s.data()) * scale};
}

void drawText(Image& image, int x, int y, std::string_view text, Rgba8 color, int scale,
              const DepthImage* depth, float textDepth) {
    if (text.empty() || image.empty()) return;
    std::string s(text);
    std::vector<EasyFontVertex> vertices(s.size() * 64 + 64);
    unsigned char rgba[4] = {color.r, color.g, color.b, color.a};
    const int quads = stb_easy_font_print(0.0f, 0.0f, s.data(), rgba, vertices.data(),
                                          int(vertices.size() * sizeof(EasyFontVertex)));
    for (int q = 0; q < quads; ++q) {
        const EasyFontVertex& a = vertices[std::size_t(q) * 4];
        const EasyFontVertex& c = vertices[std::size_t(q) * 4 + 2];
        const int x0 = std::max(0, x + int(std::lround(a.x * scale)));
        const int y0 = std::max(0, y + int(std::lround(a.y * scale)));
        const int x1 = std::min(image.width, x + int(std::lround(c.x * scale)));
        const int y1 = std::min(image.height, y + int(std::lround(c.y * scale)));
        for (int py = y0; py < y1; ++py) {
            std::uint8_t* p = image.row(py) + std::size_t(x0) * 4;
            for (int px = x0; px < x1; ++px, p += 4) {
                if (depth && textDepth > depth->at(px, py)) continue;
                p[0] = color.r, p[1] = color.g, p[2] = color.b;
            }
        }
    }
}

void drawSprite(Image& image, int x, int y, const Image& sprite, const DepthImage* depth,
                float spriteDepth) {
    for (int sy = 0; sy < sprite.height; ++sy) {
        const int py = y + sy;
        if (py < 0 || py >= image.height) continue;
        for (int sx = 0; sx < sprite.width; ++sx) {
            const int px = x + sx;
            if (px < 0 || px >= image.width) continue;
            const Rgba8 s = sprite.at(sx, sy);
            if (s.a == 0 || (depth && spriteDepth > depth->at(px, py))) continue;
            std::uint8_t* p = image.row(py) + std::size_t(px) * 4;
            const int a = s.a;
            p[0] = std::uint8_t((s.r * a + p[0] * (255 - a) + 127) / 255);
            p[1] = std::uint8_t((s.g * a + p[1] * (255 - a) + 127) / 255);
            p[2] = std::uint8_t((s.b * a + p[2] * (255 - a) + 127) / 255);
        }
    }
}

glm::vec3 labelPoint(const Rig& rig, const Label& label) {
    if (label.anchor) return *label.anchor;
    const Camera& cam = rig.camera;
    const float w = label.distance > 0.0f ? label.distance : rig.convergence;
    const glm::vec2 ndc(2.0f * label.screen.x - 1.0f, 1.0f - 2.0f * label.screen.y);
    // nvidia-gtc2010's 2D-to-3D conversion: clip = (ndc.xy · w, z, w), unprojected through the
    // mono camera.
    const glm::mat4 p = cam.clipFromView();
    const glm::vec4 clip(ndc * w, p[2][2] * -w + p[3][2], w);
    const glm::vec4 viewPoint = glm::inverse(p) * clip;
    return glm::vec3(glm::inverse(cam.viewFromWorld()) * (viewPoint / viewPoint.w));
}

std::optional<glm::vec3> projectToPixel(const View& view, glm::vec3 p, int width, int height) {
    const glm::vec4 clip = view.clipFromWorld() * glm::vec4(p, 1.0f);
    if (!(clip.w > 0.0f)) return std::nullopt;
    const glm::vec3 ndc = glm::vec3(clip) / clip.w;
    return glm::vec3((ndc.x * 0.5f + 0.5f) * float(width), (0.5f - ndc.y * 0.5f) * float(height),
                     ndc.z * 0.5f + 0.5f);
}

Status drawLabels(const Rig& rig, const std::vector<Label>& labels, std::vector<Image>& color,
                  const std::vector<DepthImage>& depth) {
    if (Status s = checkSizes(color, depth, rig, false); !s) return s;
    for (const Label& label : labels) {
        const glm::vec3 point = labelPoint(rig, label);
        const glm::ivec2 size = label.sprite.empty()
                                    ? textSize(label.text, label.scale)
                                    : glm::ivec2(label.sprite.width, label.sprite.height);
        for (std::size_t v = 0; v < color.size(); ++v) {
            Image& im = color[v];
            const auto at = projectToPixel(rig.views[v], point, im.width, im.height);
            if (!at) continue;
            const int x = int(std::lround(at->x - float(size.x) * 0.5f));
            const int y = int(std::lround(at->y - float(size.y) * 0.5f));
            const DepthImage* d = depth.empty() ? nullptr : &depth[v];
            if (label.sprite.empty()) {
                drawText(im, x, y, label.text, label.color, label.scale, d, at->z);
            } else {
                drawSprite(im, x, y, label.sprite, d, at->z);
            }
        }
    }
    return {};
}

Result<Label> parseLabel(const std::string& spec, bool anchored) {
    const char* opt = anchored ? "--label-anchor" : "--label";
    const std::string form = anchored ? "TEXT@X,Y,Z" : "TEXT@x,y[,distance]";
    const auto at = spec.rfind('@');
    if (at == std::string::npos || at == 0)
        return usageError(fmt::format("{} '{}': expected {}", opt, spec, form));
    std::vector<float> numbers;
    std::string_view rest(spec);
    rest.remove_prefix(at + 1);
    while (true) {
        const auto comma = rest.find(',');
        auto f = parseFloat(rest.substr(0, comma));
        if (!f) return usageError(fmt::format("{} '{}': expected {} (numbers)", opt, spec, form));
        numbers.push_back(*f);
        if (comma == std::string_view::npos) break;
        rest.remove_prefix(comma + 1);
    }
    Label label;
    label.text = spec.substr(0, at);
    if (anchored) {
        if (numbers.size() != 3)
            return usageError(fmt::format("{} '{}': expected {}", opt, spec, form));
        for (float n : numbers) {
            if (std::abs(n) > 1.0e12f)  // kMaxCoordinate (mesh.h): a point a scene can hold
                return usageError(fmt::format(
                    "{} '{}': X,Y,Z must be at most 1e12 in magnitude (world units)", opt, spec));
        }
        label.anchor = glm::vec3(numbers[0], numbers[1], numbers[2]);
        return label;
    }
    if (numbers.size() != 2 && numbers.size() != 3)
        return usageError(fmt::format("{} '{}': expected {}", opt, spec, form));
    if (!(numbers[0] >= 0.0f && numbers[0] <= 1.0f && numbers[1] >= 0.0f && numbers[1] <= 1.0f))
        return usageError(fmt::format(
            "{} '{}': the anchor {:g},{:g} lies outside the view (x and y must be 0..1, "
            "fractions of the view)",
            opt, spec, numbers[0], numbers[1]));
    label.screen = {numbers[0], numbers[1]};
    if (numbers.size() == 3) {
        if (!(numbers[2] > 0.0f && numbers[2] <= 1.0e12f))
            return usageError(fmt::format(
                "{} '{}': the distance must be > 0 and at most 1e12 (eye-space, world units)",
                opt, spec));
        label.distance = numbers[2];
    }
    return label;
}

Result<std::vector<WindowStrips>> applyStereoSurfaces(const StereoSurfaces& surfaces,
                                                      const Rig& rig, RenderOutput& out) {
    std::vector<WindowStrips> strips;
    if (surfaces.transparentBackground) {
        if (Status s = needsDepth("--background transparent", out); !s) return s;
        for (std::size_t v = 0; v < out.color.size(); ++v) {
            Image& im = out.color[v];
            const DepthImage& d = out.depth[v];
            for (std::size_t i = 0; i < d.depth.size(); ++i)
                if (d.depth[i] >= 1.0f) im.rgba[4 * i + 3] = 0;
        }
    }
    if (surfaces.sky) {
        if (Status s = needsDepth("--sky", out); !s) return s;
        if (Status s = drawSky(*surfaces.sky, rig, out.color, out.depth); !s) return s;
    }
    if (surfaces.angularAA > 0.0f && !(surfaces.angularAAOptional && out.depth.empty())) {
        if (Status s = needsDepth("--angular-aa", out); !s) return s;
        if (Status s = applyAngularAA(rig, out.color, out.depth, surfaces.angularAA,
                                       surfaces.angularAAShears);
            !s)
            return s;
    }
    if (!surfaces.labels.empty()) {
        if (Status s = drawLabels(rig, surfaces.labels, out.color, out.depth); !s) return s;
    }
    if (surfaces.letterboxPercent > 0.0f) {
        if (Status s = needsDepth("--letterbox", out); !s) return s;
        if (Status s = drawLetterbox(rig, out.color, out.depth, surfaces.letterboxPercent); !s)
            return s;
    }
    if (surfaces.floatingWindow) {
        if (Status s = needsDepth("--floating-window", out); !s) return s;
        auto applied = applyFloatingWindow(rig, out.color, out.depth);
        if (!applied) return applied.status();
        strips = std::move(*applied);
    }
    return strips;
}

}  // namespace mvr
