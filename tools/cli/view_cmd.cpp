// `mvr view`: the interactive stereo viewer. Its code is the library mvr_viewer
// (tools/viewer/), built when GLFW is found (MVR_BUILD_VIEWER); tools/viewer/CMakeLists.txt
// links it into `mvr` and defines MVR_HAVE_VIEWER. Without it, `mvr view` says so (exit 3).
#include "command.h"
#include "options.h"

#ifdef MVR_HAVE_VIEWER
#include "viewer.h"
#endif

namespace mvr::cli {
namespace {

#ifdef MVR_HAVE_VIEWER
const CommandRegistrar kView(40, [](CLI::App& root) { return viewer::addViewCommand(root); });
#else
const CommandRegistrar kView(40, [](CLI::App& root) -> std::function<int()> {
    CLI::App* app = root.add_subcommand(
        "view", "Interactive stereo viewer (not in this build: GLFW not found)");
    app->allow_extras();  // whatever the options, the answer is the same
    return [] {
        return fail(
            unsupportedError("mvr view: this mvr was built without the viewer (GLFW not found)"));
    };
});
#endif

}  // namespace
}  // namespace mvr::cli
