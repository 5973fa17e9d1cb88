// mvr/session/render.h — `mvr render` of a recipe in one call (library mvr::session): prepare(),
// the recipe's backend and method, the surfaces, the render, the files of writeOutputs() and
// the report JSON when the recipe names them, and the reports `mvr render` prints.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "mvr/core/render.h"
#include "mvr/core/status.h"
#include "mvr/session/prepare.h"
#include "mvr/session/recipe.h"

namespace mvr::session {

/// A still rendered from a recipe.
struct Rendered {
    Prepared prepared;
    RenderOutput output;  ///< the views (surfaces drawn), rig order
    std::string backend;  ///< the backend's name
    std::optional<ComfortReport> comfort;
    std::optional<ScreenComfortReport> screen;
    /// prepare()'s notes and the warnings after the render ("note: ...", "warning: ...").
    std::vector<std::string> notes;
    std::vector<std::string> files;  ///< written (outputs.directory, outputs.reportJson)
};

/// Renders a recipe's still as `mvr render` does, with its checks and messages (a sequence
/// recipe is refused: see mvr/session/sequence.h). `warn`: as prepare()'s.
Result<Rendered> renderStill(const RenderRecipe& recipe, const WarningSink& warn = {});

}  // namespace mvr::session
