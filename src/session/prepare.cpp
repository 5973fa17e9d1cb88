// src/session/prepare.cpp — prepare(): a RenderRecipe's scene, rig and settings, validated
// (mvr/session/prepare.h). The checks and their messages are `mvr render`'s: they name its
// options, which the Python keywords and the viewer's options mirror.
#include "mvr/session/prepare.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <mutex>
#include <regex>

#include <glm/gtc/matrix_transform.hpp>

#include <fmt/core.h>

#include "mvr/adelson/village_scene.h"
#include "mvr/core/billboards.h"
#include "mvr/core/displays.h"
#include "mvr/core/environment.h"
#include "mvr/core/framing.h"
#include "mvr/io/png.h"
#include "mvr/io/scene_io.h"
#include "mvr/session/camera.h"
#include "mvr/session/cone_depth.h"
#include "mvr/session/screen.h"
#include "mvr/session/outputs.h"
#include "mvr/session/surfaces.h"
#include "mvr/session/sampling.h"
#include "mvr/session/view_range.h"

namespace mvr::session {

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

/// A file's camera that cuts off part of the scene (Khronos's 2CylinderEngine at the bottom of
/// a 16:9 turntable): the scene's vertices in front of the camera reach beyond its frame on one
/// side but not on the opposite one (a ground plane or a room that fills the frame reaches
/// beyond both: not a crop), for more than 0.5 % of them. Said with the sides and the way out.
/// At most ~200 000 vertices are looked at.
std::optional<std::string> fileCameraCropWarning(const Scene& scene, const Camera& camera) {
    const glm::mat4 clipFromWorld = camera.clipFromView() * camera.viewFromWorld();
    std::size_t total = 0;
    for (const Instance& inst : scene.instances) {
        if (inst.mesh >= 0 && std::size_t(inst.mesh) < scene.meshes.size())
            total += scene.meshes[std::size_t(inst.mesh)].positions.size();
    }
    const std::size_t stride = std::max<std::size_t>(1, total / 200000);
    std::size_t seen = 0, outside = 0;
    bool beyond[4] = {false, false, false, false};  // left, right, bottom, top
    for (const Instance& inst : scene.instances) {
        if (inst.mesh < 0 || std::size_t(inst.mesh) >= scene.meshes.size()) continue;
        const glm::mat4 m = clipFromWorld * inst.worldFromModel;
        const auto& positions = scene.meshes[std::size_t(inst.mesh)].positions;
        for (std::size_t i = 0; i < positions.size(); i += stride) {
            const glm::vec4 c = m * glm::vec4(positions[i], 1.0f);
            if (!(c.w > 0.0f)) continue;  // behind the camera: an interior, not a crop
            ++seen;
            const bool side[4] = {c.x < -c.w, c.x > c.w, c.y < -c.w, c.y > c.w};
            if (side[0] || side[1] || side[2] || side[3]) ++outside;
            for (int k = 0; k < 4; ++k) beyond[k] = beyond[k] || side[k];
        }
    }
    if (seen == 0 || outside * 200 <= seen) return std::nullopt;
    static constexpr const char* kSide[4] = {"left", "right", "bottom", "top"};
    std::string sides;
    for (int axis = 0; axis < 2; ++axis) {
        for (int k = 2 * axis; k < 2 * axis + 2; ++k) {
            if (beyond[k] && !beyond[k ^ 1]) sides += (sides.empty() ? "" : " and ") + std::string(kSide[k]);
        }
    }
    if (sides.empty()) return std::nullopt;
    return fmt::format(
        "warning: the file's camera{} cuts the scene off at the {} ({:.1f}% of its vertices lie "
        "outside the frame; --no-file-camera frames the whole scene)",
        scene.camera && !scene.camera->name.empty() ? " '" + scene.camera->name + "'" : "", sides,
        100.0 * double(outside) / double(seen));
}


/// --convergence auto / --separation auto (docs/displays.md): a depth pre-pass of the centre
/// view; the convergence balances the parallax in and out of the screen (balancedConvergence),
/// the separation makes the largest parallax the eyes meet — at infinity, at the scene's
/// nearest and farthest points — `depthPercent` % of the screen's budget (autoSeparation).
Status chooseAutoRig(Prepared& out, FramingParams& params, bool convergenceAuto,
                     bool separationAuto, float depthPercent) {
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
    if (!separationAuto) return {};
    FramingParams trial = params;
    trial.interaxial.reset();
    trial.viewConeDegrees = 0.0f;
    trial.separation = 0.01f;
    auto framed = frameScene(out.scene, trial, out.settings);
    if (!framed) return framed.status();
    if (framed->rig.columns < 2) return usageError("--separation auto needs a row of at least two views");
    const ParallaxBudget budget = parallaxBudget(*out.screen);
    const float s = autoSeparation(framed->rig, d.minimum, d.maximum, budget, depthPercent);
    if (!(s > 0.0f) || !std::isfinite(s)) {
        out.notes.push_back(
            "note: --separation auto: the scene lies on the convergence plane (no parallax at "
            "any separation); the default spacing is kept");
        return {};
    }
    params.separation = s;
    params.interaxial.reset();
    params.viewConeDegrees = 0.0f;
    // The parallax between adjacent views the choice gives (scaled from the 1 % trial).
    const ParallaxRange r = parallaxRange(framed->rig, d.minimum, d.maximum);
    const float k = s / framed->rig.separation() / float(framed->rig.columns - 1);
    const float w = out.screen->widthCm;
    out.notes.push_back(fmt::format(
        "note: --separation auto chose {:.3g}% of the screen width: the largest parallax between "
        "adjacent views (at infinity {:.2f} cm, the scene {:+.2f} .. {:+.2f} cm) is {:.3g}% of "
        "the {:.2f} cm budget ({} eye separation on a {:.4g} cm screen)",
        100.0 * s, parallaxAtInfinity(framed->rig) * s / framed->rig.separation() * w,
        r.minParallax * k * w, r.maxParallax * k * w, depthPercent, budget.fraction * w,
        budget.desktop ? "half the" : "the", w));
    return {};
}

/// --exposure EV | auto (framing.h's exposeLights), and the warning for a model file's lights
/// that saturate the scene's centre when no exposure is given.
Status applyExposure(Prepared& out, std::optional<double> ev, bool isAuto, bool fromFiles,
                     float& appliedEv) {
    appliedEv = 0.0f;
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
        appliedEv = chosen;
        out.notes.push_back(fmt::format(
            "note: --exposure auto chose {:+.3g} EV: the brightest light lit the scene's centre "
            "at {:.4g}x full colour, now 1x",
            chosen, peak));
    } else if (ev) {
        exposeLights(out.scene, float(*ev));
        appliedEv = float(*ev);
    } else if (fromFiles && peak > 8.0f && std::isfinite(peak)) {
        // Tone mapped (applyTonemap ran first), colours this bright still wash out to white.
        out.notes.push_back(fmt::format(
            "warning: the lights of {} light the scene's centre at {:.3g}x full colour "
            "(photometric units, as Blender's exporter writes them?): surfaces {}; "
            "--exposure auto scales them to 1x, --exposure EV by 2^EV",
            out.sceneName, peak,
            out.scene.tonemap == Tonemap::None ? "saturate" : "wash out to white"));
    }
    return {};
}

