// mvr/session/direct.h — direct lenticular rendering (`mvr render --format lenticular --direct`,
// issue 43): the panel image composed from the views' rows as soft:unified finishes each band
// of them, so that no view image and no quilt is ever in memory. Same pixels, bit for bit, as
// rendering the views and composing them (composite::lenticular()): each panel row is
// composite::lenticularRow() of the rows it reads, only taken from the band scratch.
#pragma once

#include <filesystem>
#include <string>

#include "mvr/composite/compose.h"
#include "mvr/core/image.h"
#include "mvr/core/render.h"
#include "mvr/core/rig.h"
#include "mvr/core/scene.h"
#include "mvr/core/status.h"
#include "mvr/core/stereo_surfaces.h"
#include "mvr/session/outputs.h"
#include "mvr/session/prepare.h"

namespace mvr::session {

/// Whether a prepared render can go direct, before anything is rendered: only the lenticular
/// image is written (`--write composites` with `--format lenticular` alone, the default of a
/// display preset with a calibration), on soft:unified, a still, without --synthesize and
/// without a surface drawn over the views (sky, floating window, letterbox, labels, an explicit
/// --angular-aa; --angular-aa auto is left off, with a note in `notes`). Errors name --direct
/// and the option in the way (ErrorCode::Usage / Unsupported).
/// `outputs`: what the render writes (frameOutputs(prepared); Python's without output=
/// writes nothing).
Status checkDirect(const Prepared& prepared, const FrameOutputs& outputs,
                   const StereoSurfaces& surfaces, Backend& backend,
                   const std::string& backendName, const std::string& method,
                   std::vector<std::string>* notes = nullptr);

/// The panel image of `rig`'s views of `scene` on `calibration` (its screen size, 0: the view
/// size), rendered by `backend` (a RowStreamingBackend) with `method`. settings.samples > 1 sums
/// the samples' panel images and resolves them as renderSampled() resolves the views, so the
/// image is lenticular() of the anti-aliased views.
Result<Image> renderDirectLenticular(Backend& backend, const Scene& scene, const Rig& rig,
                                     const RenderSettings& settings, const std::string& method,
                                     const composite::LenticularCalibration& calibration);

/// Writes the panel as the frame's lenticular file into `dir`: writeOutputs() with the image
/// precomposed and no view (its staging, names and errors). `method` names the method rendered.
Result<WrittenFrame> writeDirectPanel(const std::filesystem::path& dir, Image panel,
                                      const Rig& rig, const FrameOutputs& outputs,
                                      const Backend* backend, const std::string& method);

}  // namespace mvr::session
