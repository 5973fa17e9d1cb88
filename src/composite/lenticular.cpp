#include "mvr/composite/lenticular.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <fmt/core.h>

#include "mvr/composite/layout.h"

namespace mvr::composite {

Result<LenticularShaderParams> lenticularShaderParams(const LenticularCalibration& cal,
                                                      int screenWidth, int screenHeight) {
    const char* who = "mvr::composite::lenticular()";
    if (!std::isfinite(cal.pitch) || !std::isfinite(cal.slope) || !std::isfinite(cal.center) ||
        !std::isfinite(cal.dpi))
        return usageError(fmt::format("{}: calibration has a non-finite value (pitch {}, slope "
                                      "{}, center {}, dpi {})",
                                      who, cal.pitch, cal.slope, cal.center, cal.dpi));
    if (cal.dpi <= 0)
        return usageError(fmt::format("{}: dpi {} (expected > 0)", who, cal.dpi));
    if (cal.slope == 0)
        return usageError(fmt::format("{}: slope 0 (expected a non-zero lens slope)", who));
    if (cal.pitch <= 0)
        return usageError(fmt::format("{}: pitch {} (expected > 0 lenticules per inch)", who,
                                      cal.pitch));
    if (screenWidth < 1 || screenHeight < 1 || screenWidth > 16384 || screenHeight > 16384)
        return usageError(fmt::format("{}: screen {}x{} (expected 1..16384 on each side)", who,
                                      screenWidth, screenHeight));
    LenticularShaderParams p;
    const double screenInches = screenWidth / cal.dpi;
    p.pitchU = cal.pitch * screenInches * std::cos(std::atan(1.0 / cal.slope));
    p.tilt = screenHeight / (screenWidth * cal.slope) * (cal.flipX ? -1.0 : 1.0);
    p.subp = 1.0 / (3.0 * screenWidth);
    p.center = cal.center;
    p.ri = cal.bgr ? 2 : 0;
    p.bi = cal.bgr ? 0 : 2;
    p.invertViews = cal.invertViews;
    return p;
}

int lenticularView(const LenticularShaderParams& p, int viewCount, int screenWidth,
                   int screenHeight, int px, int py, int subpixel) {
    const double u = (px + 0.5) / screenWidth;
    const double v = 1.0 - (py + 0.5) / screenHeight;
    double z = (u + subpixel * p.subp + v * p.tilt) * p.pitchU - p.center;
    z -= std::floor(z);
    if (p.invertViews) z = 1.0 - z;
    const int view = static_cast<int>(std::floor(z * viewCount));
    return std::clamp(view, 0, viewCount - 1);
}

Result<Image> lenticular(std::span<const Image> views, const LenticularCalibration& cal) {
    if (Status s = validateViews(views, 2, 1 << 20, "mvr::composite::lenticular()"); !s) return s;
    const int vw = views[0].width, vh = views[0].height;
    const int sw = cal.screenWidth > 0 ? cal.screenWidth : vw;
    const int sh = cal.screenHeight > 0 ? cal.screenHeight : vh;
    Result<LenticularShaderParams> params = lenticularShaderParams(cal, sw, sh);
    if (!params) return params.status();
    const LenticularShaderParams& p = *params;
    const int n = static_cast<int>(views.size());
    Image out(sw, sh);
    for (int py = 0; py < sh; ++py) {
        // Nearest view pixel of (u, v); the lookup is mirrored for a flipped panel.
        const int vy0 = std::min(vh - 1, static_cast<int>((py + 0.5) * vh / sh));
        const int vy = cal.flipY ? vh - 1 - vy0 : vy0;
        std::uint8_t* d = out.row(py);
        for (int px = 0; px < sw; ++px) {
            const int vx0 = std::min(vw - 1, static_cast<int>((px + 0.5) * vw / sw));
            const int vx = cal.flipX ? vw - 1 - vx0 : vx0;
            const std::size_t at = (static_cast<std::size_t>(vy) * vw + vx) * 4;
            const int viewR = lenticularView(p, n, sw, sh, px, py, p.ri);
            const int viewG = lenticularView(p, n, sw, sh, px, py, 1);
            const int viewB = lenticularView(p, n, sw, sh, px, py, p.bi);
            d[px * 4 + 0] = views[viewR].rgba[at + 0];
            d[px * 4 + 1] = views[viewG].rgba[at + 1];
            d[px * 4 + 2] = views[viewB].rgba[at + 2];
            d[px * 4 + 3] = 255;
        }
    }
    return out;
}

}  // namespace mvr::composite