/// The environment of `path` lit at 2^ev: built once per (file contents, ev) in a process and
/// shared (a sequence, MPI ranks' frames and Python's repeated renders reuse it). The key is a
/// hash of the bytes (environmentFileHash: a read, cheap next to the decode and the build), so
/// a file rewritten in place, or another file at the same path after a chdir, is built anew.
Result<std::shared_ptr<const Environment>> environmentOf(const std::string& path, float ev) {
    static std::mutex mutex;
    static std::uint64_t lastHash = 0;
    static float lastEv = 0.0f;
    static std::shared_ptr<const Environment> last;
    const std::uint64_t hash = environmentFileHash(path);
    {
        std::lock_guard lock(mutex);
        if (last && hash != 0 && hash == lastHash && ev == lastEv) return last;
    }
    auto map = loadEnvironmentMap(path);
    if (!map) return map.status();
    auto env = std::make_shared<const Environment>(buildEnvironment(*map, std::exp2(ev)));
    std::lock_guard lock(mutex);
    lastHash = map->contentHash, lastEv = ev, last = env;  // the bytes the map was made of
    return std::shared_ptr<const Environment>(env);
}

/// --environment MAP (issue 39 item 2): the map lights the scene (lighting.h "Image
/// lighting") at the exposure the lights have, in place of the constant ambient; an
/// occlusion map darkens its light per pixel only, so vertex shading becomes pixel shading.
Status applyEnvironment(Prepared& out, const std::string& path, float ev) {
    if (path.empty()) return {};
    auto env = environmentOf(path, ev);
    if (!env) return env.status();
    out.scene.environment = *env;
    out.scene.ambient = glm::vec3(0.0f);
    const bool occlusion =
        std::any_of(out.scene.instances.begin(), out.scene.instances.end(),
                    [](const Instance& i) { return i.material.occlusionTexture >= 0; });
    if (occlusion && out.settings.shading == Shading::Vertex) {
        out.settings.shading = Shading::Pixel;
        out.notes.push_back(
            "note: --environment with the scene's occlusion maps shades per pixel (per vertex, "
            "the maps could not darken the environment's light)");
    } else if (occlusion && out.settings.shading == Shading::Flat) {
        out.notes.push_back(
            "note: in flat shading the scene's occlusion maps do not darken the environment's "
            "light (one colour a triangle); --shading pixel draws them");
    }
    return {};
}

