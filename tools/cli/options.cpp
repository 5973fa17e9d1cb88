#include "options.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <regex>

#include <fmt/core.h>

#include "mvr/adelson/village_scene.h"
#include "mvr/core/billboards.h"
#include "mvr/core/framing.h"

namespace mvr::cli {

namespace {
std::atomic<TerminalProgress*> sActiveProgress{nullptr};
}  // namespace

int fail(const Status& status) {
    if (TerminalProgress* p = sActiveProgress.load()) p->stop();  // the error on a line of its own
    fmt::print(stderr, "error: {}\n", status.message());
    const int code = exitCode(status.code());
    return code == 0 ? 1 : code;
}

TerminalProgress::TerminalProgress(std::string what) : mWhat(std::move(what)) {
    if (!::isatty(STDERR_FILENO)) return;
    sActiveProgress = this;
    int afterMs = 2000;
    if (const char* env = std::getenv("MVR_PROGRESS_AFTER_MS")) afterMs = std::atoi(env);
    mThread = std::thread([this, afterMs] {
        using namespace std::chrono;
        const auto start = steady_clock::now();
        std::unique_lock lock(mMutex);
        if (mWake.wait_for(lock, milliseconds(afterMs), [this] { return mDone; })) return;
        do {
            const double s = duration<double>(steady_clock::now() - start).count();
            fmt::print(stderr, "\rmvr: {} ... {:.1f} s", mWhat, s);
            std::fflush(stderr);
        } while (!mWake.wait_for(lock, milliseconds(250), [this] { return mDone; }));
        fmt::print(stderr, "\r\033[K");  // erase the line: the result follows on stdout
        std::fflush(stderr);
    });
}

void TerminalProgress::stop() {
    TerminalProgress* self = this;
    sActiveProgress.compare_exchange_strong(self, nullptr);
    if (!mThread.joinable()) return;
    {
        std::lock_guard lock(mMutex);
        mDone = true;
    }
    mWake.notify_all();
    mThread.join();
}

namespace {
/// Eye-space distance w of a window depth d in [0, 1) for a perspective near/far.
float distanceFromWindowDepth(float d, float near, float far) {
    const float z = 2.0f * d - 1.0f;
    return 2.0f * near * far / ((far + near) - z * (far - near));
}
}  // namespace

std::optional<ComfortReport> comfortReport(const Rig& rig, const RenderOutput& out) {
    if (out.depth.empty() || rig.columns <= 1) return std::nullopt;
    float dMin = 1.0f, dMax = 0.0f;
    for (float d : out.depth[0].depth) {
        if (d < 1.0f) {
            dMin = std::min(dMin, d);
            dMax = std::max(dMax, d);
        }
    }
    if (dMin > dMax) return std::nullopt;
    ComfortReport report;
    report.range =
        parallaxRange(rig, distanceFromWindowDepth(dMin, rig.camera.near, rig.camera.far),
                      distanceFromWindowDepth(dMax, rig.camera.near, rig.camera.far));
    const ParallaxRange& r = report.range;
    report.line = fmt::format(
        "parallax between outer views: {:+.2f}% .. {:+.2f}% of screen width ({})",
        100.0 * r.minParallax, 100.0 * r.maxParallax,
        r.comfortable ? std::string("comfortable: all within [convergence/2, 100 x convergence]")
                      : "uncomfortable: " + r.why);
    return report;
}

std::vector<ViewDifference> viewDifferences(const std::vector<Image>& views,
                                            const std::vector<Image>& reference) {
    std::vector<ViewDifference> out;
    for (std::size_t v = 0; v < views.size() && v < reference.size(); ++v) {
        const ImageDiff d = compareImages(views[v], reference[v], kArtifactThreshold);
        out.push_back({d.differingPixels, long(views[v].width) * views[v].height, d.maxDelta});
    }
    return out;
}

Result<std::pair<int, int>> parseSize(const std::string& text, const char* what) {
    static const std::regex kSize(R"(\s*(-?\d+)\s*[xX]\s*(-?\d+)\s*)");
    std::smatch m;
    if (!std::regex_match(text, m, kSize)) {
        return usageError(
            fmt::format("{} '{}' is not of the form WxH (e.g. 1024x768)", what, text));
    }
    long w = 0, h = 0;
    try {
        w = std::stol(m[1].str());
        h = std::stol(m[2].str());
    } catch (...) {
        return usageError(
            fmt::format("{} '{}' is out of range (expected 1..16384 each)", what, text));
    }
    if (w < 1 || h < 1 || w > 16384 || h > 16384) {
        return usageError(
            fmt::format("{} '{}' is out of range (expected 1..16384 each)", what, text));
    }
    return std::pair<int, int>{int(w), int(h)};
}

void SceneOptions::addTo(CLI::App* app, bool withModels) {
    if (withModels) {
        app->add_option("models", models,
                        "Model files (OBJ, PLY, glTF 2.0). None: the procedural default scene");
    }
    app->add_option("--scene", namedScene,
                    "Procedural scene when no model is given: default, village (adelson1991's "
                    "eight buildings) or textured (the default scene with generated textures)")
        ->default_val(namedScene);
    app->add_option("--grid", grid,
                    "Lay out K copies of the model(s) in a grid (sorbier2008: 1, 3, 5, 9)")
        ->default_val(grid);
    auto* views_ = app->add_option("--views", views, "Number of views in a horizontal row (1..128)")
                       ->default_val(views);
    app->add_option("--view-grid", viewGrid,
                    "CxR grid of views, numbered left to right, top to bottom")
        ->excludes(views_);
    app->add_option("--rig", rig, "Rig: offaxis (asymmetric frustums), toein or parallel")
        ->default_val(rig);
    auto* ia =
        app->add_option("--interaxial", interaxial,
                        "Distance between adjacent eyes, world units (default: convergence / 30)");
    app->add_option(
           "--separation", separation,
           "Interaxial as a fraction of the screen width at the convergence plane (nvidia-gtc2010)")
        ->excludes(ia);
    app->add_option("--view-cone", viewCone,
                    "Spread a row of views evenly in angle over this cone, degrees (the Looking "
                    "Glass camera: view i at angle -cone/2 + cone*i/(N-1) seen from the "
                    "convergence plane; e.g. 40); excludes --interaxial and --separation")
        ->excludes(ia);
    app->add_option(
        "--convergence", convergence,
        "Distance of the zero-parallax plane, world units (default: distance to the scene center)");
    app->add_option("--fov", fov, "Vertical field of view, degrees")->default_val(fov);
    app->add_option("--size", size, "Size of one view, WxH pixels")->default_val(size);
    app->add_option("--shading", shading, "Shading: flat, vertex (Gouraud) or pixel (per-fragment)")
        ->default_val(shading);
    app->add_flag("--cull", cullBackFaces, "Cull back faces");
    app->add_flag("--wireframe", wireframe, "Draw triangle edges only");
    app->add_flag("--shadows", shadows,
                  "Shadows: the key directional light and spot lights (or the lights a file "
                  "marks) cast shadows; one shadow map per light per frame, rendered once for "
                  "all views, 3x3 percentage-closer filtering");
    app->add_option("--shadow-map-size", shadowMapSize, "Shadow map texels per side (16..8192)")
        ->default_val(shadowMapSize);
    app->add_option("--billboards", billboards,
                    "Scatter N camera-facing particle quads through the scene's bounds, in planes "
                    "parallel to the screen (nvidia-gtc2010); textured with the scene's first "
                    "texture when it has one")
        ->default_val(billboards);
    app->add_option("--billboard-size", billboardSize,
                    "Side of each billboard, world units (default: 3 % of the scene's radius)");
}

Result<Prepared> SceneOptions::prepare() const {
    Prepared out;
    // Numbers first: they are cheap to check and the model may be large.
    auto sz = parseSize(size, "--size");
    if (!sz) return sz.status();
    out.settings.width = sz->first;
    out.settings.height = sz->second;
    auto sh = parseShading(shading);
    if (!sh) return usageError(fmt::format("--shading {}: {}", shading, sh.status().message()));
    out.settings.shading = *sh;
    out.settings.cullBackFaces = cullBackFaces;
    out.settings.wireframe = wireframe;
    if (shadowMapSize < 16 || shadowMapSize > 8192) {
        return usageError(
            fmt::format("--shadow-map-size {} is out of range (expected 16..8192)", shadowMapSize));
    }
    out.settings.shadows = shadows;
    out.settings.shadowMapSize = shadowMapSize;
    auto kind = parseRigKind(rig);
    if (!kind) return usageError(fmt::format("--rig {}: {}", rig, kind.status().message()));
    FramingParams params;
    params.kind = *kind;
    if (!viewGrid.empty()) {
        static const std::regex kGrid(R"(\s*(\d{1,3})\s*[xX]\s*(\d{1,3})\s*)");
        std::smatch m;
        if (!std::regex_match(viewGrid, m, kGrid)) {
            return usageError(
                fmt::format("--view-grid '{}' is not of the form CxR (e.g. 3x3)", viewGrid));
        }
        params.columns = std::stoi(m[1].str());
        params.rows = std::stoi(m[2].str());
    } else {
        params.columns = views;
        params.rows = 1;
    }
    if (params.columns < 1 || params.rows < 1 || params.columns * params.rows > kMaxViews) {
        return usageError(fmt::format("{} {}: view count {} is out of range (expected 1..{})",
                                      viewGrid.empty() ? "--views" : "--view-grid",
                                      viewGrid.empty() ? fmt::format("{}", views) : viewGrid,
                                      params.columns * params.rows, kMaxViews));
    }
    if (grid < 1 || grid > 1024) {
        return usageError(fmt::format("--grid {} is out of range (expected 1..1024 copies)", grid));
    }
    if (!std::isfinite(fov) || fov <= 0.0 || fov >= 180.0) {
        return usageError(
            fmt::format("--fov {} is out of range (expected 0 < fov < 180 degrees)", fov));
    }
    for (const auto& [name, value] :
         {std::pair{"--interaxial", interaxial}, std::pair{"--separation", separation},
          std::pair{"--convergence", convergence}}) {
        if (value && (!std::isfinite(*value) || *value < 0.0)) {
            return usageError(
                fmt::format("{} {} is out of range (expected a finite value >= 0)", name, *value));
        }
    }
    if (viewCone) {
        if (!std::isfinite(*viewCone) || *viewCone <= 0.0 || *viewCone >= 180.0) {
            return usageError(fmt::format(
                "--view-cone {} is out of range (expected 0 < cone < 180 degrees)", *viewCone));
        }
        if (interaxial || separation) {
            return usageError(fmt::format("--view-cone {} excludes --{}", *viewCone,
                                          interaxial ? "interaxial" : "separation"));
        }
        if (!viewGrid.empty() || *kind != RigKind::OffAxis) {
            return usageError(fmt::format(
                "--view-cone {} needs an off-axis row of views (--views N, --rig offaxis)",
                *viewCone));
        }
    }
    if (convergence && *convergence <= 0.0) {
        return usageError("--convergence 0 is out of range (expected a distance > 0)");
    }

    // The scene.
    if (namedScene != "default" && namedScene != "village" && namedScene != "textured") {
        return usageError(fmt::format(
            "--scene {} is not a known scene (expected default, village or textured)", namedScene));
    }
    if (namedScene != "default" && !models.empty()) {
        return usageError(
            fmt::format("--scene {} cannot be combined with model files", namedScene));
    }
    if (models.empty() && namedScene == "village") {
        out.scene = adelson::makeVillageScene();
        out.sceneName = "village scene";
        if (grid != 1) {
            return usageError(fmt::format(
                "--grid {} needs a model file (the village scene is not gridded)", grid));
        }
    } else if (models.empty() && namedScene == "textured") {
        out.scene = makeTexturedScene();
        out.sceneName = "textured scene";
        if (grid != 1) {
            return usageError(fmt::format(
                "--grid {} needs a model file (the textured scene is not gridded)", grid));
        }
    } else if (models.empty()) {
        out.scene = makeDefaultScene();
        out.sceneName = "default scene";
        if (grid != 1) {
            return usageError(fmt::format(
                "--grid {} needs a model file (the default scene is not gridded)", grid));
        }
    } else {
        std::vector<Mesh> meshes;
        for (const std::string& path : models) {
            auto mesh = loadMesh(path);
            if (!mesh) return mesh.status();
            meshes.push_back(std::move(mesh).value());
            out.sceneName += (out.sceneName.empty() ? "" : " + ") + path;
        }
        out.scene = makeGridScene(std::move(meshes), grid);
    }
    if (Status s = validateScene(out.scene); !s) return s;

    // The camera, near/far, convergence and spacing: the library's framing (framing.h).
    params.fovYDegrees = static_cast<float>(fov);
    if (interaxial) params.interaxial = static_cast<float>(*interaxial);
    if (separation) params.separation = static_cast<float>(*separation);
    if (convergence) params.convergence = static_cast<float>(*convergence);
    if (viewCone) params.viewConeDegrees = static_cast<float>(*viewCone);
    auto framed = frameScene(out.scene, params, out.settings);
    if (!framed && framed.status().code() == ErrorCode::Usage) {
        // The rig is a product of the options and the scene: name the options that shaped it
        // ("--interaxial 1e+30: view 0 has a non-finite matrix or shear"), else the models.
        std::string culprit;
        auto add = [&](const std::string& text) {
            culprit += (culprit.empty() ? "" : ", ") + text;
        };
        if (interaxial) add(fmt::format("--interaxial {}", *interaxial));
        if (separation) add(fmt::format("--separation {}", *separation));
        if (convergence) add(fmt::format("--convergence {}", *convergence));
        if (viewCone) add(fmt::format("--view-cone {}", *viewCone));
        if (fov != 45.0) add(fmt::format("--fov {}", fov));
        if (culprit.empty()) culprit = out.sceneName;
        return Status(framed.status().code(),
                      fmt::format("{}: {}", culprit, framed.status().message()));
    }
    if (!framed) return framed.status();  // the memory budget: its message names views and size
    out.rig = std::move(framed->rig);
    out.settings = framed->settings;
    // Billboards (issue 15): after the framing (they do not move the camera), facing it.
    if (billboards < 0 || billboards > 1000000) {
        return usageError(
            fmt::format("--billboards {} is out of range (expected 0..1000000)", billboards));
    }
    if (!std::isfinite(billboardSize) || billboardSize < 0.0) {
        return usageError(fmt::format(
            "--billboard-size {} is out of range (expected a finite size >= 0)", billboardSize));
    }
    if (billboards > 0) {
        const Bounds b = out.scene.bounds();
        const float side = billboardSize > 0.0 ? float(billboardSize) : 0.03f * b.radius();
        const auto list = scatterBillboards(b, billboards, side);
        appendBillboards(out.scene, list, out.rig.camera);
        if (Status s = validateScene(out.scene); !s) return s;
    }
    return out;
}

}  // namespace mvr::cli
