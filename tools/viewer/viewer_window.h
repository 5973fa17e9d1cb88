// tools/viewer/viewer_window.h — between `mvr view`'s command (view_command.cpp) and its
// window (viewer.cpp).
#pragma once

#include <vector>

#include "input.h"
#include "mvr/session/prepare.h"
#include "mvr/session/recipe.h"
#include "viewer.h"

namespace mvr::viewer {

/// The recipe of the viewer's options: the scene options', a calibration's view cone, the
/// composite options (--quilt, --lenticular-calibration) and the backend.
session::RenderRecipe viewerRecipe(const ViewerOptions& options);

/// Opens the window on a prepared scene and runs it until it is closed (Viewer::run()).
int runViewerWindow(const ViewerOptions& options, session::Prepared prepared,
                    std::vector<ScriptStep> script);

}  // namespace mvr::viewer
