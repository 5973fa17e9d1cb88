// `mvr info`: the backends, their methods (and whether each runs here), and driver limits.
#include <memory>

#include <fmt/core.h>

#include "command.h"
#include "distribute.h"
#include "options.h"
#include "video.h"

namespace mvr::cli {
namespace {

/// `mvr info --displays`: the display presets (include/mvr/core/displays.h).
int runDisplays() {
    fmt::print(
        "display presets (mvr render --display NAME; docs/displays.md cites the figures):\n");
    fmt::print("  {:<25} {:>5}  {:<6} {:<10} {:<9} {:<7} {:>5}  {:<10} {}\n", "name", "views",
               "quilt", "quilt size", "view", "aspect", "cone", "panel", "output");
    for (const DisplayPreset& d : displayPresets()) {
        const std::string quilt =
            d.quiltColumns > 0 ? fmt::format("{}x{}", d.quiltColumns, d.quiltRows) : "-";
        const std::string quiltSize =
            d.quiltColumns > 0 ? fmt::format("{}x{}", d.quiltWidth, d.quiltHeight) : "-";
        const std::string cone =
            d.viewConeDegrees > 0.0f ? fmt::format("{:g}", d.viewConeDegrees) : "-";
        const std::string output = d.quiltColumns > 0
                                       ? fmt::format("quilt_qs{}x{}a{}.png", d.quiltColumns,
                                                     d.quiltRows, aspectText(d.aspect))
                                       : std::string(d.format) + ".png";
        fmt::print("  {:<25} {:>5}  {:<6} {:<10} {:<9} {:<7} {:>5}  {:<10} {}\n", d.name, d.views,
                   quilt, quiltSize, fmt::format("{}x{}", d.viewWidth, d.viewHeight),
                   aspectText(d.aspect), cone, fmt::format("{}x{}", d.panelWidth, d.panelHeight),
                   output);
        fmt::print("  {:<25} {}\n", "", d.description);
    }
    return 0;
}

int runInfo() {
    fmt::print("mvr {} — multiple-viewpoint rendering\n", MVR_VERSION);
    fmt::print("max views per render: {}\n", kMaxViews);
    // What this build has (-DMVR_WITH_VIDEO / -DMVR_WITH_MPI, or the libraries were missing).
    fmt::print("build: video files (FFmpeg) {}, frames over MPI ranks {}\n",
               videoAvailable() ? "yes" : "no", mpiAvailable() ? "yes" : "no");
    const auto names = backendChoices();  // the registry's backends, then auto
    if (names.empty()) fmt::print("no rendering backend is built into this mvr\n");
    for (const std::string& name : names) {
        auto backend = makeBackend(name);
        if (!backend) {
            fmt::print("backend {}: {}\n", name, backend.status().message());
            continue;
        }
        fmt::print("backend {}:\n", name);
        for (const std::string& line : (*backend)->info()) fmt::print("  {}\n", line);
        fmt::print("  methods:\n");
        for (const std::string& method : (*backend)->methods()) {
            const Status s = (*backend)->supports(method);
            fmt::print("    {:<18} {}\n", method, s ? "supported" : "unsupported: " + s.message());
        }
    }
    return 0;
}

const CommandRegistrar kInfo(90, [](CLI::App& root) -> std::function<int()> {
    CLI::App* app = root.add_subcommand(
        "info", "List backends, methods (and whether each runs here) and driver limits");
    auto displays = std::make_shared<bool>(false);
    app->add_flag("--displays", *displays,
                  "List the display presets instead (--display NAME): views, quilt columns x rows "
                  "and size, view size, per-view aspect, view cone, panel resolution, output");
    return [displays] { return *displays ? runDisplays() : runInfo(); };
});

}  // namespace
}  // namespace mvr::cli
