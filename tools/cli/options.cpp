#include "options.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <regex>

#include <glm/gtc/matrix_transform.hpp>

#include <fmt/core.h>

#include "mvr/adelson/village_scene.h"
#include "mvr/core/billboards.h"
#include "mvr/core/displays.h"
#include "mvr/core/framing.h"
#include "mvr/core/scene_io.h"

#include "display_options.h"

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
    const std::string adjacent = rig.columns > 2
                                     ? fmt::format(", between adjacent views {:+.2f}% .. {:+.2f}%",
                                                   100.0 * r.minParallax / (rig.columns - 1),
                                                   100.0 * r.maxParallax / (rig.columns - 1))
                                     : std::string();
    report.line = fmt::format(
        "parallax between outer views: {:+.2f}% .. {:+.2f}% of screen width{} ({})",
        100.0 * r.minParallax, 100.0 * r.maxParallax, adjacent,
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

namespace {

/// --convergence auto / --separation auto (docs/displays.md): a depth pre-pass of the centre
/// view; the convergence balances the parallax in and out of the screen (balancedConvergence),
/// the separation fills 95 % of the screen's budget with the parallax between the eyes' views.
Status chooseAutoRig(Prepared& out, FramingParams& params, bool convergenceAuto,
                     bool separationAuto) {
    const char* what = convergenceAuto ? "--convergence auto" : "--separation auto";
    const float aspect =
        params.aspect.value_or(float(out.settings.width) / float(out.settings.height));
    const Camera camera = centreCamera(out.scene, params, aspect);  // frameScene()'s camera
    auto depth = centreDepthPrepass(out.scene, camera, out.settings);
    if (!depth) return depth.status();
    if (!*depth) {
        return usageError(
            fmt::format("{}: the centre view sees nothing of {} (its depth pre-pass is empty)",
                        what, out.sceneName));
    }
    const DepthPercentiles& d = **depth;
    if (convergenceAuto) {
        const float c = balancedConvergence(d.nearest, d.farthest);
        params.convergence = c;
        out.notes.push_back(fmt::format(
            "note: --convergence auto chose {:.4g}: the harmonic mean of the distances the "
            "centre view sees ({:.4g} .. {:.4g}, 1st .. 99th percentile), which balances the "
            "parallax in and out of the screen",
            c, d.nearest, d.farthest));
    }
    if (separationAuto) {
        FramingParams trial = params;
        trial.interaxial.reset();
        trial.viewConeDegrees = 0.0f;
        trial.separation = 0.01f;
        auto framed = frameScene(out.scene, trial, out.settings);
        if (!framed) return framed.status();
        const Rig& rig = framed->rig;
        if (rig.columns < 2) {
            return usageError("--separation auto needs a row of at least two views");
        }
        const ParallaxRange r = parallaxRange(rig, d.minimum, d.maximum);
        const float share = 1.0f / float(rig.columns - 1);  // adjacent views: the eyes' pair
        const float worst = std::max(std::abs(r.minParallax), std::abs(r.maxParallax)) * share;
        const ParallaxBudget budget = parallaxBudget(*out.screen);
        if (worst > 0.0f && std::isfinite(worst)) {
            const float s = 0.01f * 0.95f * budget.fraction / worst;
            params.separation = s;
            params.interaxial.reset();
            params.viewConeDegrees = 0.0f;
            out.notes.push_back(fmt::format(
                "note: --separation auto chose {:.3g}% of the screen width: the largest parallax "
                "between adjacent views is then 95% of the {:.2f} cm budget ({} eye separation "
                "on a {:.4g} cm screen)",
                100.0 * s, budget.fraction * out.screen->widthCm,
                budget.desktop ? "half the" : "the", out.screen->widthCm));
        } else {
            out.notes.push_back(
                "note: --separation auto: the scene lies on the convergence plane (no parallax "
                "at any separation); the default spacing is kept");
        }
    }
    return {};
}

/// --exposure EV | auto (framing.h's exposeLights), and the warning for a model file's lights
/// that saturate the scene's centre when no exposure is given.
Status applyExposure(Prepared& out, std::optional<double> ev, bool isAuto, bool fromFiles) {
    if (ev && (!std::isfinite(*ev) || std::abs(*ev) > 64.0)) {
        return usageError(fmt::format(
            "--exposure {} is out of range (expected -64..64 stops, or auto)", *ev));
    }
    const float peak = brightestLightAt(out.scene, out.scene.bounds().center());
    if (isAuto) {
        if (!(peak > 0.0f) || !std::isfinite(peak)) {
            return usageError(fmt::format(
                "--exposure auto: the lights of {} do not reach the scene's centre (nothing to "
                "measure; give --exposure EV)",
                out.sceneName));
        }
        const float chosen = -std::log2(peak);
        exposeLights(out.scene, chosen);
        out.notes.push_back(fmt::format(
            "note: --exposure auto chose {:+.3g} EV: the brightest light lit the scene's centre "
            "at {:.4g}x full colour, now 1x",
            chosen, peak));
    } else if (ev) {
        exposeLights(out.scene, float(*ev));
    } else if (fromFiles && peak > 8.0f && std::isfinite(peak)) {
        out.notes.push_back(fmt::format(
            "warning: the lights of {} light the scene's centre at {:.3g}x full colour "
            "(photometric units, as Blender's exporter writes them?): surfaces saturate; "
            "--exposure auto scales them to 1x, --exposure EV by 2^EV",
            out.sceneName, peak));
    }
    return {};
}

}  // namespace

void SceneOptions::addTo(CLI::App* app, bool withModels) {
    if (withModels) {
        app->add_option(
            "models", models,
            "Model files (OBJ, PLY, glTF 2.0 .gltf/.glb; glTF and OBJ+MTL keep their nodes, "
            "materials, textures, lights and camera), each optionally placed: "
            "FILE@X,Y,Z[,SCALE[,YAW]] (position, uniform scale, degrees about +Y; e.g. "
            "chair.glb@2,0,-1,0.5,90). None: the procedural default scene");
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
    viewsOption = views_;
    viewGridOption = app->add_option("--view-grid", viewGrid,
                                     "CxR grid of views, numbered left to right, top to bottom")
                         ->excludes(views_);
    app->add_option("--rig", rig, "Rig: offaxis (asymmetric frustums), toein or parallel")
        ->default_val(rig);
    auto* ia =
        app->add_option("--interaxial", interaxial,
                        "Distance between adjacent eyes, world units (default: convergence / 30)");
    // A number or `auto` (--convergence and --separation): the number goes to the optional
    // double (prepare() checks its range), `auto` to the flag.
    auto numberOrAuto = [](const char* name, std::optional<double>& value, bool& isAuto) {
        return [name, &value, &isAuto](const std::string& text) {
            if (text == "auto") {
                isAuto = true;
                value.reset();
                return;
            }
            try {
                std::size_t used = 0;
                const double v = std::stod(text, &used);
                if (used != text.size()) throw std::invalid_argument(text);
                value = v;
                isAuto = false;
            } catch (const std::exception&) {
                throw CLI::ValidationError(
                    name, fmt::format("'{}' is not a number (expected a number or auto)", text));
            }
        };
    };
    app->add_option_function<std::string>(
           "--separation", numberOrAuto("--separation", separation, separationAuto),
           "Interaxial as a fraction of the screen width at the convergence plane "
           "(nvidia-gtc2010); auto: the largest that keeps the parallax between the eyes' views "
           "within the screen's budget (needs --screen-width; docs/displays.md)")
        ->type_name("FLOAT|auto")
        ->excludes(ia);
    viewConeOption =
        app->add_option(
               "--view-cone", viewCone,
               "Spread a row of views evenly in angle over this cone, degrees (the Looking "
               "Glass camera: view i at angle -cone/2 + cone*i/(N-1) seen from the "
               "convergence plane; e.g. 40); excludes --interaxial and --separation")
            ->excludes(ia);
    app->add_option_function<std::string>(
           "--convergence", numberOrAuto("--convergence", convergence, convergenceAuto),
           "Distance of the zero-parallax plane, world units (default: distance to the scene "
           "center); auto: from a depth pre-pass of the centre view, the harmonic mean of the "
           "1st and 99th percentile distances (balances the parallax in and out of the screen)")
        ->type_name("FLOAT|auto");
    app->add_option("--fov", fov,
                    "Vertical field of view, degrees (default: a model file's camera's, else 45)")
        ->default_val(fov)
        ->each([this](const std::string&) { fovGiven = true; });
    app->add_flag("--no-file-camera", noFileCamera,
                  "Frame the scene's bounds instead of using the model file's camera");
    app->add_option_function<std::string>(
           "--exposure", numberOrAuto("--exposure", exposure, exposureAuto),
           "Scale every light by 2^EV (stops). Lights are in glTF's units with no tone "
           "mapping: 1 lux (1 cd at 1 unit) lights a surface at its full colour; files in "
           "photometric units (Blender's exporter) saturate. auto: the brightest light lights "
           "the scene's centre at full colour")
        ->type_name("EV|auto");
    sizeOption = app->add_option("--size", size, "Size of one view, WxH pixels")->default_val(size);
    std::string displayHelp =
        "Render for a display (`mvr info --displays` lists them): its views, view size, view "
        "cone and output (a quilt; with --lenticular-calibration also lenticular). Options given "
        "on the command line (--views, --size, --view-cone, --quilt, spacing) override the "
        "preset's. One of:";
    for (const std::string& n : displayNames()) displayHelp += " " + n;
    app->add_option("--display", display, displayHelp);
    app->add_option("--screen-width", screenWidthCm,
                    "Width of the picture on the screen, cm: the comfort report in cm against the "
                    "6.5 cm interocular budget (docs/displays.md)");
    app->add_option("--viewing-distance", viewingDistanceCm,
                    "Eyes to screen, cm (with --screen-width): vergence angles; nearer than 100 "
                    "cm the budget is half the eye separation (desktop, nvidia-gtc2010)");
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

namespace {

/// FILE@X,Y,Z[,SCALE[,YAW]]: a file that exists under the whole name is never split.
Result<std::pair<std::string, std::optional<Placement>>> parseModelArg(const std::string& arg) {
    std::error_code ec;
    const std::size_t at = arg.rfind('@');
    if (at == std::string::npos || std::filesystem::exists(arg, ec))
        return std::pair<std::string, std::optional<Placement>>{arg, std::nullopt};
    const std::string file = arg.substr(0, at), spec = arg.substr(at + 1);
    static const std::regex kNumber(R"(\s*[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?\s*)");
    std::vector<double> values;
    std::size_t start = 0;
    bool ok = true;
    for (;;) {
        const std::size_t comma = spec.find(',', start);
        const std::string part = spec.substr(start, comma - start);
        if (!std::regex_match(part, kNumber)) {
            ok = false;
            break;
        }
        values.push_back(std::strtod(part.c_str(), nullptr));
        if (comma == std::string::npos) break;
        start = comma + 1;
    }
    const auto bad = [&](const std::string& why) {
        return usageError(
            fmt::format("model '{}': placement '{}' {} (expected "
                        "FILE@X,Y,Z[,SCALE[,YAW]], e.g. model.obj@1,0,-2,0.5,90)",
                        arg, spec, why));
    };
    if (!ok) return bad("is not a list of numbers");
    if (values.size() < 3 || values.size() > 5)
        return bad(fmt::format("has {} numbers", values.size()));
    for (double v : values)
        if (!std::isfinite(v) || std::abs(v) > 1e30) return bad("has a number out of range");
    Placement p;
    p.position = glm::vec3(float(values[0]), float(values[1]), float(values[2]));
    if (values.size() > 3) p.scale = float(values[3]);
    if (values.size() > 4) p.yawDegrees = float(values[4]);
    if (!(p.scale > 0.0f)) return bad("has a scale that is not > 0");
    return std::pair<std::string, std::optional<Placement>>{file, p};
}

/// The models of the command line as one scene. Models without materials of their own (PLY,
/// OBJ without mtllib) and without placements keep the old path exactly: one merged mesh each,
/// laid out together by makeGridScene(). Otherwise each file is its scene (scene_io.h), placed,
/// and --grid K lays out K copies of the whole combined scene (the file camera is then not
/// used: it framed one copy).
Result<Scene> loadModels(const std::vector<std::string>& args, int grid, std::string& name,
                         std::optional<SceneAnimation>& animation) {
    std::vector<Scene> scenes;
    std::vector<std::optional<Placement>> placements;
    std::vector<SceneLoadInfo> infos;
    bool plain = true;
    for (const std::string& arg : args) {
        auto parsed = parseModelArg(arg);
        if (!parsed) return parsed.status();
        SceneLoadInfo info;
        auto scene = loadScene(parsed->first, &info);
        if (!scene) return scene.status();
        for (const std::string& w : info.warnings) fmt::print(stderr, "warning: {}\n", w);
        plain = plain && !info.fromMaterials && !parsed->second;
        scenes.push_back(std::move(scene).value());
        placements.push_back(parsed->second);
        infos.push_back(std::move(info));
        name += (name.empty() ? "" : " + ") + parsed->first;
    }
    if (plain) {
        std::vector<Mesh> meshes;
        for (Scene& s : scenes) meshes.push_back(std::move(s.meshes[0]));
        return makeGridScene(std::move(meshes), grid);
    }
    Scene combined;
    std::vector<Light> fileLights;
    for (std::size_t i = 0; i < scenes.size(); ++i) {
        Scene& s = scenes[i];
        if (!infos[i].fromMaterials) {  // a plain mesh among scenes: the grid's first color
            for (Instance& inst : s.instances) inst.material = Material{{0.85f, 0.75f, 0.6f}, 0.3f};
        }
        if (infos[i].lightsFromFile)
            fileLights.insert(fileLights.end(), s.lights.begin(), s.lights.end());
        s.lights.clear();
        if (placements[i]) transformScene(s, placements[i]->matrix());
        if (infos[i].animation && animation) {
            fmt::print(stderr, "warning: {}: its animation is not played (only the first "
                       "animated model's is)\n", args[i]);
        } else if (infos[i].animation) {
            // The first animated model's animation, its instances numbered in the combination.
            animation = std::move(infos[i].animation);
            if (placements[i]) transformAnimation(*animation, placements[i]->matrix());
            for (SceneAnimation::Target& t : animation->instances)
                t.instance += int(combined.instances.size());
            if (combined.camera) animation->cameraNode = -1;  // an earlier file's camera
        }
        appendScene(combined, std::move(s));
    }
    if (fileLights.size() > std::size_t(kMaxLights)) {
        fmt::print(stderr, "warning: {} lights in the models: the first {} are used\n",
                   fileLights.size(), kMaxLights);
        fileLights.resize(kMaxLights);
    }
    combined.lights = fileLights.empty() ? defaultLights() : fileLights;
    if (grid > 1) {
        const Bounds b = combined.bounds();
        const glm::vec3 size = b.max - b.min;
        const float spacing = std::max({size.x, size.y, 1e-6f}) * 1.1f;
        const int columns = static_cast<int>(std::ceil(std::sqrt(double(grid))));
        const int rows = (grid + columns - 1) / columns;
        const std::vector<Instance> one = combined.instances;
        combined.instances.clear();
        std::vector<SceneAnimation::Target> targets;
        for (int k = 0; k < grid; ++k) {
            const glm::vec3 offset((k % columns - (columns - 1) * 0.5f) * spacing,
                                   ((rows - 1) * 0.5f - k / columns) * spacing, 0.0f);
            const glm::mat4 xf = glm::translate(glm::mat4(1.0f), offset - b.center());
            for (Instance inst : one) {
                inst.worldFromModel = xf * inst.worldFromModel;
                combined.instances.push_back(std::move(inst));
            }
            if (animation) {  // every copy plays the animation
                for (SceneAnimation::Target t : animation->instances) {
                    t.instance += k * int(one.size());
                    t.worldFromRoot = xf * t.worldFromRoot;
                    targets.push_back(t);
                }
            }
        }
        combined.camera.reset();
        if (animation) {
            animation->instances = std::move(targets);
            animation->cameraNode = -1;
        }
    }
    return combined;
}

}  // namespace

Result<Prepared> SceneOptions::prepare() const {
    Prepared out;
    // A display preset fills in what the command line did not give (displays.h).
    auto given = [](const CLI::Option* o) { return o != nullptr && o->count() > 0; };
    int nViews = views;
    std::string viewSize = size;
    std::optional<double> cone = viewCone;
    std::optional<float> aspect;
    if (!display.empty()) {
        auto d = findDisplay(display);
        if (!d) return usageError(fmt::format("--display {}: {}", display, d.status().message()));
        out.display = *d;
        if (!given(viewsOption) && !given(viewGridOption)) nViews = d->views;
        if (!given(sizeOption)) {
            viewSize = fmt::format("{}x{}", d->viewWidth, d->viewHeight);
            aspect = d->aspect;
        }
        if (!given(viewConeOption) && d->viewConeDegrees > 0.0f && !interaxial && !separation &&
            !separationAuto && viewGrid.empty() && rig == "offaxis")
            cone = d->viewConeDegrees;
    }
    // A calibration's viewCone is the panel's own: it replaces the preset's, and without a
    // preset it spreads a row of more than two views as a preset's would.
    if (calibrationViewCone && *calibrationViewCone > 0.0 && !given(viewConeOption) &&
        !interaxial && !separation && !separationAuto && viewGrid.empty() && rig == "offaxis" &&
        (out.display || nViews > 2)) {
        cone = *calibrationViewCone;
        out.notes.push_back(
            fmt::format("note: view cone {:g} degrees from the calibration's viewCone (--view-cone "
                        "overrides it)",
                        *cone));
    }
    for (const auto& [name, value] : {std::pair{"--screen-width", screenWidthCm},
                                      std::pair{"--viewing-distance", viewingDistanceCm}}) {
        if (value && (!std::isfinite(*value) || *value <= 0.0 || *value > 1e6)) {
            return usageError(fmt::format(
                "{} {} is out of range (expected a length in cm, 0 < cm <= 1e6)", name, *value));
        }
    }
    if (viewingDistanceCm && !screenWidthCm) {
        return usageError(fmt::format(
            "--viewing-distance {} needs --screen-width (the screen's width in cm)",
            *viewingDistanceCm));
    }
    if (screenWidthCm) {
        ScreenGeometry screen;
        screen.widthCm = float(*screenWidthCm);
        if (viewingDistanceCm) screen.viewingDistanceCm = float(*viewingDistanceCm);
        out.screen = screen;
    }
    if (separationAuto && !screenWidthCm) {
        return usageError(
            "--separation auto needs --screen-width CM (the budget is the 6.5 cm eye separation "
            "over the screen width)");
    }
    if (separationAuto && cone && given(viewConeOption)) {
        return usageError(fmt::format("--view-cone {} excludes --separation", *cone));
    }
    // Numbers first: they are cheap to check and the model may be large.
    auto sz = parseSize(viewSize, "--size");
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
        params.columns = nViews;
        params.rows = 1;
    }
    if (params.columns < 1 || params.rows < 1 || params.columns * params.rows > kMaxViews) {
        return usageError(fmt::format("{} {}: view count {} is out of range (expected 1..{})",
                                      viewGrid.empty() ? "--views" : "--view-grid",
                                      viewGrid.empty() ? fmt::format("{}", nViews) : viewGrid,
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
    if (cone) {
        if (!std::isfinite(*cone) || *cone <= 0.0 || *cone >= 180.0) {
            return usageError(fmt::format(
                "--view-cone {} is out of range (expected 0 < cone < 180 degrees)", *cone));
        }
        if (interaxial || separation) {
            return usageError(fmt::format("--view-cone {} excludes --{}", *cone,
                                          interaxial ? "interaxial" : "separation"));
        }
        if (!viewGrid.empty() || *kind != RigKind::OffAxis) {
            return usageError(fmt::format(
                "--view-cone {} needs an off-axis row of views (--views N, --rig offaxis)", *cone));
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
        auto loaded = loadModels(models, grid, out.sceneName, out.animation);
        if (!loaded) return loaded.status();
        out.scene = std::move(loaded).value();
    }
    if (Status s = validateScene(out.scene); !s) return s;
    if (Status s = applyExposure(out, exposure, exposureAuto, !models.empty()); !s) return s;

    // The camera, near/far, convergence and spacing: the library's framing (framing.h).
    params.fovYDegrees = static_cast<float>(fov);
    params.aspect = aspect;
    params.fovOverridesSceneCamera = fovGiven;
    params.useSceneCamera = !noFileCamera;
    if (out.animation && noFileCamera) out.animation->cameraNode = -1;
    if (interaxial) params.interaxial = static_cast<float>(*interaxial);
    if (separation) params.separation = static_cast<float>(*separation);
    if (convergence) params.convergence = static_cast<float>(*convergence);
    if (cone) params.viewConeDegrees = static_cast<float>(*cone);
    if (convergenceAuto || separationAuto) {
        if (Status s = chooseAutoRig(out, params, convergenceAuto, separationAuto); !s) return s;
    }
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
        if (cone) add(fmt::format("--view-cone {}", *cone));
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
    out.viewConeDegrees = params.viewConeDegrees;
    // No silent nonsense: a scene outside every view's frustum would give empty images.
    const std::vector<int> missing = viewsMissingScene(out.scene, out.rig);
    if (!missing.empty() && int(missing.size()) == out.rig.viewCount()) {
        return usageError(fmt::format(
            "{}: the scene lies entirely outside the frustum of every view (nothing would be "
            "drawn; check --separation / --interaxial / --convergence and the scene's camera)",
            out.sceneName));
    }
    if (!missing.empty()) {
        std::string list;
        for (std::size_t i = 0; i < missing.size() && i < 8; ++i)
            list += (i ? ", " : "") + std::to_string(missing[i]);
        if (missing.size() > 8) list += ", ...";
        out.notes.push_back(
            fmt::format("warning: {} of {} views see nothing of the scene (view{} {})",
                        missing.size(), out.rig.viewCount(), missing.size() == 1 ? "" : "s", list));
    }
    return out;
}

}  // namespace mvr::cli
