// tools/cli/options.h — options shared by `mvr render`, `mvr bench` and `mvr view`: the scene
// (models, --grid), the rig (--views/--view-grid, --rig, --interaxial/--separation,
// --convergence, --fov), the image (--size, --shading, --cull, --wireframe) and the backend.
#pragma once

#include <atomic>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "mvr/backends.h"
#include "mvr/composite/compose.h"
#include "mvr/core/animation.h"
#include "mvr/core/displays.h"
#include "mvr/core/render.h"
#include "mvr/core/rig.h"
#include "mvr/core/scene.h"
#include "mvr/core/status.h"
#include "mvr/session/prepare.h"
#include "mvr/session/recipe.h"

namespace mvr::cli {

/// A scene, rig and settings ready to render (the session library's, mvr/session/prepare.h).
using Prepared = session::Prepared;
using session::ComfortReport;
using session::comfortJson;
using session::comfortReport;
using session::displayOutputs;
using session::parseSize;
using session::renderWarnings;
using session::ScreenComfortReport;
using session::screenComfortReport;

/// The options of the scene, the rig and the image; prepare() maps them onto a
/// session::RenderRecipe and prepares that.
struct SceneOptions {
    std::vector<std::string> models;
    int grid = 1;
    std::string namedScene = "default";  ///< --scene: default | village (without models)
    int views = 2;
    std::string viewGrid;  ///< "CxR", overrides --views
    std::string rig = "offaxis";
    std::optional<double> interaxial;
    std::optional<double> separation;
    std::optional<double> viewCone;  ///< --view-cone DEG
    /// The view cone of a --lenticular-calibration visual.json ("viewCone"), set by the command
    /// before prepare(): the default cone where a preset's would apply (a preset given, or an
    /// off-axis row of more than two views without --interaxial/--separation); --view-cone wins.
    std::optional<double> calibrationViewCone;
    std::optional<double> convergence;
    double fov = 45.0;
    std::string size = "1024x768";
    std::string shading = "vertex";
    std::string specular = "center";  ///< --specular
    bool cullBackFaces = false;
    bool wireframe = false;
    bool shadows = false;                     ///< --shadows (issue 15, shadows.h)
    int shadowMapSize = 1024;                 ///< --shadow-map-size
    std::optional<int> aa;                    ///< --aa N (session/sampling.h)
    int synthesize = 1;                       ///< --synthesize K (core/synthesize.h)
    int billboards = 0;                       ///< --billboards N (billboards.h)
    double billboardSize = 0;                 ///< --billboard-size; 0: 3 % of the scene's radius
    std::string display;                      ///< --display NAME (displays.h); "" = none
    std::optional<double> screenWidthCm;      ///< --screen-width CM
    std::optional<double> viewingDistanceCm;  ///< --viewing-distance CM
    session::ScreenRecipe screen;             ///< --rig screen: --screen-mm, --eyes, ...
    bool convergenceAuto = false;             ///< --convergence auto
    std::optional<double> exposure;           ///< --exposure EV (stops; framing.h)
    bool exposureAuto = false;                ///< --exposure auto
    std::string tonemap = "auto";             ///< --tonemap
    std::string environment;                  ///< --environment
    bool separationAuto = false;              ///< --separation auto
    std::optional<double> depthPercent;       ///< --depth-percent P (with --separation auto)
    /// The options a preset fills in; one given on the command line (count() > 0) overrides
    /// the preset's value. Null (SceneOptions filled in by code): never given.
    CLI::Option *viewsOption = nullptr, *viewGridOption = nullptr, *sizeOption = nullptr,
                *viewConeOption = nullptr;
    // Appended (issue 14): a model file's camera is the centre camera unless --no-file-camera;
    // its yfov unless --fov is given (fovGiven).
    bool fovGiven = false;
    bool noFileCamera = false;
    session::CameraRecipe camera;  ///< --azimuth ... --camera-matrix, --focal-length-mm
    bool strict = false;           ///< --strict: a missing texture is an error
    std::string background;        ///< --background R,G,B | #RRGGBB

    /// Adds the options to a subcommand. `withModels`: also the positional MODEL... list.
    void addTo(CLI::App* app, bool withModels = true);
    /// The recipe of these options (the scene, rig and image fields; a preset's options given
    /// on the command line as given).
    session::RenderRecipe recipe() const;
    /// Loads the models (or the default scene), builds the rig and settings; validates all
    /// (session::prepare() of recipe()).
    Result<Prepared> prepare() const;
};

/// How far each view is from a reference render: the share of its pixels with an RGB channel
/// more than kArtifactThreshold / 255 off (the conformance suite's and src/gl/README.md's
/// "wrong pixels") and the largest channel difference. `mvr render --check` and the sorbier
/// bench's artifact column both report it.
inline constexpr int kArtifactThreshold = 2;
struct ViewDifference {
    long differing = 0;  ///< pixels off by more than kArtifactThreshold
    long pixels = 0;     ///< pixels of the view
    int maxDelta = 0;
    double percent() const { return pixels > 0 ? 100.0 * double(differing) / double(pixels) : 0; }
};
std::vector<ViewDifference> viewDifferences(const std::vector<Image>& views,
                                            const std::vector<Image>& reference);

/// "mvr: rendering 2 views ... 3.5 s" on stderr while a long step runs: only when stderr is a
/// terminal, only once the step has taken about two seconds, erased when it ends (RAII).
/// `MVR_PROGRESS_AFTER_MS` changes the two seconds (tests).
class TerminalProgress {
public:
    explicit TerminalProgress(std::string what);
    ~TerminalProgress() { stop(); }
    /// Erases the line and ends the thread (idempotent); fail() calls it before its error line.
    void stop();
    TerminalProgress(const TerminalProgress&) = delete;
    TerminalProgress& operator=(const TerminalProgress&) = delete;

private:
    std::string mWhat;
    std::mutex mMutex;
    std::condition_variable mWake;
    bool mDone = false;
    std::thread mThread;
};

/// Prints "error: <message>" on stderr and returns the exit code of its category.
int fail(const Status& status);

}  // namespace mvr::cli
