// src/session/render.cpp — renderStill(): `mvr render` of a recipe in one call
// (mvr/session/render.h).
#include "mvr/session/render.h"

#include <fmt/core.h>

#include "mvr/backends.h"
#include "mvr/session/outputs.h"
#include "mvr/session/sequence.h"
#include "mvr/session/surfaces.h"

namespace mvr::session {

Result<Rendered> renderStill(const RenderRecipe& recipe, const WarningSink& warn) {
    if (Status s = checkSequence(recipe.sequence); !s) return s;
    if (recipe.sequence.active())
        return usageError("renderStill: the recipe is a sequence (see mvr/session/sequence.h)");
    auto prepared = prepare(recipe, warn);
    if (!prepared) return prepared.status();
    Rendered r;
    r.prepared = std::move(prepared).value();
    const Prepared& p = r.prepared;
    r.notes = p.notes;
    r.backend = recipe.backend.empty() ? backendNames().front() : recipe.backend;
    auto backend = makeBackend(r.backend);
    if (!backend) {
        return Status(backend.status().code(),
                      fmt::format("--backend {}: {}", r.backend, backend.status().message()));
    }
    const std::string method = recipe.method.empty() ? (*backend)->defaultMethod() : recipe.method;
    if (Status s = (*backend)->supports(method); !s)
        return Status(s.code(), fmt::format("--method {}: {}", method, s.message()));
    auto surfaces = buildSurfaces(recipe, p);
    if (!surfaces) return surfaces.status();
    auto out = renderViews(**backend, p, p.scene, p.rig, p.settings, method);
    if (!out) return out.status();
    if (Status s = applySurfaces(*surfaces, p.rig, *out); !s) return s;
    if (int(out->color.size()) != p.rig.viewCount()) {
        return internalError(fmt::format("backend returned {} images for {} views",
                                         out->color.size(), p.rig.viewCount()));
    }
    r.output = std::move(out).value();
    r.comfort = comfortReport(p.rig, r.output);
    r.screen = screenComfortReport(p, r.comfort);
    for (std::string& w : renderWarnings(p, r.output, r.comfort, r.screen))
        r.notes.push_back(std::move(w));
    // The images and the report are one set: all of it is written, or none (issue 44).
    std::vector<ExtraFile> extra;
    if (!recipe.outputs.reportJson.empty()) {
        extra.push_back({recipe.outputs.reportJson, comfortJson(p, r.comfort, r.screen),
                         "--report-json"});
    }
    if (!recipe.outputs.directory.empty() || !extra.empty()) {
        const std::string dir =
            recipe.outputs.directory.empty() ? std::string(".") : recipe.outputs.directory;
        FrameOutputs outputs = frameOutputs(p);
        if (recipe.outputs.directory.empty())  // the report alone
            outputs.views = outputs.composites = outputs.depth = outputs.cameras = false;
        auto written = writeOutputs(dir, r.output, p.rig, outputs, backend->get(), {}, extra);
        if (!written) return written.status();
        r.files = std::move(written->paths);
    }
    return r;
}

}  // namespace mvr::session
