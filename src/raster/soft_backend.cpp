#include "mvr/raster/soft_backend.h"

#include <chrono>
#include <cmath>
#include <iterator>
#include <mutex>
#include <new>

#include <fmt/format.h>

#include "cpu.h"
#include "mvr/core/antialias.h"
#include "mvr/core/platform.h"
#include "mvr/core/shadows.h"
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

// The soft backend's methods: one row each (mScratch has one slot per row).
struct SoftMethod {
    const char* name;
    const char* description;
    void (*render)(detail::FrameContext& f, std::span<const detail::Target> targets,
                   StageTimes& times, std::unique_ptr<detail::MethodScratch>& scratch);
};

constexpr SoftMethod kMethods[] = {
    {"multipass", "N independent single-view renders", detail::renderMultipass},
    {"unified", "kalaiah2007's unified N-view pipeline with adelson1991's algorithms",
     detail::renderUnified},
};
constexpr const char* kDefaultMethod = "unified";

// The row of `name`'s index in kMethods; -1 for an unknown name.
int findMethod(const std::string& name) {
    for (std::size_t i = 0; i < std::size(kMethods); ++i) {
        if (name == kMethods[i].name) return static_cast<int>(i);
    }
    return -1;
}

class SoftBackend final : public Backend, public RowStreamingBackend {
public:
    explicit SoftBackend(const SoftOptions& options) : mOptions(options) {
        mSimd = detail::resolveSimd(options.simd);
    }

    std::string name() const override { return "soft"; }
    std::vector<std::string> methods() const override {
        std::vector<std::string> names;
        for (const SoftMethod& m : kMethods) names.emplace_back(m.name);
        return names;
    }
    std::string defaultMethod() const override { return kDefaultMethod; }
    std::optional<RenderStats> lastStats() const override {
        std::lock_guard lock(mStatsMutex);
        return mStats;
    }

    Status supports(const std::string& method) const override {
        if (findMethod(method) >= 0) return {};
        return usageError(fmt::format("soft backend: unknown method '{}' (expected {})", method,
                                      fmt::join(methods(), " or ")));
    }

    std::vector<std::string> info() const override {
        return {fmt::format("CPU: {}", mvr::cpuModelName()),
                fmt::format("SIMD path: {} (best on this CPU and build: {})", simdPathName(mSimd),
                            simdPathName(bestSimdPath())),
                fmt::format("worker threads: {} ({})", threadCount(),
                            !mPool            ? "pinned to cores when started"
                            : mPool->pinned() ? "pinned to cores"
                                              : "not pinned: the OS refused"),
                "fixed point: 8 sub-pixel bits, top-left fill rule, guard band ±64 NDC"};
    }

    Result<RenderOutput> render(const Scene& scene, const Rig& rig, const RenderSettings& settings,
                                const std::string& method) override {
        return renderThroughInto(*this, scene, rig, settings, method);
    }

    Status renderInto(const Scene& scene, const Rig& rig, const RenderSettings& requested,
                      const std::string& method, RenderOutput& out) override {
        if (requested.samples > 1) return renderSampled(*this, scene, rig, requested, method, out);
        const RenderSettings settings = shadedSettings(requested);
        if (Status s = validateRequest(scene, rig, settings); !s) return s;
        if (Status s = supports(method); !s) return s;
        return renderWithShadows(scene, rig, settings, method, out, nullptr);
    }

