// The registry of backends: the built-in rows, then those registerBackend() adds.
#include "mvr/backends.h"

#include <algorithm>
#include <mutex>

#include <fmt/format.h>

#include "auto_backend.h"

#include "mvr/raster/soft_backend.h"
#ifdef MVR_HAVE_GL
#include "mvr/gl/composite_gpu.h"
#include "mvr/gl/gl_backend.h"
#endif
#ifdef MVR_HAVE_VULKAN
#include "mvr/vk/vk_backend.h"
#endif

namespace mvr {

namespace {

Result<raster::SimdPath> parseSimd(const std::string& name) {
    for (raster::SimdPath p : {raster::SimdPath::Auto, raster::SimdPath::Scalar,
                               raster::SimdPath::Avx2, raster::SimdPath::Avx512}) {
        if (name == raster::simdPathName(p)) return p;
    }
    return usageError(
        fmt::format("unknown SIMD path '{}' (expected auto, scalar, avx2 or avx512)", name));
}

std::vector<BackendEntry> builtIn() {
    std::vector<BackendEntry> rows;
    rows.push_back(
        BackendEntry{.name = "soft",
                     .description = "CPU: mvr's own rasterizer",
                     .gpu = false,
                     .make = [](const BackendOptions& o) -> Result<std::unique_ptr<Backend>> {
                         if (o.threads < 0) {
                             return usageError(fmt::format(
                                 "threads {} is out of range (expected >= 0)", o.threads));
                         }
                         auto simd = parseSimd(o.simd);
                         if (!simd) return simd.status();
                         return raster::makeSoftBackend({.threads = o.threads, .simd = *simd});
                     },
                     .interactiveMethod = {},
                     .compose = {}});
#ifdef MVR_HAVE_GL
    rows.push_back(BackendEntry{
        .name = "gl",
        .description = "OpenGL 4.5 through EGL",
        .gpu = true,
        .make = [](const BackendOptions&) -> Result<std::unique_ptr<Backend>> {
            return gl::makeGlBackend();
        },
        .interactiveMethod = "multipass",
        .compose = [](std::string_view format, std::span<const Image> views,
                      const composite::ComposeOptions& options) -> std::optional<Result<Image>> {
            if (!gl::composeGpuSupports(std::string(format))) return std::nullopt;
            return gl::composeGpu(std::string(format), views, options);
        }});
#endif
#ifdef MVR_HAVE_VULKAN
    rows.push_back(BackendEntry{
        .name = "vk",
        .description = "Vulkan 1.2, headless (VK_KHR_multiview)",
        .gpu = true,
        .make = [](const BackendOptions&) -> Result<std::unique_ptr<Backend>> {
            return vk::makeVkBackend();
        },
        .interactiveMethod = "multiview",
        .compose = {}});
#endif
    return rows;
}

struct Registry {
    std::mutex mutex;
    std::vector<BackendEntry> rows = builtIn();
};

Registry& registry() {
    static Registry r;
    return r;
}

/// The auto backend's entry (not a row: backends() lists only backends with pixels of their own).
const BackendEntry& autoEntry() {
    static const BackendEntry entry = [] {
        BackendEntry e;
        e.name = kAutoBackend;
        e.description = "the fastest of the others for each request, measured on its first frame";
        e.gpu = std::any_of(registry().rows.begin(), registry().rows.end(),
                            [](const BackendEntry& r) { return r.gpu; });
        e.make = [](const BackendOptions& o) -> Result<std::unique_ptr<Backend>> {
            if (o.threads < 0) {
                return usageError(
                    fmt::format("threads {} is out of range (expected >= 0)", o.threads));
            }
            if (auto simd = parseSimd(o.simd); !simd) return simd.status();
            return detail::makeAutoBackend(o);
        };
        return e;
    }();
    return entry;
}

}  // namespace

std::span<const BackendEntry> backends() {
    // Rows are only ever appended before use in practice; the span stays valid until the next
    // registerBackend() call.
    return registry().rows;
}

std::vector<std::string> backendNames() {
    std::vector<std::string> names;
    for (const BackendEntry& e : backends()) names.push_back(e.name);
    return names;
}

std::vector<std::string> backendChoices() {
    std::vector<std::string> names = backendNames();
    names.push_back(kAutoBackend);
    return names;
}

Result<const BackendEntry*> findBackend(std::string_view name) {
    for (const BackendEntry& e : backends()) {
        if (e.name == name) return &e;
    }
    if (name == kAutoBackend) return &autoEntry();
    return usageError(fmt::format("unknown backend '{}' (expected {})", name,
                                  fmt::join(backendChoices(), " or ")));
}

Status registerBackend(BackendEntry entry) {
    Registry& r = registry();
    std::lock_guard lock(r.mutex);
    if (entry.name.empty() || entry.name.find(':') != std::string::npos || !entry.make) {
        return usageError(
            fmt::format("registerBackend: '{}' is not a valid backend (a name "
                        "without ':' and a factory)",
                        entry.name));
    }
    if (std::any_of(r.rows.begin(), r.rows.end(),
                    [&](const BackendEntry& e) { return e.name == entry.name; })) {
        return usageError(fmt::format("registerBackend: '{}' is already registered", entry.name));
    }
    if (entry.name == kAutoBackend) {
        return usageError(
            "registerBackend: 'auto' is taken (the backend that picks one of the "
            "others)");
    }
    r.rows.push_back(std::move(entry));
    return {};
}

Result<std::unique_ptr<Backend>> makeBackend(std::string_view name, const BackendOptions& options) {
    auto entry = findBackend(name);
    if (!entry) return entry.status();
    return (*entry)->make(options);
}

Result<MethodSpec> parseMethodSpec(std::string_view spec) {
    const std::size_t colon = spec.find(':');
    MethodSpec out;
    out.backend = std::string(spec.substr(0, colon));
    auto backend = makeBackend(out.backend);
    if (!backend) {
        return Status(backend.status().code(),
                      fmt::format("'{}': {}", spec, backend.status().message()));
    }
    if (colon == std::string_view::npos) {
        out.method = (*backend)->defaultMethod();
        return out;
    }
    out.method = std::string(spec.substr(colon + 1));
    const auto methods = (*backend)->methods();
    if (std::find(methods.begin(), methods.end(), out.method) == methods.end()) {
        return usageError(
            fmt::format("'{}': unknown method '{}' of backend {} (expected one of: {})", spec,
                        out.method, out.backend, fmt::join(methods, ", ")));
    }
    return out;
}

Result<Image> composeFor(const Backend& backend, std::string_view format,
                         std::span<const Image> views, const composite::ComposeOptions& options) {
    auto entry = findBackend(backend.name());
    if (entry && (*entry)->compose) {
        if (auto image = (*entry)->compose(format, views, options)) return std::move(*image);
    }
    return composite::compose(format, views, options);
}

}  // namespace mvr
