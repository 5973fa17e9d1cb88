// tests/conformance/gl_requirements.h — what a GL driver that CI runs must do. Without
// MVR_REQUIRE_GL=1 (a developer's machine without EGL) the GL suites skip what cannot run; with
// it (.ci/run) a missing context fails, and so does a refusal of any method on the driver's
// list below. MVR_REQUIRE_GL_DRIVER=NAME also fails unless GL_RENDERER names NAME (Mesa falls
// back to llvmpipe when the zink driver cannot load: the zink run would test llvmpipe twice).
#pragma once

#include <algorithm>
#include <cstdlib>
#include <string>
#include <vector>

namespace mvr::test {

inline bool requireGl() {
    const char* v = std::getenv("MVR_REQUIRE_GL");
    return v && std::string(v) == "1";
}

/// The driver the run must be on ("" when any will do).
inline std::string requiredGlDriver() {
    const char* v = std::getenv("MVR_REQUIRE_GL_DRIVER");
    return v ? v : "";
}

/// GL_RENDERER from a gl backend's info() lines ("" when absent).
inline std::string glRenderer(const std::vector<std::string>& info) {
    const std::string key = "GL_RENDERER: ";
    for (const std::string& line : info) {
        if (line.rfind(key, 0) == 0) return line.substr(key.size());
    }
    return "";
}

/// The gl methods a driver must run (every one of `all` on the drivers CI knows: Mesa's
/// llvmpipe and zink over lavapipe, which lack only GL_OVR_multiview); none for others.
inline std::vector<std::string> requiredGlMethods(const std::string& renderer,
                                                  const std::vector<std::string>& all) {
    const bool known = renderer.find("llvmpipe") != std::string::npos ||
                       renderer.find("zink") != std::string::npos;
    if (!known) return {};
    std::vector<std::string> out;
    for (const std::string& m : all) {
        if (m != "multiview") out.push_back(m);
    }
    return out;
}

/// Under MVR_REQUIRE_GL=1: why `method` must not be refused on this driver ("" when it may).
inline std::string mustRun(const std::vector<std::string>& info,
                           const std::vector<std::string>& all, const std::string& method) {
    if (!requireGl()) return "";
    const std::string renderer = glRenderer(info);
    const std::vector<std::string> req = requiredGlMethods(renderer, all);
    if (std::find(req.begin(), req.end(), method) == req.end()) return "";
    return "MVR_REQUIRE_GL=1 and " + renderer + " must run gl:" + method;
}

/// Under MVR_REQUIRE_GL_DRIVER: why this renderer is the wrong one ("" when right).
inline std::string wrongGlDriver(const std::vector<std::string>& info) {
    const std::string want = requiredGlDriver();
    if (want.empty()) return "";
    const std::string renderer = glRenderer(info);
    if (renderer.find(want) != std::string::npos) return "";
    return "MVR_REQUIRE_GL_DRIVER=" + want + " but GL_RENDERER is '" + renderer + "'";
}

}  // namespace mvr::test
