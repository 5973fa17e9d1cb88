#include "mvr/gl/gl_backend.h"

#include "mvr/core/antialias.h"
#include "mvr/core/shadows.h"
#include "renderer.h"

namespace mvr::gl {

namespace {

class GlBackend final : public mvr::Backend {
public:
    std::string name() const override { return "gl"; }
    std::vector<std::string> methods() const override { return detail::methodNames(); }
    std::string defaultMethod() const override { return detail::defaultMethod().name; }
    Status supports(const std::string& method) const override { return mRenderer.supports(method); }
    Result<RenderOutput> render(const Scene& scene, const Rig& rig, const RenderSettings& settings,
                                const std::string& method) override {
        return renderThroughInto(*this, scene, rig, settings, method);
    }
    // Frame after frame into one output: its images are reused (no allocation, no page
    // faults) where they have the request's size.
    Status renderInto(const Scene& scene, const Rig& rig, const RenderSettings& requested,
                      const std::string& method, RenderOutput& out) override {
        // --aa N: multisampled targets where the method and the driver take N samples (one
        // shading a pixel), else N sub-pixel passes.
        if (requested.samples > 1 && !mRenderer.multisamples(method, requested.samples))
            return renderSampled(*this, scene, rig, requested, method, out);
        const RenderSettings settings = shadedSettings(requested);
        if (!settings.shadows) return mRenderer.renderInto(scene, rig, settings, method, out);
        // Shadows (issue 15): the casters' maps once for all views, as one multi-view pass
        // whose views are the lights (the same method where it returns per-view depth).
        if (Status s = validateRequest(scene, rig, settings); !s) return s;
        if (Status s = mRenderer.supports(method); !s) return s;
        Result<ShadowSet> set = renderShadowSet(*this, scene, settings.shadowMapSize,
                                                mRenderer.shadowPassMethod(method));
        if (!set) return set.status();
        mRenderer.setShadows(&*set, scene.lights);
        const Status st = mRenderer.renderInto(scene, rig, settings, method, out);
        mRenderer.setShadows(nullptr);
        return st;
    }
    std::vector<std::string> info() const override { return mRenderer.info(); }

    std::optional<RenderStats> lastStats() const override {
        const auto& gl = mRenderer.lastStats();
        if (!gl) return std::nullopt;
        RenderStats s;
        s.method = gl->method;
        s.gpuMs = gl->gpuMs;
        s.drawWallMs = gl->drawWallMs;
        s.readbackWallMs = gl->readbackWallMs;
        s.totalWallMs = gl->totalWallMs;
        s.passes = gl->passes;
        s.samples = gl->samples;
        return s;
    }

private:
    // Lazily creates its context from const queries (supports(), info()).
    mutable detail::Renderer mRenderer;
};

}  // namespace

std::unique_ptr<mvr::Backend> makeGlBackend() { return std::make_unique<GlBackend>(); }

const std::vector<std::string>& glMethodNames() { return detail::methodNames(); }

std::optional<GlFrameStats> lastFrameStats(const mvr::Backend& backend) {
    const auto s = backend.lastStats();
    if (!s) return std::nullopt;
    return GlFrameStats{s->method,         s->gpuMs,       s->drawWallMs, s->readbackWallMs,
                        s->totalWallMs,    s->passes,      s->samples};
}

}  // namespace mvr::gl