    Status renderRows(const Scene& scene, const Rig& rig, const RenderSettings& requested,
                      const std::string& method, ViewRowSink& sink) override {
        if (requested.samples > 1)
            return unsupportedError(fmt::format(
                "soft backend: rows are streamed one sample a pixel (asked {})",
                requested.samples));
        const RenderSettings settings = shadedSettings(requested);
        if (Status s = validateRequest(scene, rig, settings); !s) return s;
        if (Status s = supports(method); !s) return s;
        if (method != "unified" || rig.viewCount() < 2)
            return unsupportedError(fmt::format(
                "soft:{} with {} view{}: only soft:unified with 2 or more views draws every "
                "view's rows at once",
                method, rig.viewCount(), rig.viewCount() == 1 ? "" : "s"));
        RenderOutput unused;
        return renderWithShadows(scene, rig, settings, method, unused, &sink);
    }

private:
    /// renderChecked() after the frame's shadow maps (issue 15: the casters' maps once for all
    /// views, as one multi-view render whose views are the lights, with the same method); out of
    /// memory is an error naming the request.
    Status renderWithShadows(const Scene& scene, const Rig& rig, const RenderSettings& settings,
                             const std::string& method, RenderOutput& out, ViewRowSink* sink) {
        try {
            ShadowSet shadows;
            if (settings.shadows) {
                Result<ShadowSet> set =
                    renderShadowSet(*this, scene, settings.shadowMapSize, method);
                if (!set) return set.status();
                shadows = std::move(*set);
            }
            renderChecked(scene, rig, settings, method, shadows, out, sink);
            return {};
        } catch (const std::bad_alloc&) {
            return internalError(
                fmt::format("soft backend: out of memory rendering {} views of {}x{}",
                            rig.viewCount(), settings.width, settings.height));
        }
    }

    /// Renders into `out`, keeping its images' storage where the view count and size match
    /// (allocateOutputs: then only the clear). `shadows`: the frame's shadow maps (issue 15),
    /// or an empty set.
    void renderChecked(const Scene& scene, const Rig& rig, const RenderSettings& settings,
                       const std::string& method, const ShadowSet& shadows, RenderOutput& out,
                       ViewRowSink* sink = nullptr) {
        std::lock_guard lock(mMutex);  // one render at a time per backend (shared pool, scratch)
        const auto start = std::chrono::steady_clock::now();
        detail::ThreadPool& pool = this->pool();
        out.method = method;
        out.note.clear();
        out.stages = {};
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
                               detail::kernels(mSimd),
                               false,
                               false,
                               {},
                               false,
                               false,
                               false,
                               {}};
        f.shading.tonemap = scene.tonemap;
        f.shading.environment = scene.environment.get();
        detail::prepareTextures(f);
        detail::Kernels shadowKernels = f.kernels;
        std::optional<detail::FrameContext> shadowed;
        if (!shadows.empty()) {
            // Shadows (issue 15): every lighting path looks the factors up (shadows.h); the
            // vertex kernel is replaced by the scalar shadowed one.
            f.shading.shadows = &shadows;
            shadowKernels.shadeVertices = detail::shadeVerticesShadowed;
            shadowed.emplace(detail::FrameContext{f.scene, f.rig, f.settings, f.pool, f.shading,
                                                  std::move(f.draw), f.bands, f.centerClip,
                                                  shadowKernels, f.textured, f.punctualLights,
                                                  std::move(f.mips), f.streamBands, f.colored,
                                                  f.tangents, {}});
        }
        detail::FrameContext& frame = shadowed ? *shadowed : f;
        frame.setViewShading();  // --specular per-view
        const double imageBytes = double(rig.viewCount()) * settings.width * settings.height * 8.0;
        frame.streamBands = imageBytes > double(mOptions.streamAboveBytes);
        std::vector<detail::Target> targets;
        if (sink) {
            // renderRows: every band streamed to the sink; the targets only size the scratch.
            frame.streamBands = true;
            frame.rowSink = sink;
            targets.assign(std::size_t(rig.viewCount()),
                           detail::Target{nullptr, nullptr, settings.width, settings.height});
        } else {
            detail::allocateOutputs(pool, out, rig.viewCount(), settings, targets);
        }
        out.stages.fillMs = clock.lap();
        const auto row = static_cast<std::size_t>(findMethod(method));  // supports() passed
        kMethods[row].render(frame, targets, out.stages, mScratch[row]);
        RenderStats stats;
        stats.method = method;
        stats.stages = out.stages;
        stats.totalWallMs =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
                .count();
        stats.drawWallMs = stats.totalWallMs;
        std::lock_guard statsLock(mStatsMutex);
        mStats = stats;
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
    mutable std::mutex mStatsMutex;
    std::optional<RenderStats> mStats;
    std::unique_ptr<detail::ThreadPool> mPool;
    std::unique_ptr<detail::MethodScratch> mScratch[std::size(kMethods)];
};

}  // namespace

std::unique_ptr<Backend> makeSoftBackend(const SoftOptions& options) {
    return std::make_unique<SoftBackend>(options);
}

}  // namespace mvr::raster
