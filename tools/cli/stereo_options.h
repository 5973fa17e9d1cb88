// tools/cli/stereo_options.h — `mvr render`'s (and mvr.render()'s) stereo surfaces drawn after
// the scene: --sky, --floating-window, --letterbox, --label, --label-anchor
// (mvr/core/stereo_surfaces.h).
#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "mvr/core/render.h"
#include "mvr/core/rig.h"
#include "mvr/core/status.h"
#include "mvr/core/stereo_surfaces.h"
#include "mvr/session/surfaces.h"

namespace mvr::cli {

struct StereoSurfaceOptions {
    std::string sky;  ///< empty: none
    bool floatingWindow = false;
    double letterbox = 0.0;  ///< percent of the height per band; 0: none
    std::vector<std::string> labels, anchors;
    std::string angularAA = "auto";  ///< --angular-aa auto | off | S

    void addTo(CLI::App* app);
    /// The recipe of these options (session::buildSurfaces() parses it).
    session::SurfaceRecipe recipe() const {
        return {sky, floatingWindow, letterbox, labels, anchors, angularAA};
    }
    /// Parses the options (loads the sky map, parses the labels).
    Result<StereoSurfaces> build() const { return session::buildSurfaces(recipe()); }
};

using session::applySurfaces;

}  // namespace mvr::cli
