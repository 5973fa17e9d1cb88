#include "viewer_backends.h"

#include <fmt/core.h>

#include "mvr/backends.h"
#include "viewer.h"

namespace mvr::viewer {

std::string defaultViewerBackend() {
    for (const BackendEntry& e : mvr::backends())
        if (e.gpu) return e.name;
    return mvr::backends().empty() ? std::string() : mvr::backends().front().name;
}

std::string fallbackViewerBackend() {
    for (const BackendEntry& e : mvr::backends())
        if (!e.gpu) return e.name;
    return {};
}

std::string startMethod(const std::string& name, const std::string& defaultMethod) {
    Result<const BackendEntry*> entry = findBackend(name);
    if (entry && !(*entry)->interactiveMethod.empty()) return (*entry)->interactiveMethod;
    return defaultMethod;
}

Status ViewerBackends::make() {
    for (const bool gpu : {true, false}) {
        for (const BackendEntry& e : mvr::backends()) {
            if (e.gpu != gpu) continue;
            auto backend = mvr::makeBackend(e.name);
            if (!backend) continue;  // cannot be made in this process
            for (const std::string& m : (*backend)->methods()) mMethods.push_back({e.name, m});
            mBackends[e.name] = std::move(backend).value();
        }
    }
    if (mMethods.empty()) return unsupportedError("mvr view: no rendering backend in this mvr");
    return Status::ok();
}

std::optional<std::size_t> ViewerBackends::find(const std::string& backend,
                                                const std::string& method) const {
    for (std::size_t i = 0; i < mMethods.size(); ++i) {
        if (mMethods[i].backend == backend && mMethods[i].method == method) return i;
    }
    return std::nullopt;
}

Result<std::size_t> chooseInitialMethod(const ViewerBackends& backends,
                                        const ViewerOptions& options,
                                        const std::function<Status(const MethodRef&)>& supports) {
    const std::string name = options.backend.empty() ? defaultViewerBackend() : options.backend;
    if (!backends.has(name)) {
        auto made = mvr::makeBackend(name);  // for its error message
        if (!made) return made.status();
        return unsupportedError(fmt::format("backend '{}' is not available", name));
    }
    // Default method: the backend's interactive one (gl: multipass rather than auto, which
    // measures every method again for each new window size; `m` reaches auto).
    const auto begin = [&](const std::string& backend) {
        return startMethod(backend, backends.backend(backend).defaultMethod());
    };
    const std::string wanted = !options.method.empty() ? options.method : begin(name);
    std::optional<std::size_t> index = backends.find(name, wanted);
    if (!index) {
        return usageError(
            fmt::format("--method '{}' is not a method of the {} backend (see `mvr "
                        "info`)",
                        wanted, name));
    }
    Status s = supports(backends.methods()[*index]);
    const std::string fallback = fallbackViewerBackend();
    if (!s && !options.backendGiven && s.code() == ErrorCode::Unsupported && fallback != name &&
        backends.has(fallback)) {
        // The default backend has no context here: show the fallback instead.
        fmt::print(stderr, "mvr view: {} backend unavailable ({}); using {}\n", name, s.message(),
                   fallback);
        index = backends.find(fallback, options.method);
        if (!index) index = backends.find(fallback, begin(fallback));
        if (!index) return internalError(fmt::format("mvr view: {} has no methods", fallback));
        s = supports(backends.methods()[*index]);
    }
    if (!s) return s;
    return *index;
}

}  // namespace mvr::viewer
