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
    auto surfaces = buildSurfaces(recipe);
    if (!surfaces) return surfaces.status();
    auto out = (*backend)->render(p.scene, p.rig, p.settings, method);
    if (!out) return out.status();
    if (Status s = applySurfaces(*surfaces, p.rig, *out); !s) return s;
    if (int(out->color.size()) != p.rig.viewCount()) {
        return internalError(fmt::format("backend returned {} images for {} views",
                                         out->color.size(), p.rig.viewCount()));
    }
    r.output = std::move(out).value();
    if (!recipe.outputs.directory.empty()) {
        auto written = writeOutputs(recipe.outputs.directory, r.output, p.rig,
                                    frameOutputs(p), backend->get());
        if (!written) return written.status();
        r.files = std::move(written->paths);
    }
    r.comfort = comfortReport(p.rig, r.output);
    r.screen = screenComfortReport(p, r.comfort);
    for (std::string& w : renderWarnings(p, r.output, r.comfort, r.screen))
        r.notes.push_back(std::move(w));
    if (!recipe.outputs.reportJson.empty()) {
        if (!writeTextFile(recipe.outputs.reportJson, comfortJson(p, r.comfort, r.screen))) {
            return outputError(fmt::format("--report-json {}: cannot write the file",
                                           recipe.outputs.reportJson));
        }
        r.files.push_back(recipe.outputs.reportJson);
    }
    return r;
}

}  // namespace mvr::session
