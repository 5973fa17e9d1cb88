#include "mvr/raster/soft_backend.h"

#include <cmath>
#include <mutex>
#include <new>

#include <fmt/core.h>

#include "cpu.h"
#include "mvr/core/platform.h"
#include "methods.h"

namespace mvr::raster {

const char* simdPathName(SimdPath path) {
    switch (path) {
        case SimdPath::Auto: return "auto";
        case SimdPath::Scalar: return "scalar";
        case SimdPath::Avx2: return "avx2";
        case SimdPath::Avx512: return "avx512";
    }
    return "?";
}

SimdPath bestSimdPath() { return detail::bestSupportedSimd(); }

namespace {

bool finiteMatrix(const glm::mat4& m) {
    for (int c = 0; c < 4; ++c) {
        for (int r = 0; r < 4; ++r) {
            if (!std::isfinite(m[c][r])) return false;
        }
    }
    return true;
}

Status validateRig(const Rig& rig) {
    if (rig.viewCount() < 1 || rig.viewCount() > kMaxViews) {
        return usageError(fmt::format("soft backend: rig has {} views (expected 1..{})",
                                      rig.viewCount(), kMaxViews));
    }
    if (!std::isfinite(rig.convergence)) {
        return usageError("soft backend: rig convergence is not finite");
    }
    for (int v = 0; v < rig.viewCount(); ++v) {
        const View& view = rig.views[std::size_t(v)];
        if (!finiteMatrix(view.clipFromWorld()) ||
            (view.clipShear && !(std::isfinite(view.clipShear->x) && std::isfinite(view.clipShear->y)))) {
            return usageError(fmt::format("soft backend: view {} has a non-finite matrix or shear", v));
        }
    }
    if (!finiteMatrix(rig.camera.clipFromView() * rig.camera.viewFromWorld())) {
        return usageError("soft backend: the rig's center camera has a non-finite matrix");
    }
    return {};
}

class SoftBackend final : public Backend {
public:
    explicit SoftBackend(const SoftOptions& options) : mOptions(options) {
        mSimd = detail::resolveSimd(options.simd);
    }

    std::string name() const override { return "soft"; }
    std::vector<std::string> methods() const override { return {"multipass", "unified"}; }

    Status supports(const std::string& method) const override {
        if (method == "multipass" || method == "unified") return {};
        return usageError(fmt::format("soft backend: unknown method '{}' (expected multipass or unified)",
                                      method));
    }

    std::vector<std::string> info() const override {
        return {fmt::format("CPU: {}", mvr::cpuModelName()),
                fmt::format("SIMD path: {} (best on this CPU and build: {})", simdPathName(mSimd),
                            simdPathName(bestSimdPath())),
                fmt::format("worker threads: {} ({})", threadCount(),
                            !mPool ? "pinned to cores when started" : mPool->pinned() ? "pinned to cores" : "not pinned: the OS refused"),
                "fixed point: 8 sub-pixel bits, top-left fill rule, guard band ±64 NDC"};
    }

    Result<RenderOutput> render(const Scene& scene, const Rig& rig, const RenderSettings& settings,
                                const std::string& method) override {
        if (Status s = supports(method); !s) return s;
        if (Status s = validateSettings(settings); !s) return s;
        if (Status s = validateScene(scene); !s) return s;
        if (Status s = validateRig(rig); !s) return s;
        for (const Instance& inst : scene.instances) {
            if (!finiteMatrix(inst.worldFromModel)) {
                return usageError("soft backend: an instance has a non-finite transform");
            }
        }

        // Color + depth per view (8 bytes a pixel): refuse what cannot reasonably be allocated
        // instead of dying in the allocator.
        const double frameBytes = double(settings.width) * settings.height * 8.0 * rig.viewCount();
        if (frameBytes > kMaxFramebufferBytes) {
            return usageError(fmt::format(
                "soft backend: {} views of {}x{} need {:.1f} GiB of color and depth images (limit {:.0f} GiB)",
                rig.viewCount(), settings.width, settings.height, frameBytes / 1073741824.0,
                kMaxFramebufferBytes / 1073741824.0));
        }
        try {
            return renderChecked(scene, rig, settings, method);
        } catch (const std::bad_alloc&) {
            return internalError(fmt::format("soft backend: out of memory rendering {} views of {}x{}",
                                             rig.viewCount(), settings.width, settings.height));
        }
    }

private:
    static constexpr double kMaxFramebufferBytes = 8.0 * 1073741824.0;

    Result<RenderOutput> renderChecked(const Scene& scene, const Rig& rig, const RenderSettings& settings,
                                       const std::string& method) {
        std::lock_guard lock(mMutex);  // one render at a time per backend (shared pool, scratch)
        detail::ThreadPool& pool = this->pool();
        RenderOutput out;
        out.method = method;
        detail::StageClock clock;
        detail::FrameContext f{scene,
                               rig,
                               settings,
                               pool,
                               ShadingContext{std::span<const DirectionalLight>(scene.lights),
                                              scene.ambient, rig.centerEye()},
                               detail::makeDrawList(scene),
                               detail::makeBands(settings.height, pool.size()),
                               detail::centerClipFromWorld(rig),
                               detail::kernels(mSimd)};
        std::vector<detail::Target> targets;
        detail::allocateOutputs(pool, out, rig.viewCount(), settings, targets);
        out.stages.fillMs = clock.lap();
        if (method == "multipass") {
            detail::renderMultipass(f, targets, out.stages, mScratch[0]);
        } else {
            detail::renderUnified(f, targets, out.stages, mScratch[1]);
        }
        return out;
    }

    int threadCount() const {
        return mOptions.threads > 0 ? mOptions.threads : detail::availableCpus();
    }
    detail::ThreadPool& pool() {
        if (!mPool) mPool = std::make_unique<detail::ThreadPool>(mOptions.threads);
        return *mPool;
    }

    SoftOptions mOptions;
    SimdPath mSimd = SimdPath::Scalar;
    std::mutex mMutex;
    std::unique_ptr<detail::ThreadPool> mPool;
    std::unique_ptr<detail::MethodScratch> mScratch[2];
};

}  // namespace

std::unique_ptr<Backend> makeSoftBackend(const SoftOptions& options) {
    return std::make_unique<SoftBackend>(options);
}

}  // namespace mvr::raster