/// --tonemap NAME onto Scene::tonemap; auto keeps the scene's (loadModels: khr-neutral under
/// the files' own lights, else none).
Status applyTonemap(Scene& scene, const std::string& name) {
    if (name == "none") scene.tonemap = Tonemap::None;
    else if (name == "khr-neutral") scene.tonemap = Tonemap::KhrNeutral;
    else if (name == "aces") scene.tonemap = Tonemap::Aces;
    else if (name != "auto")
        return usageError(fmt::format(
            "--tonemap {}: not a tone mapping (expected none, khr-neutral, aces or auto)", name));
    return {};
}

}  // namespace

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
    static constexpr const char* kNames[] = {"X", "Y", "Z", "SCALE", "YAW"};
    for (std::size_t i = 0; i < values.size(); ++i) {
        const double v = values[i];
        const bool inRange = i < 3   ? std::abs(v) <= kMaxPlacementOffset
                             : i == 3 ? v >= kMinPlacementScale && v <= kMaxPlacementScale
                                      : std::abs(v) <= kMaxPlacementYaw;
        if (!inRange) {
            return bad(fmt::format(
                "has {} = {:g} out of range (|X|, |Y|, |Z| at most {:g}; SCALE {:g}..{:g}; "
                "|YAW| at most {:g} degrees)",
                kNames[i], v, kMaxPlacementOffset,
                kMinPlacementScale, kMaxPlacementScale, kMaxPlacementYaw));
        }
    }
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
Result<Scene> loadModels(const std::vector<std::string>& args,
                         const std::vector<InlineModel>& inlineModels, int grid, bool strict,
                         std::string& name, std::optional<SceneAnimation>& animation,
                         const WarningSink& warn) {
    std::vector<Scene> scenes;
    std::vector<std::optional<Placement>> placements;
    std::vector<SceneLoadInfo> infos;
    bool plain = true;
    for (const std::string& arg : args) {
        auto parsed = parseModelArg(arg);
        if (!parsed) return parsed.status();
        SceneLoadInfo info;
        info.strict = strict;
        auto scene = loadScene(parsed->first, &info);
        if (!scene) return scene.status();
        for (const std::string& w : info.warnings) warn("warning: " + w);
        plain = plain && !info.fromMaterials && !parsed->second;
        scenes.push_back(std::move(scene).value());
        placements.push_back(parsed->second);
        infos.push_back(std::move(info));
        name += (name.empty() ? "" : " + ") + parsed->first;
    }
    for (const InlineModel& m : inlineModels) {  // Python's mvr.Mesh: as a plain file's mesh
        if (!m.mesh) return usageError(fmt::format("{}: no mesh", m.name));
        std::optional<Placement> placement;
        if (!m.placement.empty()) {
            auto parsed = parseModelArg(m.name + "@" + m.placement);
            if (!parsed) return parsed.status();
            placement = parsed->second;
        }
        Scene s;
        s.meshes = {*m.mesh};
        s.instances = {Instance{0, glm::mat4(1.0f), Material{}}};
        SceneLoadInfo info;
        if (m.texture) {
            if (m.mesh->texcoords.size() != m.mesh->positions.size())
                return usageError(fmt::format("{}: a texture needs uvs (one per vertex)", m.name));
            s.textures.push_back(Texture{m.name, *m.texture});
            s.instances[0].material.baseColorTexture = 0;
            info.fromMaterials = true;
        }
        plain = plain && !info.fromMaterials && !placement;
        scenes.push_back(std::move(s));
        placements.push_back(placement);
        infos.push_back(std::move(info));
        name += (name.empty() ? "" : " + ") + m.name;
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
            for (Instance& inst : s.instances) {  // vertex colours shown as they are
                const bool colored = !s.meshes[std::size_t(inst.mesh)].colors.empty();
                inst.material = Material{colored ? glm::vec3(1.0f) : glm::vec3(0.85f, 0.75f, 0.6f),
                                         0.3f};
            }
        }
        if (infos[i].lightsFromFile)
            fileLights.insert(fileLights.end(), s.lights.begin(), s.lights.end());
        s.lights.clear();
        if (placements[i]) transformScene(s, placements[i]->matrix());
        if (infos[i].animation && animation) {
            warn(fmt::format("warning: {}: its animation is not played (only the first "
                             "animated model's is)",
                             args[i]));
        } else if (infos[i].animation) {
            // The first animated model's animation, its instances numbered in the combination.
            animation = std::move(infos[i].animation);
            if (placements[i]) transformAnimation(*animation, placements[i]->matrix());
            for (SceneAnimation::Target& t : animation->instances)
                t.instance += int(combined.instances.size());
            for (SceneAnimation::Skin& sk : animation->skins)
                sk.instance += int(combined.instances.size());
            if (combined.camera) animation->cameraNode = -1;  // an earlier file's camera
        }
        appendScene(combined, std::move(s));
    }
    if (fileLights.size() > std::size_t(kMaxLights)) {
        warn(fmt::format("warning: {} lights in the models: the first {} are used",
                         fileLights.size(), kMaxLights));
        fileLights.resize(kMaxLights);
    }
    combined.lights = fileLights.empty() ? defaultLights() : fileLights;
    // --tonemap auto's choice (applyTonemap): the files' own lights are KHR_lights_punctual's
    // physical units, whose highlights a clamp would flatten.
    combined.tonemap = fileLights.empty() ? Tonemap::None : Tonemap::KhrNeutral;
    if (grid > 1) {
        const Bounds b = combined.bounds();
        const glm::vec3 size = b.max - b.min;
        const float spacing = std::max({size.x, size.y, 1e-6f}) * 1.1f;
        const int columns = static_cast<int>(std::ceil(std::sqrt(double(grid))));
        const int rows = (grid + columns - 1) / columns;
        const std::vector<Instance> one = combined.instances;
        combined.instances.clear();
        std::vector<SceneAnimation::Target> targets;
        std::vector<SceneAnimation::Skin> skins;
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
                // The copies share the posed mesh (and a skinned instance stands at the root, moved
                // only by its copy's matrix): posed once, by the first copy.
                if (k == 0) skins = animation->skins;
            }
        }
        combined.camera.reset();
        if (animation) {
            animation->instances = std::move(targets);
            animation->skins = std::move(skins);
            animation->cameraNode = -1;
        }
    }
    return combined;
}

