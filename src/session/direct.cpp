// src/session/direct.cpp — direct lenticular rendering (mvr/session/direct.h).
#include "mvr/session/direct.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include <fmt/format.h>

#include "mvr/composite/lenticular.h"
#include "mvr/core/antialias.h"
#include "mvr/raster/soft_backend.h"
#include "mvr/session/outputs.h"

namespace mvr::session {
namespace {

/// Composes the panel rows whose source rows a band finished, into `panel` (one image per
/// sample pass). Bands are disjoint, so concurrent calls write disjoint panel rows.
class PanelSink final : public raster::ViewRowSink {
public:
    PanelSink(const composite::LenticularLayout& layout, Image& panel)
        : mLayout(layout), mPanel(panel) {
        // The panel rows of each view row: one contiguous run (the nearest-row lookup is
        // monotone, mirrored by flipY).
        mFirst.assign(std::size_t(layout.viewHeight), 0);
        mCount.assign(std::size_t(layout.viewHeight), 0);
        for (int py = 0; py < layout.screenHeight; ++py) {
            const std::size_t r = std::size_t(layout.sourceRow[std::size_t(py)]);
            if (mCount[r]++ == 0 || py < mFirst[r]) mFirst[r] = py;
        }
    }

    void rows(const raster::ViewRows& rows) override {
        std::array<const std::uint8_t*, kMaxViews> viewRows{};
        for (int r = rows.firstRow; r <= rows.lastRow; ++r) {
            for (int v = 0; v < mLayout.views; ++v) viewRows[std::size_t(v)] = rows.row(v, r);
            const int first = mFirst[std::size_t(r)], count = mCount[std::size_t(r)];
            for (int py = first; py < first + count; ++py)
                composite::lenticularRow(mLayout, py, viewRows.data(), mPanel.row(py));
        }
    }

private:
    const composite::LenticularLayout& mLayout;
    Image& mPanel;
    std::vector<int> mFirst, mCount;
};

}  // namespace

Status checkDirect(const Prepared& p, const FrameOutputs& outputs, const StereoSurfaces& surfaces,
                   Backend& backend, const std::string& backendName, const std::string& method,
                   std::vector<std::string>* notes) {
    const bool lenticular =
        std::find(outputs.formats.begin(), outputs.formats.end(), "lenticular") !=
        outputs.formats.end();
    if (!lenticular || !outputs.composites)
        return usageError(
            "--direct: renders the lenticular panel image; give --format lenticular (with "
            "--lenticular-calibration or a display preset's calibration)");
    if (outputs.formats.size() > 1) {
        std::vector<std::string> others;
        for (const std::string& f : outputs.formats)
            if (f != "lenticular") others.push_back(f);
        return usageError(fmt::format(
            "--direct: writes the lenticular image alone, and --format also asks for {} (give "
            "--format lenticular only, or leave --direct out)",
            fmt::join(others, ",")));
    }
    if (outputs.views || outputs.depth || outputs.cameras)
        return usageError(fmt::format(
            "--direct: keeps no view, so it cannot write {} (give --write composites, or leave "
            "--direct out)",
            outputs.views ? "view-N.png" : outputs.depth ? "depth-N.png" : "cameras.json"));
    if (!dynamic_cast<raster::RowStreamingBackend*>(&backend) || method != "unified")
        return unsupportedError(fmt::format(
            "--direct: {}:{} renders whole views; the panel is composed from the views' rows by "
            "soft:unified (--backend soft --method unified)",
            backendName, method));
    if (p.rig.viewCount() < 2)
        return usageError("--direct: a lenticular panel needs 2 or more views");
    if (p.synthesize > 1)
        return usageError(fmt::format(
            "--direct: --synthesize {} warps whole views; leave one of them out", p.synthesize));
    if (surfaces.sky) return usageError("--direct: --sky is drawn over whole views; leave one out");
    if (surfaces.floatingWindow || surfaces.letterboxPercent > 0.0f || !surfaces.labels.empty())
        return usageError(
            "--direct: --floating-window, --letterbox and --label are drawn over whole views; "
            "leave them or --direct out");
    if (surfaces.angularAA > 0.0f) {
        if (!surfaces.angularAAOptional)
            return usageError(
                "--direct: --angular-aa filters whole views by their depth; give --angular-aa "
                "off, or leave --direct out");
        if (notes)
            notes->push_back(
                "note: --direct: angular anti-aliasing is off (it filters whole views; "
                "--angular-aa off says so)");
    }
    return {};
}

Result<Image> renderDirectLenticular(Backend& backend, const Scene& scene, const Rig& rig,
                                     const RenderSettings& settings, const std::string& method,
                                     const composite::LenticularCalibration& calibration) {
    auto* rows = dynamic_cast<raster::RowStreamingBackend*>(&backend);
    if (!rows)
        return unsupportedError(fmt::format(
            "--direct: the {} backend renders whole views (soft:unified streams their rows)",
            backend.name()));
    if (Status s = validateSettings(settings); !s) return s;
    Result<composite::LenticularLayout> layout =
        composite::lenticularLayout(calibration, rig.viewCount(), settings.width, settings.height);
    if (!layout) return layout.status();
    Image panel(layout->screenWidth, layout->screenHeight);
    RenderSettings one = settings;
    one.samples = 1;
    one.output = nullptr;
    one.depth = false;
    const int n = settings.samples;
    PanelSink sink(*layout, panel);  // each pass writes every panel row
    if (n == 1) {
        if (Status s = rows->renderRows(scene, rig, one, method, sink); !s) return s;
        return panel;
    }
    // Each sample's panel, summed, resolved as renderSampled() resolves the views: composing
    // picks one view's byte per sub-pixel, so it commutes with the per-byte sum and rounding.
    std::vector<std::uint16_t> sums(panel.rgba.size(), 0);
    for (int k = 0; k < n; ++k) {
        const Rig moved =
            offsetRig(rig, samplePositions(n)[std::size_t(k)], settings.width, settings.height);
        if (Status s = rows->renderRows(scene, moved, one, method, sink); !s) return s;
        accumulateSamples(panel.rgba.data(), sums.data(), sums.size());
    }
    resolveSampleSums(sums.data(), panel.rgba.data(), sums.size(), n);
    return panel;
}

Result<WrittenFrame> writeDirectPanel(const std::filesystem::path& dir, Image panel,
                                      const Rig& rig, const FrameOutputs& outputs,
                                      const Backend* backend, const std::string& method) {
    ComposedImages composed;
    composed.images.emplace_back("lenticular", std::move(panel));
    RenderOutput none;
    none.method = method;
    return writeOutputs(dir, none, rig, outputs, backend, {}, {}, &composed);
}

}  // namespace mvr::session
