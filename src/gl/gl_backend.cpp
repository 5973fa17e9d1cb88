#include "mvr/gl/gl_backend.h"

#include "renderer.h"

namespace mvr::gl {

namespace {

class GlBackend final : public mvr::Backend {
public:
    std::string name() const override { return "gl"; }
    std::vector<std::string> methods() const override { return detail::methodNames(); }
    Status supports(const std::string& method) const override {
        return mRenderer.supports(method);
    }
    Result<RenderOutput> render(const Scene& scene, const Rig& rig,
                                const RenderSettings& settings,
                                const std::string& method) override {
        return mRenderer.render(scene, rig, settings, method);
    }
    std::vector<std::string> info() const override { return mRenderer.info(); }

    const std::optional<GlFrameStats>& stats() const { return mRenderer.lastStats(); }

private:
    // Lazily creates its context from const queries (supports(), info()).
    mutable detail::Renderer mRenderer;
};

}  // namespace

std::unique_ptr<mvr::Backend> makeGlBackend() { return std::make_unique<GlBackend>(); }

const std::vector<std::string>& glMethodNames() { return detail::methodNames(); }

std::optional<GlFrameStats> lastFrameStats(const mvr::Backend& backend) {
    if (const auto* gl = dynamic_cast<const GlBackend*>(&backend)) return gl->stats();
    return std::nullopt;
}

}  // namespace mvr::gl