/// Every format to write takes the rig's views at their size (composite::outputSize(), what
/// compose() refuses), checked before anything is rendered or written: a refused format must
/// leave the output directory as it was, not half-written (issue 44). A format the recipe gives
/// is named as its --format; one a display preset adds, as the --display's. A recipe that
/// neither writes files nor names formats (the viewer's: it composes for its window, at the
/// window's size) is not checked.
Status checkFormats(const RenderRecipe& r, const Prepared& p) {
    if (r.outputs.directory.empty() && r.outputs.formats.empty()) return Status::ok();
    for (const std::string& name : p.formats) {
        const bool given =
            std::find(r.outputs.formats.begin(), r.outputs.formats.end(), name) !=
            r.outputs.formats.end();
        const std::string who = given ? fmt::format("--format {}", name)
                                      : fmt::format("--display {}: its format {}", r.display, name);
        auto info = composite::findFormat(name);
        if (!info)
            return Status(info.status().code(),
                          fmt::format("{}: {}", who, info.status().message()));
        composite::ComposeOptions compose = p.compose;
        compose.baseline = p.rig.interaxial;  // as writeOutputs() composes them
        compose.convergence = p.rig.convergence;
        // rgbd: the centre view's colour and depth (outputs.h), two images of the view's size.
        if (info->colourAndDepth) {
            if (Status s = checkCentreView(p.rig, who); !s) return s;
        }
        auto size = composite::outputSize(*info, info->colourAndDepth ? 2 : p.rig.viewCount(),
                                          p.settings.width,
                                          p.settings.height, compose, who);
        if (!size) {
            const std::string& why = size.status().message();
            return Status(size.status().code(),
                          why.rfind(who, 0) == 0 ? why : fmt::format("{}: {}", who, why));
        }
    }
    return Status::ok();
}

/// No name in an output path longer than a file system takes (NAME_MAX: 255 bytes on Linux's).
Status checkNameLengths(const char* option, const std::string& path) {
    for (const std::filesystem::path& part : std::filesystem::path(path)) {
        if (part.native().size() > 255) {
            return outputError(fmt::format("{} {}...: a name of {} bytes (at most 255)", option,
                                           path.substr(0, 40), part.native().size()));
        }
    }
    return {};
}

/// The output paths, before anything is rendered (issue 44): -o is a folder or can be made one,
/// and a file output (the report, the video) can have its folder made and is a file or nothing
/// yet — never a device or a directory, which a rename into place would replace.
Status checkOutputPaths(const RenderRecipe& r) {
    namespace fs = std::filesystem;
    if (!r.outputs.reportJson.empty() && r.sequence.active()) {
        return usageError(fmt::format("--report-json {}: the comfort report is a still's (not "
                                      "with --frames, --orbit or --camera-path)",
                                      r.outputs.reportJson));
    }
    std::error_code ec;
    if (!r.outputs.directory.empty()) {
        if (Status s = checkNameLengths("-o", r.outputs.directory); !s) return s;
        fs::path p = r.outputs.directory;
        while (!p.empty() && !fs::exists(p, ec) && p != p.parent_path()) p = p.parent_path();
        if (!p.empty() && fs::exists(p, ec) && !fs::is_directory(p, ec)) {
            return outputError(fmt::format("-o {}: cannot create output directory: '{}' is "
                                           "not a directory",
                                           r.outputs.directory, p.string()));
        }
    }
    auto checkFile = [&](const char* option, const std::string& path) -> Status {
        if (path.empty()) return {};
        const fs::path p(path);
        if (Status s = checkNameLengths(option, path); !s) return s;
        const fs::file_status st = fs::status(p, ec);
        if (fs::exists(st) && !fs::is_regular_file(st)) {
            return outputError(fmt::format("{} {}: not a regular file (expected a new file or "
                                           "one to replace)",
                                           option, path));
        }
        // Its folder is made when missing (as -o's), under one that exists.
        fs::path folder = p.has_parent_path() ? p.parent_path() : fs::path(".");
        while (!folder.empty() && !fs::exists(folder, ec) && folder != folder.parent_path())
            folder = folder.parent_path();
        if (!folder.empty() && fs::exists(folder, ec) && !fs::is_directory(folder, ec)) {
            return outputError(
                fmt::format("{} {}: '{}' is not a directory", option, path, folder.string()));
        }
        return {};
    };
    if (Status s = checkFile("--report-json", r.outputs.reportJson); !s) return s;
    return checkFile("--video", r.sequence.video);
}

}  // namespace

