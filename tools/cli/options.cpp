#include "options.h"

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>

#include <fmt/core.h>

#include "mvr/core/displays.h"
#include "validators.h"

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

std::vector<ViewDifference> viewDifferences(const std::vector<Image>& views,
                                            const std::vector<Image>& reference) {
    std::vector<ViewDifference> out;
    for (std::size_t v = 0; v < views.size() && v < reference.size(); ++v) {
        const ImageDiff d = compareImages(views[v], reference[v], kArtifactThreshold);
        out.push_back({d.differingPixels, long(views[v].width) * views[v].height, d.maxDelta});
    }
    return out;
}

void SceneOptions::addTo(CLI::App* app, bool withModels) {
    if (withModels) {
        app->add_option(
            "models", models,
            "Model files (OBJ, PLY, glTF 2.0 .gltf/.glb; glTF and OBJ+MTL keep their nodes, "
            "materials, textures, lights and camera), each optionally placed: "
            "FILE@X,Y,Z[,SCALE[,YAW]] (position, uniform scale, degrees about +Y; |X|,|Y|,|Z| <= "
            "1e6, SCALE 1e-6..1e6, |YAW| <= 360; e.g. chair.glb@2,0,-1,0.5,90). None: the procedural default scene");
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
    app->add_option("--rig", rig,
                    "Rig: offaxis (asymmetric frustums), toein, parallel, or screen (a physical "
                    "screen and tracked eyes in mm: eye-tracked stereo monitors)")
        ->default_val(rig);
    app->add_option("--screen-mm", screen.size,
                    "--rig screen: the screen, WxH mm, centred, facing +Z (default: "
                    "--screen-width at the views' aspect, else 597.9x336.3, a 27-inch 16:9 panel)")
        ->check(nonEmpty("WxH in millimetres"));
    app->add_option("--screen-corners", screen.corners,
                    "--rig screen: a tilted screen by three corners, mm: lower-left;lower-right;"
                    "upper-left, each X,Y,Z")
        ->check(nonEmpty("three corners X,Y,Z separated by ';'"));
    app->add_option("--screen-tilt", screen.tiltDegrees,
                    "--rig screen: the screen leaning back, degrees, about its horizontal centre "
                    "line; the scene stays upright in the room (default: the display's, 45 for "
                    "Sony's, else 0)");
    app->add_option("--eyes", screen.eyes,
                    "--rig screen: the eyes in mm of screen space, LX,LY,LZ;RX,RY,RZ (a tracker's "
                    "reading)")
        ->check(nonEmpty("two points X,Y,Z separated by ';'"));
    app->add_option("--ipd-mm", screen.ipdMm,
                    "--rig screen: the eyes' distance, mm (default 63), about --head");
    app->add_option("--head", screen.head,
                    "--rig screen: the eyes' midpoint X,Y,Z mm (default 0,0,--viewing-distance "
                    "or 600 mm)")
        ->check(nonEmpty("X,Y,Z in millimetres"));
    app->add_option("--depth-factor", screen.depthFactor,
                    "--rig screen: the eyes' distance scaled about their midpoint (the SR "
                    "runtimes' Depth Factor; default 1)");
    app->add_option("--look-around", screen.lookAround,
                    "--rig screen: the head's movement from the default head scaled (the SR "
                    "runtimes' Look Around Factor; 0: fixed, default 1)");
    app->add_option("--eye-track", screen.eyeTrack,
                    "--rig screen, sequences: the eyes per frame, a CSV of t,lx,ly,lz,rx,ry,rz "
                    "(s, mm; interpolated at f/--fps; docs/displays.md)")
        ->check(nonEmpty("a CSV file"));
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
           "within the screen's budget, at infinity and over the scene (needs --screen-width; "
           "--depth-percent; docs/displays.md)")
        ->type_name("FLOAT|auto")
        ->excludes(ia);
    app->add_option("--depth-percent", depthPercent,
                    "With --separation auto: the largest parallax the eyes meet (at infinity, at "
                    "the scene's nearest and farthest points) as a percentage of the screen's "
                    "budget, 0 < P <= 100 (default 100: fill it; docs/displays.md)")
        ->check(positiveAtMost(100));
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
    app->add_flag("--strict", strict,
                  "A model's texture file that is missing is an error (default: a warning, "
                  "the material's base colour used)");
    // The viewpoint (mvr/session/camera.h): orbit-style, eye and look-at, or a matrix.
    app->add_option("--azimuth", camera.azimuth,
                    "View the scene from this angle about +Y, degrees (0: from +Z, the default "
                    "framing; 90: from +X), at --distance from --target");
    app->add_option("--elevation", camera.elevation,
                    "...and from this angle above the horizontal plane, degrees (-90..90)");
    app->add_option_function<std::string>(
           "--distance",
           [this](const std::string& text) {
               if (text == "auto") return camera.distance.reset();
               try {
                   std::size_t used = 0;
                   camera.distance = std::stod(text, &used);
                   if (used == text.size()) return;
               } catch (const std::exception&) {
               }
               throw CLI::ValidationError("--distance",
                                          fmt::format("'{}' is not a number or auto", text));
           },
           "...from the target, world units; auto (default): the whole scene in view")
        ->type_name("D|auto");
    app->add_option("--target", camera.target,
                    "The point the orbit-style camera looks at, X,Y,Z, or centre (default)");
    app->add_option("--camera-position", camera.position,
                    "The camera's eye, X,Y,Z (with --look-at, default the scene's centre, and "
                    "--up, default 0,1,0)");
    app->add_option("--look-at", camera.lookAt, "The point the camera looks at, X,Y,Z");
    app->add_option("--up", camera.up, "The camera's up direction, X,Y,Z");
    app->add_option("--camera-matrix", camera.matrix,
                    "The camera as a 4x4 world-from-camera matrix, row-major (looking down its "
                    "-Z, +Y up): 16 numbers, or a file holding them");
    app->add_option("--focal-length-mm", camera.focalLengthMm,
                    "Field of view from a lens: focal length on a --sensor-width-mm sensor "
                    "(the horizontal field of view); excludes --fov");
    app->add_option("--sensor-width-mm", camera.sensorWidthMm,
                    "Sensor width for --focal-length-mm")
        ->default_val(camera.sensorWidthMm);
    app->add_option("--background", background,
                    "Background colour: R,G,B in 0..1, or #RRGGBB (default: the scene's), or "
                    "transparent (alpha 0 where nothing is drawn, in the PNGs)");
    app->add_option_function<std::string>(
           "--exposure", numberOrAuto("--exposure", exposure, exposureAuto),
           "Scale every light by 2^EV (stops). Lights are in glTF's units with no tone "
           "mapping: 1 lux (1 cd at 1 unit) lights a surface at its full colour; files in "
           "photometric units (Blender's exporter) saturate. auto: the brightest light lights "
           "the scene's centre at full colour")
        ->type_name("EV|auto");
    app->add_option("--tonemap", tonemap,
                    "Tone mapping of the lit colours: none (clamped), khr-neutral (Khronos PBR "
                    "Neutral) or aces (Narkowicz's ACES fit); auto: khr-neutral when a model "
                    "file's own lights (physical units) light the scene, else none")
        ->default_val(tonemap)
        ->type_name("none|khr-neutral|aces|auto");
    app->add_option("--environment", environment,
                    "Light the scene with an environment map (image lighting: diffuse and "
                    "glossy reflections, in place of the constant ambient): Radiance .hdr, "
                    "OpenEXR, PNG or JPEG, equirectangular (2:1) or a horizontal cube cross "
                    "(4:3), scaled by --exposure as the lights are")
        ->type_name("MAP");
    sizeOption = app->add_option("--size", size, "Size of one view, WxH pixels")->default_val(size);
    std::string displayHelp =
        "Render for a display (`mvr info --displays` lists them): its views, view size, view "
        "cone and output (a quilt; with --lenticular-calibration also lenticular). Options given "
        "on the command line (--views, --size, --view-cone, --quilt, spacing) override the "
        "preset's. One of:";
    for (const std::string& n : displayNames()) displayHelp += " " + n;
    app->add_option("--display", display, displayHelp)
        ->check(nonEmpty("a display name; `mvr info --displays` lists them"));
    app->add_option("--screen-width", screenWidthCm,
                    "Width of the picture on the screen, cm: the comfort report in cm against the "
                    "6.5 cm interocular budget (docs/displays.md)");
    app->add_option("--viewing-distance", viewingDistanceCm,
                    "Eyes to screen, cm (with --screen-width): vergence angles; nearer than 100 "
                    "cm the budget is half the eye separation (desktop, nvidia-gtc2010)");
    app->add_option("--shading", shading, "Shading: flat, vertex (Gouraud) or pixel (per-fragment)")
        ->default_val(shading);
    app->add_option("--specular", specular,
                    "Whose eye the highlights are seen from: center (the rig's centre eye, "
                    "shading shared by every view) or per-view (each view's own eye, per pixel: "
                    "highlights move between views as on a real surface)")
        ->default_val(specular)
        ->type_name("center|per-view");
    app->add_flag("--cull", cullBackFaces, "Cull back faces");
    app->add_flag("--wireframe", wireframe, "Draw triangle edges only");
    app->add_flag("--shadows", shadows,
                  "Shadows: the key directional light and spot lights (or the lights a file "
                  "marks) cast shadows; one shadow map per light per frame, rendered once for "
                  "all views, 3x3 percentage-closer filtering");
    app->add_option("--shadow-map-size", shadowMapSize, "Shadow map texels per side (16..8192)")
        ->default_val(shadowMapSize);
    app->add_option("--aa", aa,
                    "Anti-aliasing: N samples a pixel, 1, 2, 4 or 8, at the standard multisample "
                    "positions, resolved to the output (default 4 for light-field --display "
                    "presets, else 1: plain renders and the benches keep one sample)");
    app->add_option("--synthesize", synthesize,
                    "View synthesis: render every K-th view of each row (and its last) exactly and "
                    "warp the views between from their depth (an off-axis rig of 3 or more views "
                    "a row; 1, the default: every view exact). --check prints each warped "
                    "view's PSNR against its exact render");
    app->add_option("--billboards", billboards,
                    "Scatter N camera-facing particle quads through the scene's bounds, in planes "
                    "parallel to the screen (nvidia-gtc2010); textured with the scene's first "
                    "texture when it has one")
        ->default_val(billboards);
    app->add_option("--billboard-size", billboardSize,
                    "Side of each billboard, world units (default: 3 % of the scene's radius)");
}

