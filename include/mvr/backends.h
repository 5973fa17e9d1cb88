// mvr/backends.h — every backend of this build, by name: the one place that knows which
// backends exist. Tools, benches, the viewer and the tests create backends here and never
// spell a backend's name.
//
// Built in: "soft" (mvr's CPU rasterizer, always) and "gl" (OpenGL 4.5 through EGL, when the
// build has it), in that order. A new backend joins by a row in src/backends/registry.cpp (or,
// from outside the library, registerBackend()); the conformance suite then tests every one of
// its methods against soft:multipass.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "mvr/composite/compose.h"
#include "mvr/core/render.h"
#include "mvr/core/status.h"

namespace mvr {

/// Options a backend may honour when it is created (the others ignore them).
struct BackendOptions {
    int threads = 0;            ///< CPU worker threads; 0 = one per core the process may use
    std::string simd = "auto";  ///< CPU SIMD path: auto | scalar | avx2 | avx512
};

/// One backend of the registry.
struct BackendEntry {
    std::string name;         ///< "soft", "gl", …
    std::string description;  ///< one line for help texts and `mvr info`
    bool gpu = false;         ///< renders on a GPU (or its driver's software rasterizer)
    std::function<Result<std::unique_ptr<Backend>>(const BackendOptions&)> make;
    /// The method an interactive tool (`mvr view`) starts on, where it is not the backend's
    /// defaultMethod() (gl: "multipass", since its default "auto" measures every method again
    /// for each new view size). Empty: defaultMethod().
    std::string interactiveMethod;
    /// Composes an image format from that backend's views on its own device (gl: on the GPU);
    /// nullopt where it does not (the caller composes on the CPU). May be empty.
    std::function<std::optional<Result<Image>>(std::string_view format,
                                               std::span<const Image> views,
                                               const composite::ComposeOptions& options)>
        compose;
};

/// The backend that picks one of the others: "auto" (src/backends/auto_backend.cpp). For each
/// kind of request (view count, size, shading, culling, wireframe, shadows, the scene's size:
/// not the cameras) it measures every registered backend's default method on the first frame
/// (soft: unified; gl: auto, i.e. the exact gl method gl measured fastest) — one warm-up, then
/// the best of two renders by wall clock — renders with the fastest and keeps that choice for
/// every later frame of the same kind. Its one method is "auto" (any other is refused with a
/// Usage error: name the backend to pick a method); RenderOutput::method and
/// RenderStats::method are the pick as "BACKEND:METHOD" (e.g. "gl:instanced-layer"), and
/// RenderOutput::note says "auto picked BACKEND:METHOD: ..." with every candidate's time.
/// It is not a row of backends() (which the conformance suite and the viewer walk: it has no
/// pixels of its own); findBackend() / makeBackend() / parseMethodSpec() know it, and
/// backendChoices() lists it. Its entry's `gpu` is true when a GPU backend is registered (it may
/// render on it: callers that serialise GPU work treat it as one).
inline constexpr const char* kAutoBackend = "auto";

/// The registered backends in a stable order (soft first).
std::span<const BackendEntry> backends();
/// Their names.
std::vector<std::string> backendNames();
/// Every name makeBackend() accepts: backendNames(), then "auto" (kAutoBackend).
std::vector<std::string> backendChoices();
/// The entry of `name` (a registered backend, or "auto"). Errors: Usage for an unknown name,
/// listing the known ones.
Result<const BackendEntry*> findBackend(std::string_view name);
/// Adds a backend (for backends outside this library; the built-in ones are always there). It
/// is one of the auto backend's candidates from then on (for auto backends made after it).
/// Errors: Usage when the name is empty, taken (or "auto"), or contains ':'.
Status registerBackend(BackendEntry entry);

/// Creates a backend by name. Errors: Usage for an unknown name or bad options (an unknown
/// SIMD path), whatever the backend's own factory refuses.
Result<std::unique_ptr<Backend>> makeBackend(std::string_view name,
                                             const BackendOptions& options = {});

/// A "backend:method" pair, e.g. soft:unified, gl:gs-layered.
struct MethodSpec {
    std::string backend;
    std::string method;
    std::string text() const { return backend + ":" + method; }
};
/// Parses "backend:method", or "backend" alone for its default method (the backend is created
/// to ask it). Checks that the backend exists and knows the method (not that it runs here).
/// Errors: Usage naming the spec and what is wrong.
Result<MethodSpec> parseMethodSpec(std::string_view spec);

/// Composes `format` from the views `backend` rendered: on the backend's device where it has a
/// composer for that format, else on the CPU (composite::compose). Same pixels either way
/// (anaglyphs within 1/255, src/gl/README.md).
Result<Image> composeFor(const Backend& backend, std::string_view format,
                         std::span<const Image> views, const composite::ComposeOptions& options);

}  // namespace mvr
