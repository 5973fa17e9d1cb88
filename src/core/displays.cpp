#include "mvr/core/displays.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <fmt/core.h>
#include <glm/glm.hpp>

namespace mvr {

namespace {

constexpr std::string_view kLgQuilts =
    "Looking Glass, 'Quilts: Quilt Settings by Device' (docs.lookingglassfactory.com/keyconcepts/"
    "quilts)";

// Views, quilt C x R and total size, tile, picture aspect, cone, panel, format, source.
// Tiles are the quilt divided by its grid (rounded down); mvr's quilt is C·W × R·H.
constexpr DisplayPreset lightField(std::string_view name, std::string_view description, int cols,
                                   int rows, int views, int qw, int qh, float aspect, float cone,
                                   int pw, int ph, std::string_view source) {
    DisplayPreset d;
    d.name = name;
    d.description = description;
    d.views = views;
    d.quiltColumns = cols;
    d.quiltRows = rows;
    d.quiltWidth = qw;
    d.quiltHeight = qh;
    d.viewWidth = qw / cols;
    d.viewHeight = qh / rows;
    d.aspect = aspect;
    d.viewConeDegrees = cone;
    d.panelWidth = pw;
    d.panelHeight = ph;
    d.format = "quilt";
    d.source = source;
    return d;
}

constexpr DisplayPreset stereo(std::string_view name, std::string_view description, int vw, int vh,
                               float aspect, int pw, int ph, std::string_view format,
                               std::string_view source) {
    DisplayPreset d;
    d.name = name;
    d.description = description;
    d.views = 2;
    d.viewWidth = vw;
    d.viewHeight = vh;
    d.aspect = aspect;
    d.panelWidth = pw;
    d.panelHeight = ph;
    d.format = format;
    d.source = source;
    return d;
}

constexpr float k16x9 = 16.0f / 9.0f;

// An eye-tracked monitor: two 1920x1080 views side by side (the SR weaver's full-width
// side-by-side texture), the picture's mm from its diagonal at 16:9 unless the maker's figure
// is known (docs/displays.md).
constexpr DisplayPreset tracked(std::string_view name, std::string_view description, float wMm,
                                float hMm, std::string_view source, float tiltDegrees = 0.0f) {
    DisplayPreset d = stereo(name, description, 1920, 1080, wMm / hMm, 3840, 2160, "sbs", source);
    d.screenWidthMm = wMm;
    d.screenHeightMm = hMm;
    d.screenTiltDegrees = tiltDegrees;
    return d;
}

const std::array kPresets{
    // The 8.9"'s cone is the maker's 35 degrees (docs.lookingglassfactory.com/keyconcepts/camera:
    // "the digital view angle that we find that renders best is 35°"; docs/displays.md).
    lightField("lkg-8.9", "Looking Glass 8.9\" (first generation)", 5, 9, 45, 4096, 4096, 1.6f,
               35.0f, 2560, 1600, kLgQuilts),
    lightField("lkg-16", "Looking Glass 16\" (second generation)", 5, 9, 45, 4096, 4096, k16x9,
               40.0f, 3840, 2160, kLgQuilts),
    lightField("portrait", "Looking Glass Portrait", 8, 6, 48, 3360, 3360, 0.75f, 40.0f, 1536, 2048,
               kLgQuilts),
    lightField("go", "Looking Glass Go", 11, 6, 66, 4092, 4092, 0.5625f, 54.0f, 1440, 2560,
               kLgQuilts),
    lightField("lkg-16-spatial-portrait", "Looking Glass 16\" Spatial Display (portrait)", 11, 6,
               66, 5995, 6000, 0.5625f, 50.0f, 2160, 3840, kLgQuilts),
    lightField("lkg-16-spatial-landscape", "Looking Glass 16\" Spatial Display (landscape)", 7, 7,
               49, 5999, 5999, k16x9, 50.0f, 3840, 2160, kLgQuilts),
    lightField("lkg-32", "Looking Glass 32\" (second generation)", 5, 9, 45, 8192, 8192, k16x9,
               40.0f, 7680, 4320, kLgQuilts),
    lightField("lkg-65", "Looking Glass 65\"", 8, 9, 72, 8192, 8192, k16x9, 40.0f, 7680, 4320,
               kLgQuilts),
    stereo("3dtv", "3D TV, HDMI 1.4a frame packing 1080p (two 1920x1080 views)", 1920, 1080, k16x9,
           1920, 1080, "hdmi-frame-packing", "HDMI 1.4a 3D frame packing, 1920x2205"),
    stereo("sbs-half", "side-by-side half width: glasses-free 3D phone or a TV's SBS mode", 1920,
           1080, k16x9, 1920, 1080, "sbs-half", "half side by side, each view squeezed 2:1"),
    stereo("headset", "side-by-side headset (Cardboard-style: each eye sees one half)", 960, 1080,
           960.0f / 1080.0f, 1920, 1080, "sbs", "full side by side, one half per eye"),
    tracked("odyssey-3d", "Samsung Odyssey 3D 27\" (G90XF), eye-tracked: --rig screen, 597.7x336.2 mm",
            597.7f, 336.2f, "27-inch 16:9 4K panel (reviews); mm from the diagonal"),
    tracked("spatiallabs-view",
            "Acer SpatialLabs View 15.6\" (ASV15-1B), eye-tracked: --rig screen, 345.4x194.3 mm",
            345.4f, 194.3f, "15.6-inch 16:9 4K panel; mm from the diagonal"),
    tracked("sony-sr1",
            "Sony Spatial Reality Display ELF-SR1 15.6\", eye-tracked: --rig screen, 345.4x194.3 mm, "
            "45-degree tilt",
            345.4f, 194.3f, "Sony's SR white paper: 15.6-inch 4K, 45-degree stand", 45.0f),
    tracked("sony-sr2",
            "Sony Spatial Reality Display ELF-SR2 27\", eye-tracked: --rig screen, 596.7x335.7 mm, "
            "45-degree tilt",
            596.7f, 335.7f, "Sony's SR display plugin: 59.6736 x 33.5664 cm, 45-degree tilt", 45.0f),
    stereo("barrier", "two-view parallax barrier (column interleave, kalaiah2007 section 4)", 1920,
           1080, k16x9, 1920, 1080, "columns", "kalaiah2007 section 4: column interleave"),
};

}  // namespace

std::span<const DisplayPreset> displayPresets() { return kPresets; }

std::vector<std::string> displayNames() {
    std::vector<std::string> out;
    for (const DisplayPreset& d : kPresets) out.emplace_back(d.name);
    return out;
}

Result<DisplayPreset> findDisplay(std::string_view name) {
    for (const DisplayPreset& d : kPresets) {
        if (d.name == name) return d;
    }
    std::string names;
    for (const DisplayPreset& d : kPresets)
        names += (names.empty() ? "" : ", ") + std::string(d.name);
    return usageError(fmt::format("unknown display '{}' (expected one of: {})", name, names));
}

std::string aspectText(double aspect) {
    std::string s = fmt::format("{:.4f}", aspect);
    while (!s.empty() && s.back() == '0') s.pop_back();
    if (!s.empty() && s.back() == '.') s.pop_back();
    return s;
}

ParallaxBudget parallaxBudget(const ScreenGeometry& screen) {
    ParallaxBudget b;
    b.eyeSeparation = screen.widthCm > 0.0f ? screen.interocularCm / screen.widthCm : 0.0f;
    b.desktop = screen.viewingDistanceCm > 0.0f && screen.viewingDistanceCm < kDesktopDistanceCm;
    b.fraction = b.desktop ? 0.5f * b.eyeSeparation : b.eyeSeparation;
    return b;
}

float parallaxAtInfinity(const Rig& rig) {
    return rig.kind == RigKind::Parallel ? 0.0f : rig.separation();
}

float autoSeparation(const Rig& trial, float nearest, float farthest,
                     const ParallaxBudget& budget, float depthPercent) {
    if (trial.columns < 2 || !(trial.separation() > 0.0f)) return 0.0f;
    const ParallaxRange r = parallaxRange(trial, nearest, farthest);
    const float share = 1.0f / float(trial.columns - 1);  // adjacent views: the eyes' pair
    const float worst = std::max({std::abs(r.minParallax) * share,
                                  std::abs(r.maxParallax) * share, parallaxAtInfinity(trial)});
    if (!(worst > 0.0f) || !std::isfinite(worst)) return 0.0f;
    return trial.separation() * (depthPercent / 100.0f) * budget.fraction / worst;
}

int eyePairViews(const Rig& rig, float viewConeDegrees, const ScreenGeometry& screen) {
    const int n = rig.columns;
    if (n <= 2 || viewConeDegrees <= 0.0f || screen.viewingDistanceCm <= 0.0f) return 1;
    const float eyesDeg =
        glm::degrees(2.0f * std::atan(0.5f * screen.interocularCm / screen.viewingDistanceCm));
    const float stepDeg = viewConeDegrees / float(n - 1);
    return std::clamp(int(std::lround(eyesDeg / stepDeg)), 1, n - 1);
}

ScreenComfort screenComfort(const Rig& rig, const ParallaxRange& outer, int pairViews,
                            const ScreenGeometry& screen, float viewConeDegrees) {
    ScreenComfort c;
    c.screen = screen;
    c.budget = parallaxBudget(screen);
    c.pairViews = pairViews;
    const float share = rig.columns > 1 ? float(pairViews) / float(rig.columns - 1) : 0.0f;
    c.minParallax = outer.minParallax * share;
    c.maxParallax = outer.maxParallax * share;
    c.minParallaxCm = c.minParallax * screen.widthCm;
    c.maxParallaxCm = c.maxParallax * screen.widthCm;
    c.infinityParallax = float(pairViews) * parallaxAtInfinity(rig);
    c.infinityParallaxCm = c.infinityParallax * screen.widthCm;
    c.separationRule = (rig.kind == RigKind::OffAxis || rig.kind == RigKind::ToeIn) &&
                       !rig.screen && viewConeDegrees == 0.0f;
    const float nan = std::numeric_limits<float>::quiet_NaN();
    auto vergence = [&](float parallaxCm) {
        if (screen.viewingDistanceCm <= 0.0f) return nan;
        return glm::degrees(2.0f * std::atan((screen.interocularCm - parallaxCm) /
                                             (2.0f * screen.viewingDistanceCm)));
    };
    c.nearestVergenceDeg = vergence(c.minParallaxCm);
    c.farthestVergenceDeg = vergence(c.maxParallaxCm);
    c.screenVergenceDeg = vergence(0.0f);
    const float budgetCm = c.budget.fraction * screen.widthCm;
    const std::string budgetText = fmt::format(
        "the {:.2f} cm budget ({} eye separation, {:.1f} cm / {:.1f} cm screen)", budgetCm,
        c.budget.desktop ? "desktop: half the" : "the", screen.interocularCm, screen.widthCm);
    auto add = [&](const std::string& text) { c.why += (c.why.empty() ? "" : "; ") + text; };
    auto over = [](float value, float limit) { return value > limit * (1.0f + 1e-4f); };
    if (c.separationRule && over(c.infinityParallaxCm, budgetCm)) {
        add(fmt::format("separation {:.2f} cm (the parallax at infinity) exceeds {}{}",
                        c.infinityParallaxCm, budgetText,
                        over(c.infinityParallaxCm, screen.interocularCm)
                            ? ": beyond the scene the eyes diverge"
                            : ""));
    }
    if (over(c.maxParallaxCm, screen.interocularCm)) {
        add(
            fmt::format("parallax behind the screen {:.2f} cm exceeds the {:.1f} cm between the "
                        "eyes: they diverge",
                        c.maxParallaxCm, screen.interocularCm));
    } else if (over(c.maxParallaxCm, budgetCm)) {
        add(fmt::format("parallax behind the screen {:.2f} cm exceeds {}", c.maxParallaxCm,
                        budgetText));
    }
    if (over(-c.minParallaxCm, budgetCm)) {
        add(fmt::format("parallax out of the screen {:.2f} cm exceeds {}", c.minParallaxCm,
                        budgetText));
    }
    c.comfortable = c.why.empty();
    return c;
}

float balancedConvergence(float nearest, float farthest) {
    return 2.0f / (1.0f / nearest + 1.0f / farthest);
}

float distanceFromWindowDepth(float d, float near, float far) {
    const float z = 2.0f * d - 1.0f;
    return 2.0f * near * far / ((far + near) - z * (far - near));
}

std::optional<DepthPercentiles> depthPercentiles(std::span<const float> windowDepth, float near,
                                                 float far, float lowPercent, float highPercent) {
    // A histogram of window depths (1024 bins over [0, 1)): the percentiles are the bins'
    // upper edges, converted to distances (monotonic in the window depth).
    constexpr int kBins = 1024;
    std::array<long, kBins> bins{};
    DepthPercentiles out;
    float dMin = 1.0f, dMax = 0.0f;
    for (float d : windowDepth) {
        if (!(d < 1.0f) || !(d >= 0.0f)) continue;
        bins[std::min(kBins - 1, int(d * kBins))]++;
        dMin = std::min(dMin, d);
        dMax = std::max(dMax, d);
        ++out.pixels;
    }
    if (out.pixels == 0) return std::nullopt;
    auto percentile = [&](float percent, bool upperEdge) {
        const double want = double(out.pixels) * percent / 100.0;
        long seen = 0;
        for (int i = 0; i < kBins; ++i) {
            seen += bins[i];
            if (double(seen) >= want && seen > 0) return float(i + (upperEdge ? 1 : 0)) / kBins;
        }
        return 1.0f;
    };
    const float dLow = std::clamp(percentile(lowPercent, false), dMin, dMax);
    const float dHigh = std::clamp(percentile(highPercent, true), dMin, dMax);
    out.nearest = distanceFromWindowDepth(dLow, near, far);
    out.farthest = distanceFromWindowDepth(dHigh, near, far);
    out.minimum = distanceFromWindowDepth(dMin, near, far);
    out.maximum = distanceFromWindowDepth(dMax, near, far);
    return out;
}

}  // namespace mvr