std::vector<std::string> ignoredOptionWarnings(const RenderRecipe& r,
                                               const std::vector<std::string>& formats) {
    std::vector<std::string> out;
    if (r.given.empty()) return out;
    auto given = [&](std::string_view name) { return r.gave(name); };
    auto writes = [&](std::string_view f) {
        return std::find(formats.begin(), formats.end(), f) != formats.end();
    };
    auto warn = [&](std::string_view name, std::string_view why) {
        if (given(name)) out.push_back(fmt::format("warning: {} is ignored {}", name, why));
    };
    if (!r.shadows) warn("--shadow-map-size", "without --shadows");
    if (r.billboards == 0) warn("--billboard-size", "without --billboards");
    if (!r.camera.focalLengthMm) warn("--sensor-width-mm", "without --focal-length-mm");
    if (!r.sequence.active()) {
        for (const char* name : {"--fps", "--threads", "--gather-stats"})
            warn(name, "without a sequence (--frames, --orbit or --camera-path)");
    }
    if (!r.outputs.depth && r.outputs.write.find("depth") == std::string::npos)
        warn("--depth-format", "without --depth");
    if (r.sequence.video.empty()) {
        for (const char* name : {"--codec", "--crf", "--encoder-preset"}) warn(name, "without --video");
    }
    if (!writes("jps") && !writes("mpo")) warn("--jpeg-quality", "without --format jps or mpo");
    if (!writes("lenticular")) {
        for (const char* name :
             {"--lenticular-pitch", "--lenticular-slope", "--lenticular-center", "--lenticular-dpi",
              "--lenticular-screen", "--lenticular-calibration",
              "--lenticular-bgr", "--lenticular-invert-views",
              "--lenticular-flip-x", "--lenticular-flip-y"})
            warn(name, "without a lenticular image (--format lenticular)");
    }
    if (!writes("rgbd"))  // --depthiness, --focus: also the view cone's (cone_depth.h)
        warn("--rgbd-depth-position", "without an RGB-D image (--format rgbd)");
    return out;
}

Result<WriteSet> writeSetOf(const RenderRecipe& r, bool display) {
    WriteSet w;
    const bool video = !r.sequence.video.empty();
    if (r.outputs.write.empty()) {
        // --direct keeps no view: its default is the lenticular image alone (direct.h).
        w.views = !display && !video && !r.outputs.direct;
        w.composites = !video;
        w.video = video;
    } else {
        w = WriteSet{false, false, false, false, false};
        std::size_t start = 0;
        for (;;) {
            const std::size_t comma = r.outputs.write.find(',', start);
            const std::string word = r.outputs.write.substr(
                start, comma == std::string::npos ? std::string::npos : comma - start);
            if (word == "views") w.views = true;
            else if (word == "depth") w.depth = true;
            else if (word == "composites") w.composites = true;
            else if (word == "cameras") w.cameras = true;
            else if (word == "video") w.video = true;
            else {
                return usageError(fmt::format(
                    "--write {}: {} (expected a comma list of views, depth, composites, "
                    "cameras, video)",
                    r.outputs.write, word.empty() ? "an empty item" : "unknown '" + word + "'"));
            }
            if (comma == std::string::npos) break;
            start = comma + 1;
        }
        if (w.video && !video) {
            return usageError(
                fmt::format("--write {}: video, and no --video FILE to write", r.outputs.write));
        }
        if (video && !w.video) {
            return usageError(fmt::format("--video {}: --write {} leaves the video out",
                                          r.sequence.video, r.outputs.write));
        }
    }
    w.depth = w.depth || r.outputs.depth;
    w.cameras = w.cameras || r.outputs.cameras;
    return w;
}

