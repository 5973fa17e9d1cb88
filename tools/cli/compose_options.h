// tools/cli/compose_options.h — the command-line options of the composite formats
// (mvr::composite::ComposeOptions), shared by `mvr render` and `mvr compose`.
#pragma once

#include <CLI/CLI.hpp>

#include "mvr/composite/compose.h"

namespace mvr::cli {

/// Adds the composite options to a CLI11 subcommand; they write into `options`, which must
/// outlive parsing: --swap-eyes, --cross-eyed, --quilt CxR, --jpeg-quality Q,
/// --base-viewpoint K, --lenticular-calibration visual.json (read while parsing: a bad file is
/// a usage error, exit 1), --lenticular-pitch/-slope/-center/-dpi, --lenticular-screen WxH,
/// --lenticular-bgr, --lenticular-invert-views, --lenticular-flip-x, --lenticular-flip-y, and
/// with `withStereoMetadata` (for `mvr compose`, which has no rig) --baseline M and
/// --convergence D. Bad values are CLI11 validation errors (usage, exit 1).
void addComposeOptions(CLI::App* app, composite::ComposeOptions& options,
                       bool withStereoMetadata = false);

}  // namespace mvr::cli
