// tools/viewer/viewer_backends.h — the backends and methods `mvr view` shows, all from the
// registry (mvr::backends(), mvr/backends.h): the backend it starts on (the first GPU backend),
// the method (the row's interactiveMethod, else the backend's defaultMethod()), the fallback
// when that cannot run here (the first non-GPU backend), and the order `m` cycles the methods.
// No backend is named here.
#pragma once

#include <cstddef>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "mvr/core/render.h"
#include "mvr/core/status.h"

namespace mvr::viewer {

struct ViewerOptions;

/// One method of one backend, e.g. gl:multipass.
struct MethodRef {
    std::string backend;
    std::string method;
    std::string label() const { return backend + ":" + method; }
};

/// The default --backend: the first GPU backend of mvr::backends(), else the first backend.
std::string defaultViewerBackend();
/// The backend the viewer falls back to: the first non-GPU backend ("" when there is none).
std::string fallbackViewerBackend();
/// The method backend `name` starts on: its row's interactiveMethod, else `defaultMethod`.
std::string startMethod(const std::string& name, const std::string& defaultMethod);

/// The backends `mvr view` switches between. Every call (creation included) belongs on the
/// viewer's render worker (render_worker.h).
class ViewerBackends {
public:
    /// Makes every backend of the registry (skipping one whose factory fails) and lists their
    /// methods in the order `m` cycles them: GPU backends first, then the others, each group in
    /// registry order. Errors: Unsupported when no backend could be made.
    Status make();
    /// Destroys the backends (their GL objects die with their context's thread).
    void clear() { mBackends.clear(); }

    const std::vector<MethodRef>& methods() const { return mMethods; }
    bool has(const std::string& name) const { return mBackends.count(name) > 0; }
    /// The backend `name`; precondition: has(name).
    Backend& backend(const std::string& name) const { return *mBackends.at(name); }
    /// The index of `backend`:`method` in methods().
    std::optional<std::size_t> find(const std::string& backend, const std::string& method) const;

private:
    std::map<std::string, std::unique_ptr<Backend>> mBackends;
    std::vector<MethodRef> mMethods;
};

/// The index in `backends.methods()` of the method the viewer starts on: options.method, or the
/// start method of options.backend. When that backend cannot run here (Unsupported), --backend
/// was not given and there is a fallback backend, it says so on stderr ("mvr view: gl backend
/// unavailable (…); using soft") and starts the fallback on the same method when it has one,
/// else on its start method. `supports` asks a backend whether a method runs (on the render
/// worker). Errors: the backend is unknown or not available, options.method is not one of its
/// methods (Usage), or the method does not run here.
Result<std::size_t> chooseInitialMethod(const ViewerBackends& backends,
                                        const ViewerOptions& options,
                                        const std::function<Status(const MethodRef&)>& supports);

}  // namespace mvr::viewer