session::RenderRecipe SceneOptions::recipe() const {
    auto given = [](const CLI::Option* o) { return o != nullptr && o->count() > 0; };
    session::RenderRecipe r;
    r.models = models;
    r.scene = namedScene;
    r.grid = grid;
    r.noFileCamera = noFileCamera;
    r.camera = camera;
    r.strict = strict;
    r.background = background;
    r.exposure = exposure;
    r.exposureAuto = exposureAuto;
    r.tonemap = tonemap;
    r.environment = environment;
    r.billboards = billboards;
    r.billboardSize = billboardSize;
    // Without a preset the values are the ones to use; with one, those given on the command
    // line override its values (filled in by code, never given).
    if (display.empty() || given(viewsOption)) r.views = views;
    r.viewGrid = viewGrid;
    r.display = display;
    r.rig = rig;
    r.interaxial = interaxial;
    r.separation = separation;
    r.separationAuto = separationAuto;
    r.depthPercent = depthPercent;
    r.convergence = convergence;
    r.convergenceAuto = convergenceAuto;
    r.viewCone = viewCone;
    r.calibrationViewCone = calibrationViewCone;
    if (fovGiven || fov != 45.0) r.fov = fov;
    r.screenWidthCm = screenWidthCm;
    r.viewingDistanceCm = viewingDistanceCm;
    r.screen = screen;
    if (display.empty() || given(sizeOption)) r.size = size;
    r.shading = shading;
    r.specular = specular;
    r.cull = cullBackFaces;
    r.wireframe = wireframe;
    r.shadows = shadows;
    r.shadowMapSize = shadowMapSize;
    r.aa = aa;
    r.synthesize = synthesize;
    return r;
}

Result<Prepared> SceneOptions::prepare() const {
    // The benches time the views with their depth images (as bench/README.md's figures were).
    auto p = session::prepare(recipe());
    if (p) p->settings.depth = true;
    return p;
}

}  // namespace mvr::cli
