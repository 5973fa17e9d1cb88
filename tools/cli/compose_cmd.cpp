// `mvr compose`: existing view images (PNG, JPEG; an MPO or JPS is split into its views) →
// any output format of the composite module.
#include <algorithm>
#include <cctype>
#include <filesystem>
#include <memory>
#include <optional>
#include <regex>
#include <string>
#include <vector>

#include <fmt/core.h>

#include "command.h"
#include "compose_options.h"
#include "options.h"

#include "mvr/composite/compose.h"
#include "mvr/core/displays.h"
#include "mvr/session/outputs.h"
#include "mvr/session/prepare.h"
#include "mvr/session/rgbd_input.h"

namespace mvr::cli {
namespace {

struct ComposeCommandOptions {
    std::vector<std::string> inputs;
    std::string format = std::string(composite::kDefaultAnaglyph);
    std::string output = "out";
    bool quiet = false;
    bool formatGiven = false;  ///< --format on the command line (else inferred from -o .mpo/.jps)
    composite::ComposeOptions compose;
    /// --from-rgbd: the input is one RGB-D picture (or colour and depth) and the views are
    /// warped from it for --display (mvr/session/rgbd_input.h).
    bool fromRgbd = false;
    std::string display;
    bool quiltGiven = false, depthPositionGiven = false, depthinessGiven = false,
         focusGiven = false, calibrationGiven = false;
};

std::string lowerExtension(const std::filesystem::path& p) {
    std::string ext = p.extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return ext;
}

/// `mvr compose view-*.png`: a shell glob sorts view-10.png before view-2.png. Files named
/// PREFIX<N>SUFFIX (one prefix and suffix, distinct N) given in text order that is not their
/// numeric order are put in numeric order (returned); any other order is the caller's.
std::optional<std::vector<std::string>> numericOrder(const std::vector<std::string>& files) {
    static const std::regex numbered(R"(^(.*?)(\d+)(\D*)$)");
    std::vector<std::pair<unsigned long long, std::string>> keyed;
    std::string prefix, suffix;
    for (const std::string& f : files) {
        std::smatch m;
        if (!std::regex_match(f, m, numbered) || m[2].length() > 18) return std::nullopt;
        if (keyed.empty()) prefix = m[1], suffix = m[3];
        if (m[1] != prefix || m[3] != suffix) return std::nullopt;
        keyed.emplace_back(std::stoull(m[2]), f);
    }
    if (keyed.size() < 2 || !std::is_sorted(files.begin(), files.end())) return std::nullopt;
    auto sorted = keyed;
    std::stable_sort(sorted.begin(), sorted.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
    if (sorted == keyed) return std::nullopt;
    for (std::size_t i = 1; i < sorted.size(); ++i)
        if (sorted[i].first == sorted[i - 1].first) return std::nullopt;
    std::vector<std::string> out;
    for (auto& k : sorted) out.push_back(std::move(k.second));
    return out;
}

/// `mvr compose IMAGE --from-rgbd --display NAME`: the display's views warped from the RGB-D
/// picture, composed as the display takes them (a quilt) or as --format says.
int runFromRgbd(ComposeCommandOptions& o) {
    if (o.display.empty())
        return fail(usageError("--from-rgbd needs --display NAME, the light-field display whose "
                               "views to make (`mvr info --displays` lists them)"));
    Result<DisplayPreset> display = findDisplay(o.display);
    if (!display) return fail(display.status());
    std::optional<composite::DepthPosition> position;
    if (o.depthPositionGiven) position = o.compose.rgbdDepth;
    Result<session::RgbdInput> input = session::readRgbdInput(o.inputs, position);
    if (!input) return fail(input.status());
    const session::RgbdLook look = session::rgbdLook(
        *input, o.depthinessGiven ? std::optional<double>(o.compose.depthiness) : std::nullopt,
        o.focusGiven ? std::optional<double>(o.compose.focus) : std::nullopt);
    std::vector<std::string> formats;
    if (o.formatGiven) formats.push_back(o.format);
    session::displayOutputs(*display, o.calibrationGiven, o.quiltGiven, display->aspect, formats,
                            o.compose);
    o.format = formats.front();
    std::optional<TerminalProgress> progress;
    progress.emplace(fmt::format("warping {} views from {}", display->views, o.inputs[0]));
    Result<std::vector<Image>> views =
        session::viewsFromRgbd(*input, *display, look.depthiness, look.focus);
    if (!views) return fail(views.status());
    auto path = session::writeComposed(o.format, *views, o.compose, std::filesystem::path(o.output));
    if (!path) return fail(path.status());
    progress.reset();
    if (!o.quiet)
        fmt::print("composed {} views of {}x{} for {} from {} ({}{}) as {}\nwrote:\n  {}\n",
                   views->size(), views->front().width, views->front().height, display->name,
                   o.inputs.size() == 1 ? o.inputs[0] : o.inputs[0] + " and " + o.inputs[1],
                   input->measured ? "depth in world units from " : "depth as disparity",
                   input->measured ? input->sidecar : std::string(), o.format, path->string());
    return 0;
}

int runCompose(ComposeCommandOptions o) {
    if (o.fromRgbd) return runFromRgbd(o);
    if (!o.display.empty())
        return fail(usageError(fmt::format(
            "--display {}: mvr compose takes a display only with --from-rgbd (to compose "
            "rendered views for a display, give its --format and --quilt)",
            o.display)));
    if (auto ordered = numericOrder(o.inputs)) {
        fmt::print(stderr,
                   "note: the views are taken in the order of their numbers ({} before {}): "
                   "a shell glob sorts them as text\n",
                   (*ordered)[0], o.inputs[0] == (*ordered)[0] ? (*ordered)[1] : o.inputs[0]);
        o.inputs = std::move(*ordered);
    }
    // `-o pair.mpo` / `-o pair.jps` without --format: the file name says what to write.
    if (!o.formatGiven) {
        const std::string ext = lowerExtension(o.output);
        for (const composite::FormatInfo& f : composite::formats()) {
            // The first JPEG-file format (mpo, jps) whose own extension it is.
            if (f.file != composite::FileKind::Png && f.extension == ext) {
                o.format = std::string(f.name);
                break;
            }
        }
    }
    std::vector<Image> views;
    std::vector<std::string> sources;  // where each view came from, for messages
    for (const std::string& input : o.inputs) {
        auto read = composite::readViewFile(input);
        if (!read) return fail(read.status());
        const std::size_t count = read->size();
        for (std::size_t i = 0; i < count; ++i) {
            sources.push_back(count == 1 ? input
                                         : fmt::format("{} (view {} of {})", input, i, count));
            views.push_back(std::move((*read)[i]));
        }
    }
    for (std::size_t i = 1; i < views.size(); ++i) {
        if (views[i].width != views[0].width || views[i].height != views[0].height) {
            return fail(
                inputError(fmt::format("views differ in size: {} is {}x{} but {} is {}x{} "
                                       "(expected all views of one size)",
                                       sources[i], views[i].width, views[i].height, sources[0],
                                       views[0].width, views[0].height)));
        }
    }
    auto info = composite::findFormat(o.format);
    if (!info) return fail(info.status());
    const int n = static_cast<int>(views.size());
    if (n < info->minViews || n > info->maxViews) {
        const std::string expected = info->minViews == info->maxViews
                                         ? fmt::format("exactly {}", info->minViews)
                                     : info->maxViews >= composite::kAnyViewCount
                                         ? fmt::format("at least {}", info->minViews)
                                         : fmt::format("{} to {}", info->minViews, info->maxViews);
        return fail(usageError(fmt::format("--format {}: {} view{} given (expected {} views)",
                                           info->name, n, n == 1 ? "" : "s", expected)));
    }

    const std::filesystem::path out(o.output);
    std::filesystem::path written;
    std::optional<TerminalProgress> progress;  // on a terminal, after ~2 s (options.h)
    progress.emplace(fmt::format("composing {} view{} as {}", n, n == 1 ? "" : "s", info->name));
    // Written under a temporary name and moved into place: a failed run leaves -o as it was.
    auto path = session::writeComposed(o.format, views, o.compose, out);
    if (!path) return fail(path.status());
    written = *path;
    progress.reset();
    if (!o.quiet)
        fmt::print("composed {} view{} of {}x{} as {}\nwrote:\n  {}\n", n, n == 1 ? "" : "s",
                   views[0].width, views[0].height, info->name, written.string());
    return 0;
}

const CommandRegistrar kCompose(20, [](CLI::App& root) -> std::function<int()> {
    auto o = std::make_shared<ComposeCommandOptions>();
    CLI::App* app = root.add_subcommand(
        "compose",
        "Compose existing view images (left to right; PNG or JPEG, an MPO or .jps file counts as "
        "its views) into a stereo / multi-view format");
    app->add_option("views", o->inputs,
                    "View images, leftmost first (an MPO gives all its images, a .jps its "
                    "left and right halves)")
        ->required()
        ->type_name("VIEW");
    app->add_option("-f,--format", o->format,
                    "Output format (list below); default: mpo / jps for an -o file name ending "
                    "in .mpo / .jps, else the Dubois red-cyan anaglyph")
        ->check(CLI::IsMember(composite::formatNames()))
        ->default_val(o->format);
    app->add_option("-o,--output", o->output,
                    "A directory (created if missing; gets DIR/<format>.png, "
                    "DIR/quilt_qsCxRaA.png, DIR/jps.jps or DIR/mpo.mpo) or a file name ending "
                    "in .png, .jpg, .jpeg, .jps or .mpo (written as is)")
        ->default_val(o->output);
    app->add_flag("-q,--quiet", o->quiet, "Print nothing on success");
    app->add_flag("--from-rgbd", o->fromRgbd,
                  "The input is one RGB-D picture (colour and grey depth side by side, white = "
                  "near; --rgbd-depth-position, or its FILE.json sidecar, says where) or two "
                  "files, colour then depth: the views of --display are warped from it (depth "
                  "in world units with mvr's rgbd.json, else taken as disparity; "
                  "docs/displays.md)");
    app->add_option("--display", o->display,
                    "With --from-rgbd: the light-field display whose views to make (its view "
                    "count, size and cone; output: its format, a quilt, unless --format)")
        ->check(CLI::IsMember(displayNames()))
        ->type_name("NAME");
    addComposeOptions(app, o->compose, /*withStereoMetadata=*/true);
    app->footer("Formats:\n" + composite::formatHelp() +
                "Views are numbered left to right: the first view is the left eye.\n"
                "Exit codes: 0 ok, 1 usage, 2 unreadable input, 3 unsupported, 4 output.");
    CLI::Option* format = app->get_option("--format");
    return [o, format, app] {
        o->formatGiven = format->count() > 0;
        o->quiltGiven = app->get_option("--quilt")->count() > 0;
        o->depthPositionGiven = app->get_option("--rgbd-depth-position")->count() > 0;
        o->depthinessGiven = app->get_option("--depthiness")->count() > 0;
        o->focusGiven = app->get_option("--focus")->count() > 0;
        o->calibrationGiven = app->get_option("--lenticular-calibration")->count() > 0;
        return runCompose(*o);
    };
});

}  // namespace
}  // namespace mvr::cli
