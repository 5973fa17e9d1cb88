#include "mvr/composite/lenticular.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <optional>

#include <fmt/core.h>

#include "mvr/composite/jpeg.h"
#include "mvr/composite/layout.h"

namespace mvr::composite {
namespace {

std::size_t skipSpace(std::string_view s, std::size_t at) {
    while (at < s.size() && (s[at] == ' ' || s[at] == '\t' || s[at] == '\n' || s[at] == '\r')) ++at;
    return at;
}

// Position just after `"key"` followed by ':' (a JSON key, not a string value), or npos.
std::size_t findKey(std::string_view json, std::string_view key, std::size_t from, std::size_t to) {
    std::string quoted(1, '"');  // (not "\"" + key + "\"": GCC 12 -Wrestrict false positive)
    quoted.append(key);
    quoted.push_back('"');
    for (std::size_t at = json.find(quoted, from); at != std::string_view::npos && at < to;
         at = json.find(quoted, at + 1)) {
        const std::size_t colon = skipSpace(json, at + quoted.size());
        if (colon < json.size() && json[colon] == ':') return colon + 1;
    }
    return std::string_view::npos;
}

// A number (or true / false) at `at`.
std::optional<double> parseScalar(std::string_view json, std::size_t at) {
    at = skipSpace(json, at);
    if (json.substr(at, 4) == "true") return 1.0;
    if (json.substr(at, 5) == "false") return 0.0;
    const std::size_t end = json.find_first_of(",}] \t\r\n", at);
    const std::string text(json.substr(at, end == std::string_view::npos ? json.npos : end - at));
    if (text.empty()) return std::nullopt;
    char* stop = nullptr;
    const double v = std::strtod(text.c_str(), &stop);
    if (stop != text.c_str() + text.size() || !std::isfinite(v)) return std::nullopt;
    return v;
}

// The value of top-level-ish key `key`: {"value": x} or x. nullopt when absent; error text when
// present but not a number.
std::optional<double> calibrationValue(std::string_view json, std::string_view key, bool& bad) {
    std::size_t at = findKey(json, key, 0, json.size());
    if (at == std::string_view::npos) return std::nullopt;
    at = skipSpace(json, at);
    if (at < json.size() && json[at] == '{') {
        const std::size_t close = json.find('}', at);
        const std::size_t v = findKey(json, "value", at, close);
        if (v == std::string_view::npos) {
            bad = true;
            return std::nullopt;
        }
        at = v;
    }
    std::optional<double> value = parseScalar(json, at);
    if (!value) bad = true;
    return value;
}

// Structure check before reading values: one object, balanced braces/brackets outside strings,
// strings closed. Catches truncated files, whose last number could otherwise be cut short.
bool wellFormedObject(std::string_view json) {
    const std::size_t first = skipSpace(json, 0);
    if (first >= json.size() || json[first] != '{') return false;
    int depth = 0;
    bool inString = false;
    std::size_t end = first;
    for (std::size_t i = first; i < json.size(); ++i) {
        const char c = json[i];
        if (inString) {
            if (c == '\\')
                ++i;
            else if (c == '"')
                inString = false;
            continue;
        }
        if (c == '"')
            inString = true;
        else if (c == '{' || c == '[')
            ++depth;
        else if (c == '}' || c == ']') {
            if (--depth < 0) return false;
            if (depth == 0) {
                end = i;
                break;
            }
        }
    }
    return depth == 0 && !inString && end > first && skipSpace(json, end + 1) == json.size();
}

}  // namespace

Result<LenticularCalibration> parseLookingGlassCalibration(std::string_view json,
                                                           const std::string& what) {
    if (!wellFormedObject(json))
        return inputError(
            fmt::format("{}: not a complete JSON object (truncated or malformed "
                        "calibration file)",
                        what));
    LenticularCalibration cal;
    struct Field {
        const char* key;
        bool required;
        double* number;
        int* integer;
        bool* flag;
    } fields[] = {
        {"pitch", true, &cal.pitch, nullptr, nullptr},
        {"slope", true, &cal.slope, nullptr, nullptr},
        {"center", true, &cal.center, nullptr, nullptr},
        {"DPI", true, &cal.dpi, nullptr, nullptr},
        {"screenW", false, nullptr, &cal.screenWidth, nullptr},
        {"screenH", false, nullptr, &cal.screenHeight, nullptr},
        {"invView", false, nullptr, nullptr, &cal.invertViews},
        {"flipImageX", false, nullptr, nullptr, &cal.flipX},
        {"flipImageY", false, nullptr, nullptr, &cal.flipY},
        {"flipSubp", false, nullptr, nullptr, &cal.bgr},
        {"viewCone", false, &cal.viewCone, nullptr, nullptr},
    };
    for (const Field& f : fields) {
        bool bad = false;
        const std::optional<double> v = calibrationValue(json, f.key, bad);
        if (bad)
            return inputError(
                fmt::format("{}: calibration key \"{}\" is not a number", what, f.key));
        if (!v) {
            if (f.required)
                return inputError(
                    fmt::format("{}: calibration key \"{}\" missing (expected a "
                                "Looking Glass visual.json with pitch, slope, "
                                "center and DPI)",
                                what, f.key));
            continue;
        }
        if (f.number) *f.number = *v;
        if (f.flag) *f.flag = *v != 0.0;
        if (f.integer) {
            if (*v < 0 || *v > 16384 || *v != std::floor(*v))
                return inputError(
                    fmt::format("{}: calibration {} = {} (expected a whole number "
                                "of pixels, 0..16384)",
                                what, f.key, *v));
            *f.integer = static_cast<int>(*v);
        }
    }
    if (cal.viewCone != 0.0 && !(cal.viewCone > 0.0 && cal.viewCone < 180.0))
        return inputError(
            fmt::format("{}: calibration viewCone = {} (expected degrees, 0 < cone < 180)", what,
                        cal.viewCone));
    if (!(cal.pitch > 0 && cal.pitch <= kMaxLenticularPitch))
        return inputError(fmt::format("{}: calibration pitch {} is out of range (must be > 0 and "
                                      "at most {:g} lenticules per inch)",
                                      what, cal.pitch, kMaxLenticularPitch));
    if (!(std::abs(cal.slope) >= kMinLenticularSlope && std::abs(cal.slope) <= kMaxLenticularSlope))
        return inputError(fmt::format("{}: calibration slope {} is out of range (must be non-zero, "
                                      "{:g} <= |slope| <= {:g})",
                                      what, cal.slope, kMinLenticularSlope, kMaxLenticularSlope));
    if (!(std::abs(cal.center) <= kMaxLenticularCenter))
        return inputError(fmt::format("{}: calibration center {} is out of range (must be "
                                      "-{:g}..{:g} lenticules)",
                                      what, cal.center, kMaxLenticularCenter, kMaxLenticularCenter));
    if (!(cal.dpi > 0 && cal.dpi <= kMaxLenticularDpi))
        return inputError(fmt::format("{}: calibration DPI {} is out of range (must be > 0 and at "
                                      "most {:g})",
                                      what, cal.dpi, kMaxLenticularDpi));
    return cal;
}

Result<LenticularCalibration> readLookingGlassCalibration(const std::filesystem::path& path) {
    Result<std::vector<std::uint8_t>> bytes = readFileBytes(path);
    if (!bytes) return bytes.status();
    const std::string_view json(reinterpret_cast<const char*>(bytes->data()), bytes->size());
    return parseLookingGlassCalibration(json, path.string());
}

Result<LenticularShaderParams> lenticularShaderParams(const LenticularCalibration& cal,
                                                      int screenWidth, int screenHeight) {
    const char* who = "mvr::composite::lenticular()";
    if (!std::isfinite(cal.pitch) || !std::isfinite(cal.slope) || !std::isfinite(cal.center) ||
        !std::isfinite(cal.dpi))
        return usageError(
            fmt::format("{}: calibration has a non-finite value (pitch {}, slope "
                        "{}, center {}, dpi {})",
                        who, cal.pitch, cal.slope, cal.center, cal.dpi));
    if (cal.dpi <= 0 || cal.dpi > kMaxLenticularDpi)
        return usageError(fmt::format("{}: dpi {} (must be > 0 and at most {:g})", who, cal.dpi,
                                      kMaxLenticularDpi));
    if (std::abs(cal.slope) < kMinLenticularSlope || std::abs(cal.slope) > kMaxLenticularSlope)
        return usageError(fmt::format("{}: slope {} (must be non-zero, {:g} <= |slope| <= {:g})",
                                      who, cal.slope, kMinLenticularSlope, kMaxLenticularSlope));
    if (cal.pitch <= 0 || cal.pitch > kMaxLenticularPitch)
        return usageError(fmt::format("{}: pitch {} (must be > 0 and at most {:g} lenticules per "
                                      "inch)",
                                      who, cal.pitch, kMaxLenticularPitch));
    if (std::abs(cal.center) > kMaxLenticularCenter)
        return usageError(fmt::format("{}: center {} (must be -{:g}..{:g} lenticules)", who,
                                      cal.center, kMaxLenticularCenter, kMaxLenticularCenter));
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

namespace {

/// std::floor, without a libm call below 2^52 (where every double's floor is its truncation,
/// less one for a negative non-integer): the compose runs it twice a sub-pixel.
inline double floorExact(double x) {
    if (!(std::abs(x) < 4503599627370496.0)) return std::floor(x);  // 2^52; NaN, infinities
    const double t = static_cast<double>(static_cast<std::int64_t>(x));
    return t > x ? t - 1.0 : t;
}

/// The view of sub-pixel `subpixel` at u, with v·tilt given: lenticularView()'s formula.
inline int viewAt(const LenticularShaderParams& p, int viewCount, double u, double vTilt,
                  int subpixel) {
    double z = (u + subpixel * p.subp + vTilt) * p.pitchU - p.center;
    z -= floorExact(z);
    if (p.invertViews) z = 1.0 - z;
    const int view = static_cast<int>(floorExact(z * viewCount));
    return std::clamp(view, 0, viewCount - 1);
}

}  // namespace

int lenticularView(const LenticularShaderParams& p, int viewCount, int screenWidth,
                   int screenHeight, int px, int py, int subpixel) {
    const double u = (px + 0.5) / screenWidth;
    const double v = 1.0 - (py + 0.5) / screenHeight;
    return viewAt(p, viewCount, u, v * p.tilt, subpixel);
}

Result<LenticularLayout> lenticularLayout(const LenticularCalibration& cal, int viewCount,
                                          int viewWidth, int viewHeight) {
    if (viewCount < 1 || viewCount > (1 << 20) || viewWidth < 1 || viewHeight < 1 ||
        viewWidth > 16384 || viewHeight > 16384)
        return usageError(fmt::format("mvr::composite::lenticularLayout(): {} views of {}x{} "
                                      "(expected 1..2^20 views of 1..16384 on each side)",
                                      viewCount, viewWidth, viewHeight));
    const int sw = cal.screenWidth > 0 ? cal.screenWidth : viewWidth;
    const int sh = cal.screenHeight > 0 ? cal.screenHeight : viewHeight;
    Result<LenticularShaderParams> params = lenticularShaderParams(cal, sw, sh);
    if (!params) return params.status();
    LenticularLayout l;
    l.params = *params;
    l.views = viewCount;
    l.viewWidth = viewWidth, l.viewHeight = viewHeight;
    l.screenWidth = sw, l.screenHeight = sh;
    // Nearest view pixel of (u, v); the lookup is mirrored for a flipped panel.
    l.sourceColumn.resize(std::size_t(sw));
    for (int px = 0; px < sw; ++px) {
        const int vx0 = std::min(viewWidth - 1, static_cast<int>((px + 0.5) * viewWidth / sw));
        l.sourceColumn[std::size_t(px)] = cal.flipX ? viewWidth - 1 - vx0 : vx0;
    }
    l.columnU.resize(std::size_t(sw));
    for (int px = 0; px < sw; ++px) l.columnU[std::size_t(px)] = (px + 0.5) / sw;
    // |z| <= (|u| + 2 subp + |v tilt|) |pitchU| + |center| with u, v in [0, 1].
    const LenticularShaderParams& p = l.params;
    const double bound =
        (1.0 + 2.0 * std::abs(p.subp) + std::abs(p.tilt)) * std::abs(p.pitchU) + std::abs(p.center);
    // The rounding constant needs each add and subtract rounded to double (no x87 excess
    // precision, no -ffast-math reassociation): elsewhere std::floor's path.
#if defined(__FAST_MATH__) || !defined(FLT_EVAL_METHOD) || FLT_EVAL_METHOD != 0
    l.smallPhases = false;
    (void)bound;
#else
    l.smallPhases = bound < 1125899906842624.0;  // 2^50
#endif
    l.sourceRow.resize(std::size_t(sh));
    for (int py = 0; py < sh; ++py) {
        const int vy0 = std::min(viewHeight - 1, static_cast<int>((py + 0.5) * viewHeight / sh));
        l.sourceRow[std::size_t(py)] = cal.flipY ? viewHeight - 1 - vy0 : vy0;
    }
    return l;
}

namespace {

/// floor(x) for |x| < 2^51 by rounding to an integer with 1.5 · 2^52 (round to nearest, then one
/// less where that is above x): exact.
inline double floorSmall(double x) {
    constexpr double kRound = 6755399441055744.0;  // 1.5 * 2^52
    const double t = (x + kRound) - kRound;
    return t > x ? t - 1.0 : t;
}

/// The views of sub-pixel `subpixel` of `count` pixels from column px0: viewAt()'s formula with
/// u read from the layout and the floors by floorSmall() (no libm, no int64 conversion).
void smallPhaseViews(const LenticularLayout& l, int px0, int count, double vTilt, int subpixel,
                     int* views) {
    const LenticularShaderParams& p = l.params;
    const double* u = l.columnU.data() + px0;
    const double s = subpixel * p.subp, pitchU = p.pitchU, center = p.center;
    const double n = l.views, last = l.views - 1;
    const bool invert = p.invertViews;
    for (int k = 0; k < count; ++k) {
        double z = (u[k] + s + vTilt) * pitchU - center;
        z -= floorSmall(z);
        if (invert) z = 1.0 - z;
        double f = floorSmall(z * n);
        f = f < 0.0 ? 0.0 : f;
        f = f > last ? last : f;
        views[k] = static_cast<int>(f);
    }
}

}  // namespace

void lenticularRow(const LenticularLayout& l, int py, const std::uint8_t* const* viewRows,
                   std::uint8_t* d) {
    const LenticularShaderParams& p = l.params;
    const int n = l.views, sw = l.screenWidth, sh = l.screenHeight;
    const double v = 1.0 - (py + 0.5) / sh, vTilt = v * p.tilt;  // as lenticularView()
    constexpr int kChunk = 64;
    int viewR[kChunk], viewG[kChunk], viewB[kChunk];
    for (int px0 = 0; px0 < sw; px0 += kChunk) {
        const int count = std::min(kChunk, sw - px0);
        if (l.smallPhases) {
            smallPhaseViews(l, px0, count, vTilt, p.ri, viewR);
            smallPhaseViews(l, px0, count, vTilt, 1, viewG);
            smallPhaseViews(l, px0, count, vTilt, p.bi, viewB);
        } else {
            for (int k = 0; k < count; ++k) {
                const double u = l.columnU[std::size_t(px0 + k)];
                viewR[k] = viewAt(p, n, u, vTilt, p.ri);
                viewG[k] = viewAt(p, n, u, vTilt, 1);
                viewB[k] = viewAt(p, n, u, vTilt, p.bi);
            }
        }
        for (int k = 0; k < count; ++k) {
            const int px = px0 + k;
            const std::size_t at = std::size_t(l.sourceColumn[std::size_t(px)]) * 4;
            d[px * 4 + 0] = viewRows[viewR[k]][at + 0];
            d[px * 4 + 1] = viewRows[viewG[k]][at + 1];
            d[px * 4 + 2] = viewRows[viewB[k]][at + 2];
            d[px * 4 + 3] = 255;
        }
    }
}

Result<Image> lenticular(std::span<const Image> views, const LenticularCalibration& cal) {
    if (Status s = validateViews(views, 2, 1 << 20, "mvr::composite::lenticular()"); !s) return s;
    Result<LenticularLayout> layout =
        lenticularLayout(cal, int(views.size()), views[0].width, views[0].height);
    if (!layout) return layout.status();
    const LenticularLayout& l = *layout;
    Image out(l.screenWidth, l.screenHeight);
    std::vector<const std::uint8_t*> rows(views.size());
    for (int py = 0; py < l.screenHeight; ++py) {
        const std::size_t row = std::size_t(l.sourceRow[std::size_t(py)]) * l.viewWidth * 4;
        for (std::size_t v = 0; v < views.size(); ++v) rows[v] = views[v].rgba.data() + row;
        lenticularRow(l, py, rows.data(), out.row(py));
    }
    return out;
}

}  // namespace mvr::composite
