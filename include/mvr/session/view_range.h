// mvr/session/view_range.h — `mvr render --view-range A:B` (Python view_range=(A, B)): render
// only views A..B of the rig, for farms that split a quilt's views over machines (library
// mvr::session).
//
// A and B are view numbers as the whole render numbers them, both included (the files are
// view-A.png ... view-B.png, depth-A.png ... likewise), 0 <= A <= B < N. The rig is built
// whole (framing, --convergence auto / --separation auto, the view cone) and then cut down to
// the range, so every view's camera is the whole rig's and its pixels those of the whole
// render, byte for byte. What needs every view is refused (a composite: --format, --write
// composites; a sequence, which --frame-range and --shard split) or left out (a --display
// preset's quilt: the range writes its views instead; a pair's anaglyph.png). cameras.json and
// the comfort report cover the range: cameras.json numbers its views as the whole rig does and
// says "view_range": [A, B]; the report's outer views are A and B.
#pragma once

#include <string>
#include <utility>

#include "mvr/core/status.h"
#include "mvr/session/prepare.h"
#include "mvr/session/recipe.h"

namespace mvr::session {

/// Parses "A:B" for a rig of `viewCount` views. Errors (ErrorCode::Usage, one line naming
/// --view-range and the value): not two whole numbers "A:B", B < A, B >= viewCount.
Result<std::pair<int, int>> parseViewRange(const std::string& text, int viewCount);

/// Cuts prepared.rig down to recipe.viewRange (nothing when it is empty): views A..B, the row of
/// them as the rig's columns; prepared.viewRange says which; the writes and formats as the
/// header says. Errors (ErrorCode::Usage): parseViewRange()'s, a grid of views (--view-grid),
/// a sequence, a composite format or --write composites.
Status restrictToViewRange(const RenderRecipe& recipe, Prepared& prepared);

}  // namespace mvr::session
