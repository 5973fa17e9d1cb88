// mvr — multiple-viewpoint rendering: command-line entry point.
#include <algorithm>
#include <cstdio>
#include <exception>
#include <new>

#include <fmt/core.h>

#include "command.h"
#include "stop_signals.h"
#include "mvr/core/platform.h"
#include "mvr/core/status.h"

namespace mvr::cli {
std::vector<CommandEntry>& commandRegistry() {
    static std::vector<CommandEntry> registry;
    return registry;
}
}  // namespace mvr::cli

int main(int argc, char** argv) {
    using namespace mvr::cli;
    handleStopSignals();  // before any thread: outputs stay whole when the run is stopped
    mvr::retainFreedMemory();  // per-frame buffers (ours, llvmpipe's) stop page-faulting
    CLI::App app{
        "mvr — render one 3D scene from 2..N viewpoints (stereo pairs, autostereo rows, "
        "view grids) cheaper than N renders."};
    app.set_version_flag("--version", std::string("mvr ") + MVR_VERSION);
    app.require_subcommand(1);
    app.fallthrough(false);
    auto& registry = commandRegistry();
    std::sort(registry.begin(), registry.end(),
              [](const CommandEntry& a, const CommandEntry& b) { return a.order < b.order; });
    std::vector<std::pair<CLI::App*, std::function<int()>>> commands;
    for (const CommandEntry& entry : registry) {
        const std::size_t before = app.get_subcommands({}).size();
        std::function<int()> run = entry.setup(app);
        auto subs = app.get_subcommands({});
        if (subs.size() > before) commands.emplace_back(subs.back(), std::move(run));
    }
    if (argc > 1 && argv[1][0] != '-') {
        const std::string name = argv[1];
        std::string known;
        bool found = false;
        for (auto& [sub, run] : commands) {
            found = found || sub->get_name() == name;
            known += (known.empty() ? "" : ", ") + sub->get_name();
        }
        if (!found) {
            fmt::print(stderr, "error: unknown command '{}' (expected one of {})\n", name, known);
            return 1;
        }
    }
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        fmt::print(stderr, "error: {}\n", e.what());
        fmt::print(stderr, "run `mvr --help` (or `mvr COMMAND --help`) for usage\n");
        // A file an option names that is malformed (--lenticular-calibration) is exit 2.
        const int code = e.get_exit_code();
        return code >= 2 && code <= 5 ? code : 1;
    }
    for (auto& [sub, run] : commands) {
        if (!sub->parsed()) continue;
        // Requests are checked up front (views x size against a fixed budget), but what fits
        // depends on the machine: running out of memory is one error line, not an abort.
        try {
            return run();
        } catch (const std::bad_alloc&) {
            fmt::print(stderr,
                       "error: mvr {}: out of memory (ask for fewer views, a smaller --size or "
                       "fewer threads)\n",
                       sub->get_name());
            return mvr::exitCode(mvr::ErrorCode::Internal);  // as the soft backend's own
        } catch (const std::exception& e) {
            fmt::print(stderr, "error: mvr {}: internal error: {}\n", sub->get_name(), e.what());
            return mvr::exitCode(mvr::ErrorCode::Internal);
        }
    }
    return 1;
}
