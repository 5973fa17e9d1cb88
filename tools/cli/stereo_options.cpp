#include "stereo_options.h"

#include <fmt/core.h>

#include "mvr/core/scene_io.h"

namespace mvr::cli {

void StereoSurfaceOptions::addTo(CLI::App* app) {
    app->add_option("--sky", sky,
                    "Sky at infinity behind everything, with each view's stereo projection "
                    "(parallax = the separation): 'gradient', or a PNG/JPEG map: equirectangular "
                    "(2:1, centre column looks down -Z) or a horizontal cube cross (4:3: "
                    "+Y above; -X -Z +X +Z; -Y below). Needs a depth buffer");
    app->add_flag("--floating-window", floatingWindow,
                  "Black out, per view, the strip at the left/right frame edge where an object "
                  "nearer than the screen is seen by one eye only (width from the rig and the "
                  "nearest such depth). Off-axis rigs; needs a depth buffer");
    app->add_option("--letterbox", letterbox,
                    "Two black bands, each this percentage of the height, at the convergence depth "
                    "(out-of-screen objects overdraw them). Needs a depth buffer");
    app->add_option("--label", labels,
                    "Text at a depth: 'TEXT@x,y[,distance]', x,y fractions of the view (0,0 = top "
                    "left), distance = eye-space distance (default: the convergence, on the "
                    "screen); parallax = separation x (1 - convergence/distance); repeatable")
        ->type_name("TEXT@x,y[,d]");
    app->add_option("--label-anchor", anchors,
                    "Text attached to a 3D anchor point: 'TEXT@X,Y,Z' (world units); repeatable")
        ->type_name("TEXT@X,Y,Z");
}

Result<StereoSurfaces> StereoSurfaceOptions::build() const {
    StereoSurfaces s;
    if (!sky.empty()) {
        auto loaded = loadSky(sky);
        if (!loaded) return loaded.status();
        s.sky = std::move(*loaded);
    }
    s.floatingWindow = floatingWindow;
    if (letterbox != 0.0) {
        if (!(letterbox > 0.0 && letterbox < 50.0))
            return usageError(
                fmt::format("--letterbox {}: must be in (0, 50) percent of the height", letterbox));
        s.letterboxPercent = float(letterbox);
    }
    for (const std::string& spec : labels) {
        auto l = parseLabel(spec, false);
        if (!l) return l.status();
        s.labels.push_back(std::move(*l));
    }
    for (const std::string& spec : anchors) {
        auto l = parseLabel(spec, true);
        if (!l) return l.status();
        s.labels.push_back(std::move(*l));
    }
    return s;
}

Status applySurfaces(const StereoSurfaces& surfaces, const Rig& rig, RenderOutput& out) {
    if (!surfaces.any()) return {};
    auto applied = applyStereoSurfaces(surfaces, rig, out);
    if (!applied) return applied.status();
    return {};
}

}  // namespace mvr::cli
