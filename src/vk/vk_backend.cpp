#include "mvr/vk/vk_backend.h"

#include "mvr/core/antialias.h"
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
        return mRenderer.renderInto(scene, rig, shadedSettings(requested), method, out);
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
