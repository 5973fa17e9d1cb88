#include "mvr/vk/vk_backend.h"

#include "mvr/core/antialias.h"
#include "mvr/core/shadows.h"
#include "renderer.h"

namespace mvr::vk {

namespace {

class VkBackend final : public mvr::Backend {
public:
    std::string name() const override { return "vk"; }
    std::vector<std::string> methods() const override { return vkMethodNames(); }
    std::string defaultMethod() const override { return "auto"; }
    Status supports(const std::string& method) const override {
        return mRenderer.supports(method);
    }
    Result<RenderOutput> render(const Scene& scene, const Rig& rig, const RenderSettings& settings,
                                const std::string& method) override {
        return renderThroughInto(*this, scene, rig, settings, method);
    }
    Status renderInto(const Scene& scene, const Rig& rig, const RenderSettings& requested,
                      const std::string& method, RenderOutput& out) override {
        if (requested.samples > 1) return renderSampled(*this, scene, rig, requested, method, out);
        const RenderSettings settings = shadedSettings(requested);
        if (!settings.shadows) return mRenderer.renderInto(scene, rig, settings, method, out);
        // Shadows (issue 15): the casters' maps once for all views, as one multi-view pass
        // whose views are the lights, through the same method (auto: multipass, the
        // reference), then sampled by every view (textures.cpp: prepareShadows).
        if (Status s = validateRequest(scene, rig, settings); !s) return s;
        if (Status s = mRenderer.supports(method); !s) return s;
        Result<ShadowSet> set = renderShadowSet(*this, scene, settings.shadowMapSize,
                                                method == "auto" ? "multipass" : method);
        if (!set) return set.status();
        mRenderer.setShadows(&*set);
        const Status st = mRenderer.renderInto(scene, rig, settings, method, out);
        mRenderer.setShadows(nullptr);
        return st;
    }
    std::vector<std::string> info() const override { return mRenderer.info(); }
    std::optional<RenderStats> lastStats() const override { return mRenderer.lastStats(); }

private:
    // Creates its device lazily, from const queries too (supports(), info()).
    mutable detail::Renderer mRenderer;
};

}  // namespace

std::unique_ptr<mvr::Backend> makeVkBackend() { return std::make_unique<VkBackend>(); }

const std::vector<std::string>& vkMethodNames() {
    static const std::vector<std::string> names = {"multipass", "multiview", "instanced-layer",
                                                   "auto"};
    return names;
}

}  // namespace mvr::vk