Result<Prepared> prepare(const RenderRecipe& r, const WarningSink& warnIn) {
    const WarningSink warn =
        warnIn ? warnIn : [](const std::string& line) { fmt::print(stderr, "{}\n", line); };
    Prepared out;
    // A display preset fills in what the command line did not give (displays.h).
    const double fov = r.fov.value_or(45.0);
    int nViews = r.views.value_or(2);
    std::string viewSize = r.size.value_or("1024x768");
    std::optional<double> cone = r.viewCone;
    std::optional<float> aspect;
    if (!r.display.empty()) {
        auto d = findDisplay(r.display);
        if (!d) return usageError(fmt::format("--display {}: {}", r.display, d.status().message()));
        out.display = *d;
        if (!r.views.has_value() && r.viewGrid.empty()) nViews = d->views;
        if (!r.size.has_value()) {
            viewSize = fmt::format("{}x{}", d->viewWidth, d->viewHeight);
            aspect = d->aspect;
        }
        if (!r.viewCone.has_value() && d->viewConeDegrees > 0.0f && !r.interaxial && !r.separation &&
            !r.separationAuto && r.viewGrid.empty() && r.rig == "offaxis")
            cone = d->viewConeDegrees;
    }
    // A calibration's viewCone is the panel's own: it replaces the preset's, and without a
    // preset it spreads a row of more than two views as a preset's would.
    if (r.calibrationViewCone && *r.calibrationViewCone > 0.0 && !r.viewCone.has_value() &&
        !r.interaxial && !r.separation && !r.separationAuto && r.viewGrid.empty() && r.rig == "offaxis" &&
        (out.display || nViews > 2)) {
        cone = *r.calibrationViewCone;
        out.notes.push_back(
            fmt::format("note: view cone {:g} degrees from the calibration's viewCone (--view-cone "
                        "overrides it)",
                        *cone));
    }
    for (const auto& [name, value] : {std::pair{"--screen-width", r.screenWidthCm},
                                      std::pair{"--viewing-distance", r.viewingDistanceCm}}) {
        if (value && (!std::isfinite(*value) || *value <= 0.0 || *value > 1e6)) {
            return usageError(fmt::format(
                "{} {} is out of range (expected a length in cm, 0 < cm <= 1e6)", name, *value));
        }
    }
    if (r.viewingDistanceCm && !r.screenWidthCm) {
        return usageError(fmt::format(
            "--viewing-distance {} needs --screen-width (the screen's width in cm)",
            *r.viewingDistanceCm));
    }
    if (r.screenWidthCm) {
        ScreenGeometry screen;
        screen.widthCm = float(*r.screenWidthCm);
        if (r.viewingDistanceCm) screen.viewingDistanceCm = float(*r.viewingDistanceCm);
        out.screen = screen;
    }
    if (r.separationAuto && !r.screenWidthCm) {
        return usageError(
            "--separation auto needs --screen-width CM (the budget is the 6.5 cm eye separation "
            "over the screen width)");
    }
    if (r.depthPercent && (!std::isfinite(*r.depthPercent) || *r.depthPercent <= 0.0 ||
                           *r.depthPercent > kMaxDepthPercent)) {
        return usageError(fmt::format(
            "--depth-percent {} is out of range (expected 0 < P <= 100: the largest parallax as "
            "a percentage of the screen's budget)",
            *r.depthPercent));
    }
    if (r.depthPercent && !r.separationAuto) {
        return usageError(fmt::format(
            "--depth-percent {} needs --separation auto (it sets the strength auto chooses)",
            *r.depthPercent));
    }
    if (r.separationAuto && cone && r.viewCone.has_value()) {
        return usageError(fmt::format("--view-cone {} excludes --separation", *cone));
    }
    // Numbers first: they are cheap to check and the model may be large.
    auto sz = parseSize(viewSize, "--size");
    if (!sz) return sz.status();
    out.settings.width = sz->first;
    out.settings.height = sz->second;
    auto sh = parseShading(r.shading);
    if (!sh) return usageError(fmt::format("--shading {}: {}", r.shading, sh.status().message()));
    out.settings.shading = *sh;
    if (r.specular == "per-view") {
        if (out.settings.shading == Shading::Flat) {
            return usageError(
                "--specular per-view needs --shading pixel or vertex (flat shading has no "
                "highlight)");
        }
        out.settings.specular = SpecularEye::PerView;
        if (out.settings.shading == Shading::Vertex) {
            out.settings = shadedSettings(out.settings);  // what the backends render (render.h)
            out.notes.push_back(
                "note: --specular per-view shades per pixel (vertex colours are shared by all "
                "views)");
        }
    } else if (r.specular != "center") {
        return usageError(fmt::format(
            "--specular {}: not a shading eye (expected center or per-view)", r.specular));
    }
    out.settings.cullBackFaces = r.cull, out.settings.wireframe = r.wireframe;
    if (Status s = applySampling(r, out); !s) return s;  // --aa (sampling.h)
    if (r.shadowMapSize < 16 || r.shadowMapSize > 8192) {
        return usageError(
            fmt::format("--shadow-map-size {} is out of range (expected 16..8192)", r.shadowMapSize));
    }
    out.settings.shadows = r.shadows;
    if (r.shadows && out.settings.shading == Shading::Vertex) {
        out.settings = shadedSettings(out.settings);  // what the backends render (render.h)
        out.notes.push_back(
            "note: --shadows shades per pixel (looked up per vertex, a shadow vanishes inside "
            "large triangles)");
    }
    // Depth images only when written or drawn into; the reports need only each view's range,
    // which a backend measures without reading the images back (RenderOutput::depthRange).
    auto write = writeSetOf(r, !r.display.empty());
    if (!write) return write.status();
    out.write = *write;
    const SurfaceRecipe& sf = r.surfaces;
    const bool depthFormat = std::any_of(
        r.outputs.formats.begin(), r.outputs.formats.end(), [](const std::string& f) {
            auto info = composite::findFormat(f);
            return info && info->colourAndDepth;  // rgbd: the centre view's depth
        });
    out.settings.depth = depthFormat || out.write.depth || isTransparentBackground(r.background) || !sf.sky.empty() || sf.floatingWindow ||
                         sf.letterbox > 0.0 || !sf.labels.empty() || !sf.anchors.empty();
    out.settings.shadowMapSize = r.shadowMapSize;
    const bool screenRig = usesScreenRig(r, out.display ? &*out.display : nullptr);  // screen.h
    auto kind = screenRig ? Result<RigKind>(RigKind::OffAxis) : parseRigKind(r.rig);
    if (!kind) return usageError(fmt::format("--rig {}: {}", r.rig, kind.status().message()));
    FramingParams params;
    params.kind = *kind;
    if (!r.viewGrid.empty()) {
        static const std::regex kGrid(R"(\s*(\d{1,3})\s*[xX]\s*(\d{1,3})\s*)");
        std::smatch m;
        if (!std::regex_match(r.viewGrid, m, kGrid)) {
            return usageError(
                fmt::format("--view-grid '{}' is not of the form CxR (e.g. 3x3)", r.viewGrid));
        }
        params.columns = std::stoi(m[1].str());
        params.rows = std::stoi(m[2].str());
    } else {
        params.columns = nViews;
        params.rows = 1;
    }
    if (params.columns < 1 || params.rows < 1 || params.columns * params.rows > kMaxViews) {
        return usageError(fmt::format("{} {}: view count {} is out of range (expected 1..{})",
                                      r.viewGrid.empty() ? "--views" : "--view-grid",
                                      r.viewGrid.empty() ? fmt::format("{}", nViews) : r.viewGrid,
                                      params.columns * params.rows, kMaxViews));
    }
    if (Status s = checkScreenOptions(r, params.columns * params.rows, screenRig); !s) return s;
    if (r.grid < 1 || r.grid > 1024) {
        return usageError(fmt::format("--grid {} is out of range (expected 1..1024 copies)", r.grid));
    }
    if (!std::isfinite(fov) || fov <= 0.0 || fov >= 180.0) {
        return usageError(
            fmt::format("--fov {} is out of range (expected 0 < fov < 180 degrees)", fov));
    }
    for (const auto& [name, value] :
         {std::pair{"--interaxial", r.interaxial}, std::pair{"--separation", r.separation},
          std::pair{"--convergence", r.convergence}}) {
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
        if (r.interaxial || r.separation) {
            return usageError(fmt::format("--view-cone {} excludes --{}", *cone,
                                          r.interaxial ? "interaxial" : "separation"));
        }
        if (!r.viewGrid.empty() || *kind != RigKind::OffAxis) {
            return usageError(fmt::format(
                "--view-cone {} needs an off-axis row of views (--views N, --rig offaxis)", *cone));
        }
    }
    if (r.convergence && *r.convergence <= 0.0) {
        return usageError("--convergence 0 is out of range (expected a distance > 0)");
    }

    // The scene.
    if (r.scene != "default" && r.scene != "village" && r.scene != "textured") {
        return usageError(fmt::format(
            "--scene {} is not a known scene (expected default, village or textured)", r.scene));
    }
    const bool noModels = r.models.empty() && r.meshes.empty();
    if (r.scene != "default" && !noModels) {
        return usageError(
            fmt::format("--scene {} cannot be combined with model files", r.scene));
    }
    if (noModels && r.scene == "village") {
        out.scene = adelson::makeVillageScene();
        out.sceneName = "village scene";
        if (r.grid != 1) {
            return usageError(fmt::format(
                "--grid {} needs a model file (the village scene is not gridded)", r.grid));
        }
    } else if (noModels && r.scene == "textured") {
        out.scene = makeTexturedScene();
        out.sceneName = "textured scene";
        if (r.grid != 1) {
            return usageError(fmt::format(
                "--grid {} needs a model file (the textured scene is not gridded)", r.grid));
        }
    } else if (noModels) {
        out.scene = makeDefaultScene();
        out.sceneName = "default scene";
        if (r.grid != 1) {
            return usageError(fmt::format(
                "--grid {} needs a model file (the default scene is not gridded)", r.grid));
        }
    } else {
        auto loaded = loadModels(r.models, r.meshes, r.grid, r.strict, out.sceneName, out.animation, warn);
        if (!loaded) return loaded.status();
        out.scene = std::move(loaded).value();
    }
    if (Status s = validateScene(out.scene); !s) return s;
    if (out.settings.shading == Shading::Vertex &&
        std::any_of(out.scene.instances.begin(), out.scene.instances.end(), [](const Instance& i) {
            return i.material.metallicRoughnessTexture >= 0 || i.material.normalTexture >= 0;
        })) {
        out.settings.shading = Shading::Pixel;  // lighting.h: these maps are per pixel only
        out.notes.push_back(
            "note: the scene's metallic-roughness and normal maps shade per pixel (per vertex, "
            "only the factors and the surface's own normals would be lit)");
    }
    if (Status s = applyTonemap(out.scene, r.tonemap); !s) return s;
    if (r.tonemap == "auto" && out.scene.tonemap != Tonemap::None) {
        out.notes.push_back(
            "note: --tonemap auto chose khr-neutral: the model files' own lights (physical "
            "units) light the scene; --tonemap none clamps instead");
    }
    float ev = 0.0f;
    if (Status s = applyExposure(out, r.exposure, r.exposureAuto, !noModels, ev); !s) return s;
    out.exposureScale = std::exp2(ev);
    if (Status s = applyEnvironment(out, r.environment, ev); !s) return s;

    // The camera, near/far, convergence and spacing: the library's framing (framing.h).
    params.fovYDegrees = static_cast<float>(fov);
    params.aspect = aspect;
    params.fovOverridesSceneCamera = r.fov.has_value();
    params.useSceneCamera = !r.noFileCamera;
    // The caller's lens and viewpoint (mvr/session/camera.h): over the file's camera.
    const float viewAspect =
        aspect.value_or(float(out.settings.width) / float(out.settings.height));
    auto lens = fovFromFocalLength(r.camera, viewAspect);
    if (!lens) return lens.status();
    if (*lens) {
        if (r.fov) return usageError("--focal-length-mm excludes --fov (give one of them)");
        params.fovYDegrees = float(**lens);
        params.fovOverridesSceneCamera = true;
    }
    auto viewpoint = viewpointOf(r.camera, out.scene, params.fovYDegrees, viewAspect);
    if (!viewpoint) return viewpoint.status();
    if (*viewpoint) {
        params.viewpoint = **viewpoint;
        params.useSceneCamera = false;
    }
    if (out.animation && !params.useSceneCamera) out.animation->cameraNode = -1;
    std::optional<ScreenEyes> screenEyes;
    if (screenRig) {
        auto eyes = screenEyesOf(r, viewAspect, &out.eyeTrack, out.display ? &*out.display : nullptr);
        if (!eyes) return eyes.status();
        screenEyes = *eyes;
        params.aspect = eyes->screen.width() / eyes->screen.height();  // the window is the screen
        if (auto n = screenStretchNote(eyes->screen, out.settings.width, out.settings.height))
            out.notes.push_back(*n);
        if (!out.screen) out.screen = screenGeometryOf(*eyes);  // the report in cm of this screen
    }
    // "transparent": the scene's colour stays, the views' alpha is 0 there (buildSurfaces()).
    auto background =
        backgroundOf(isTransparentBackground(r.background) ? std::string() : r.background);
    if (!background) return background.status();
    if (*background) params.clearColor = **background;
    if (r.interaxial) params.interaxial = static_cast<float>(*r.interaxial);
    if (r.separation) params.separation = static_cast<float>(*r.separation);
    if (r.convergence) params.convergence = static_cast<float>(*r.convergence);
    if (Status s = applyConeDepth(r, out.scene, cone.value_or(0.0), params, out.notes); !s) return s;
    if (r.convergenceAuto || r.separationAuto) {
        if (Status s = chooseAutoRig(out, params, r.convergenceAuto, r.separationAuto,
                                         float(r.depthPercent.value_or(kDefaultDepthPercent))); !s) return s;
    }
    auto framed = frameScene(out.scene, params, out.settings);
    if (!framed && framed.status().code() == ErrorCode::Usage) {
        // The rig is a product of the options and the scene: name the options that shaped it
        // ("--interaxial 1e+30: view 0 has a non-finite matrix or shear"), else the models.
        std::string culprit;
        auto add = [&](const std::string& text) {
            culprit += (culprit.empty() ? "" : ", ") + text;
        };
        if (r.interaxial) add(fmt::format("--interaxial {}", *r.interaxial));
        if (r.separation) add(fmt::format("--separation {}", *r.separation));
        if (r.convergence) add(fmt::format("--convergence {}", *r.convergence));
        if (cone) add(fmt::format("--view-cone {}", *cone));
        if (fov != 45.0) add(fmt::format("--fov {}", fov));
        if (culprit.empty()) {  // no option shaped it: the models' extent is at fault (exit 2)
            return inputError(fmt::format("{}: the scene cannot be framed ({})", out.sceneName,
                                          framed.status().message()));
        }
        return Status(framed.status().code(),
                      fmt::format("{}: {}", culprit, framed.status().message()));
    }
    if (!framed) return framed.status();  // the memory budget: its message names views and size
    out.rig = std::move(framed->rig);
    out.settings = framed->settings;
    if (screenEyes) {
        auto placed = makeScreenRig(out.rig.camera, out.rig.convergence, *screenEyes);
        if (!placed) return placed.status();
        out.rig = std::move(placed).value();
    }
    if (params.useSceneCamera && out.scene.camera && !out.scene.viewpoint) {
        if (auto w = fileCameraCropWarning(out.scene, out.rig.camera)) out.notes.push_back(*w);
    }
    // Billboards (issue 15): after the framing (they do not move the camera), facing it.
    if (r.billboards < 0 || r.billboards > 1000000) {
        return usageError(
            fmt::format("--billboards {} is out of range (expected 0..1000000)", r.billboards));
    }
    if (!std::isfinite(r.billboardSize) || r.billboardSize < 0.0) {
        return usageError(fmt::format(
            "--billboard-size {} is out of range (expected a finite size >= 0)", r.billboardSize));
    }
    if (r.billboards > 0) {
        const Bounds b = out.scene.bounds();
        const float side = r.billboardSize > 0.0 ? float(r.billboardSize) : 0.03f * b.radius();
        const auto list = scatterBillboards(b, r.billboards, side);
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
    // The outputs: the recipe's, and what a display preset adds.
    out.formats = r.outputs.formats, out.compose = r.outputs.compose;
    auto png = parsePngCompression(r.outputs.pngCompression);
    if (!png) return png.status();
    out.png = *png;
    if (r.outputs.depthFormat != "png16" && r.outputs.depthFormat != "exr") {
        return usageError(fmt::format("--depth-format {}: expected png16 or exr",
                                      r.outputs.depthFormat));
    }
    out.depthExr = r.outputs.depthFormat == "exr";
    if (out.display) {
        displayOutputs(*out.display, r.outputs.calibrationGiven,
                       r.outputs.quiltGiven || out.rig.viewCount() != out.display->views,
                       out.rig.camera.aspect, out.formats, out.compose);
        // --direct (direct.h): the panel image alone; the preset's quilt would need the views.
        const auto& asked = r.outputs.formats;
        if (r.outputs.direct && std::find(asked.begin(), asked.end(), "quilt") == asked.end() &&
            std::find(out.formats.begin(), out.formats.end(), "lenticular") != out.formats.end())
            out.formats.erase(std::remove(out.formats.begin(), out.formats.end(), "quilt"),
                              out.formats.end());
    }
    for (std::string& w : ignoredOptionWarnings(r, out.formats)) out.notes.push_back(std::move(w));
    // No silent nonsense: a quilt layout nothing uses.
    if (r.outputs.quiltGiven &&
        std::find(out.formats.begin(), out.formats.end(), "quilt") == out.formats.end()) {
        return usageError(
            r.outputs.direct
                ? "--quilt lays out a quilt, and --direct writes the lenticular image alone "
                  "(leave --quilt or --direct out)"
                : "--quilt lays out a quilt, and no quilt is written (give --format quilt, or a "
                  "--display whose output is a quilt)");
    }
    if (Status s = resolveAngularAA(r, out); !s) return s;  // angular_aa.cpp
    if (Status s = restrictToViewRange(r, out); !s) return s;  // view_range.h
    if (Status s = resolveSynthesis(r, out); !s) return s;     // synthesis.cpp
    if (Status s = checkFormats(r, out); !s) return s;
    if (Status s = checkOutputPaths(r); !s) return s;
    return out;
}

}  // namespace mvr::session
