// `mvr info`: the backends, their methods (and whether each runs here), and driver limits.
#include <fmt/core.h>

#include "command.h"
#include "options.h"

namespace mvr::cli {
namespace {

int runInfo() {
    fmt::print("mvr {} — multiple-viewpoint rendering\n", MVR_VERSION);
    fmt::print("max views per render: {}\n", kMaxViews);
    const auto names = backendNames();
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
    root.add_subcommand("info",
                        "List backends, methods (and whether each runs here) and driver limits");
    return runInfo;
});

}  // namespace
}  // namespace mvr::cli
