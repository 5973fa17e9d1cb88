// src/session/outputs.cpp — the one writer of a frame's files (mvr/session/outputs.h) and the
// surfaces drawn after the scene (mvr/session/surfaces.h).
#include "mvr/session/outputs.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cerrno>
#include <cctype>
#include <cstdio>
#include <deque>
#include <functional>
#include <optional>
#include <thread>

#include <fmt/core.h>

#include "mvr/core/output_file.h"
#include "mvr/io/exr.h"
#include "mvr/io/png.h"
#include "mvr/io/scene_io.h"
#include "mvr/session/cameras.h"
#include "mvr/session/pending.h"
#include "mvr/session/surfaces.h"

namespace mvr::session {

Status runParallel(const std::vector<std::function<Status()>>& jobs, int threads) {
    if (jobs.empty()) return {};
    if (threads <= 0) threads = int(std::max(1u, std::thread::hardware_concurrency()));
    threads = std::min<int>(threads, int(jobs.size()));
    std::vector<Status> results(jobs.size());
    std::atomic<std::size_t> next{0};
    auto work = [&] {
        for (std::size_t i = next++; i < jobs.size(); i = next++) results[i] = jobs[i]();
    };
    std::vector<std::thread> workers;
    for (int t = 1; t < threads; ++t) workers.emplace_back(work);
    work();
    for (std::thread& w : workers) w.join();
    for (Status& s : results)
        if (!s) return s;  // the first in order, whatever finished first
    return {};
}

Result<WrittenFrame> writeOutputs(const std::filesystem::path& dir, const RenderOutput& out,
                                  const Rig& rig, const FrameOutputs& outputs,
                                  const Backend* backend, const std::string& keepFormat,
                                  const std::vector<ExtraFile>& extra,
                                  ComposedImages* precomposed) {
    const auto start = std::chrono::steady_clock::now();
    // No file in `dir` (a video's image alone, the report alone): no folder either.
    const bool inDir = outputs.writesFiles(out.color.size(), out.depth.size());
    if (!inDir && extra.empty())
        return writeFrameFiles(dir, out, rig, outputs, backend, keepFormat, precomposed);
    auto staged = inDir ? StagedFiles::inFolder(dir) : Result<StagedFiles>(StagedFiles::elsewhere());
    if (!staged) return staged.status();
    auto written =
        writeFrameFiles(inDir ? staged->folder() : dir, out, rig, outputs, backend, keepFormat,
                        precomposed);
    // Errors name the files as the user knows them, not their temporary names.
    if (!written) return staged->withFinalNames(written.status());
    for (const ExtraFile& file : extra) {
        auto temp = staged->stage(file.path);
        if (!temp) return Status(temp.status().code(), file.option + " " + temp.status().message());
        errno = 0;
        if (!writeTextFile(temp->string(), file.text)) {
            const Status s = writeError(file.path, "write failed");
            return outputError(fmt::format("{} {}: {}", file.option, file.path.string(), s.message()));
        }
        written->paths.push_back(temp->string());
    }
    if (Status s = staged->commit(written->paths); !s) return s;
    written->times.wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return written;
}

bool composesOnDevice(const Backend* backend) {
    if (!backend) return false;
    auto entry = findBackend(backend->name());
    return entry && (*entry)->compose;
}

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

/// The image composites a frame writes or keeps, in the order writeFrameFiles() writes them.
std::vector<std::string> imageComposites(const RenderOutput& out, const FrameOutputs& outputs,
                                         const std::string& keepFormat) {
    std::vector<std::string> names;
    if (out.color.size() == 2 && outputs.composites)
        names.emplace_back(composite::kDefaultAnaglyph);
    bool kept = false;
    for (const std::string& format : outputs.formats) {
        const bool keep = format == keepFormat && !kept;
        if (!outputs.composites && !keep) continue;
        auto info = composite::findFormat(format);
        if (!info || info->extension != ".png") continue;  // writeFrameFiles() says why
        if (info->colourAndDepth) continue;  // rgbd: from the depth too, in writeFrameFiles()
        kept = kept || keep;
        names.push_back(format);
    }
    return names;
}

}  // namespace

Result<ComposedImages> composeImages(const RenderOutput& out, const Rig& rig,
                                     const FrameOutputs& outputs, const Backend* backend,
                                     const std::string& keepFormat) {
    const auto start = Clock::now();
    composite::ComposeOptions compose = outputs.compose;
    compose.baseline = rig.interaxial;
    compose.convergence = rig.convergence;
    ComposedImages composed;
    for (const std::string& format : imageComposites(out, outputs, keepFormat)) {
        auto image = backend ? composeFor(*backend, format, out.color, compose)
                             : composite::compose(format, out.color, compose);
        if (!image) return image.status();
        composed.images.emplace_back(format, std::move(image).value());
    }
    composed.seconds = since(start);
    return composed;
}

Result<WrittenFrame> writeFrameFiles(const std::filesystem::path& dir, const RenderOutput& out,
                                     const Rig& rig, const FrameOutputs& outputs,
                                     const Backend* backend, const std::string& keepFormat,
                                     ComposedImages* precomposed) {
    const auto start = Clock::now();
    WrittenFrame written;
    WriteTimes& times = written.times;
    composite::ComposeOptions compose = outputs.compose;
    compose.baseline = rig.interaxial;
    compose.convergence = rig.convergence;
    if (precomposed) times.compose = precomposed->seconds;
    // Image composites: composed already (composeImages(), on a GPU backend's thread), else
    // where the backend composes (same pixels as the CPU, anaglyphs within 1/255;
    // src/gl/README.md), else on the CPU.
    auto composeImage = [&](std::string_view format) -> Result<Image> {
        if (precomposed) {
            for (auto& [name, image] : precomposed->images) {
                if (name == format && !image.empty()) return std::move(image);  // in order
            }
        }
        const auto t = Clock::now();
        auto image = backend ? composeFor(*backend, format, out.color, compose)
                             : composite::compose(format, out.color, compose);
        times.compose += since(t);
        return image;
    };
    // The images are composed here, in order (a GPU backend composes on its context, which is
    // this thread's); their files are encoded and written by workers, each file independent,
    // and `paths` lists them in this order whatever order they finish in. Each job keeps its
    // own times (encoding, writing), summed once all are done.
    std::vector<std::function<Status()>> jobs;
    std::deque<std::array<double, 2>> jobTimes;  // stable addresses: {encode, write} per job
    std::deque<Image> composed;  // stable addresses while the jobs read them
    const PngCompression png = outputs.png;
    auto writeImage = [&](std::filesystem::path path, const Image* image) {
        written.paths.push_back(path.string());
        double* t = jobTimes.emplace_back(std::array<double, 2>{}).data();
        jobs.push_back([path = std::move(path), image, png, t] {
            const auto t0 = Clock::now();
            auto bytes = encodePng(*image, png);
            if (!bytes) {
                errno = 0;
                return writeError(path, bytes.status().message());
            }
            t[0] = since(t0);
            const auto t1 = Clock::now();
            Status s = writeBytes(path, *bytes);
            t[1] = since(t1);
            return s;
        });
    };
    // --view-range A:B: the files are numbered as in the whole render (view-A.png ...).
    const std::size_t first = outputs.viewRange ? std::size_t(outputs.viewRange->first) : 0;
    for (std::size_t v = 0; v < out.color.size(); ++v) {
        if (outputs.views) writeImage(dir / fmt::format("view-{}.png", first + v), &out.color[v]);
        if (outputs.depth && v < out.depth.size()) {
            auto dpath =
                dir / fmt::format("depth-{}.{}", first + v, outputs.depthExr ? "exr" : "png");
            written.paths.push_back(dpath.string());
            const DepthImage* d = &out.depth[v];
            double* t = jobTimes.emplace_back(std::array<double, 2>{}).data();  // all "encode"
            if (outputs.depthExr && v < rig.views.size()) {
                // Window depth to eye-space distance, with this view's projection.
                const glm::mat4& p = rig.views[v].clipFromView;
                jobs.push_back([dpath = std::move(dpath), d, p22 = p[2][2], p32 = p[3][2], t] {
                    const auto t0 = Clock::now();
                    std::vector<float> distance(d->depth.size());
                    for (std::size_t i = 0; i < distance.size(); ++i)
                        distance[i] = distanceOfDepth(p22, p32, d->depth[i]);
                    Status s = writeDepthExr(dpath, d->width, d->height, distance);
                    t[0] = since(t0);
                    return s;
                });
            } else {
                jobs.push_back([dpath = std::move(dpath), d, png, t] {
                    const auto t0 = Clock::now();
                    Status s = writeDepthPng(dpath, *d, png);
                    t[0] = since(t0);
                    return s;
                });
            }
        }
    }
    if (out.color.size() == 2 && outputs.composites) {
        // The red-cyan anaglyph every stereo frame gets: Dubois' least-squares red-cyan.
        auto anaglyph = composeImage(composite::kDefaultAnaglyph);
        if (!anaglyph) return anaglyph.status();
        composed.push_back(std::move(anaglyph).value());
        writeImage(dir / "anaglyph.png", &composed.back());
    }
    if (outputs.cameras && !out.color.empty()) {
        const auto path = dir / "cameras.json";
        errno = 0;
        if (!writeTextFile(path.string(),
                           camerasJson(rig, out.color[0].width, out.color[0].height,
                                       outputs.viewRange))) {
            return writeError(path, "write failed");
        }
        written.paths.push_back(path.string());
    }
    std::optional<std::size_t> keptIndex;
    for (const std::string& format : outputs.formats) {
        const bool keep = format == keepFormat && !keptIndex;
        if (!outputs.composites && !keep) continue;
        auto info = composite::findFormat(format);
        if (!info) return info.status();
        if (info->colourAndDepth) {  // rgbd: the centre view's colour and depth, and a sidecar
            auto pair = colourAndDepthOf(out, rig, "--format " + format);
            if (!pair) return pair.status();
            auto name = composite::compositeFileName(format, pair->images, compose);
            if (!name) return name.status();
            auto image = composite::compose(format, pair->images, compose);
            if (!image) return image.status();
            composed.push_back(std::move(image).value());
            if (keep) keptIndex = composed.size() - 1;
            if (!outputs.composites) continue;
            writeImage(dir / *name, &composed.back());
            pair->sidecar.image = *name;
            const auto json = dir / std::filesystem::path(*name).replace_extension(".json");
            errno = 0;
            if (!writeTextFile(json.string(), composite::rgbdSidecarJson(compose, pair->sidecar)))
                return writeError(json, "write failed");
            written.paths.push_back(json.string());
            continue;
        }
        if (info->extension == ".png") {
            // A precomposed image without its views (--direct) is named by its format alone.
            const bool viewless = out.color.empty() && precomposed &&
                                  info->size.rule != composite::SizeRule::QuiltGrid;
            auto name = viewless ? Result<std::string>(std::string(info->name) +
                                                       std::string(info->extension))
                                 : composite::compositeFileName(format, out.color, compose);
            if (!name) return name.status();
            auto image = composeImage(format);
            if (!image) return image.status();
            composed.push_back(std::move(image).value());
            if (keep) keptIndex = composed.size() - 1;
            if (outputs.composites) writeImage(dir / *name, &composed.back());
            continue;
        }
        const auto t = Clock::now();  // a JPEG file: composed and encoded by its writer
        auto path = composite::writeComposite(format, out.color, compose, dir);
        times.encode += since(t);
        if (!path) return path.status();
        written.paths.push_back(path->string());
    }
    if (Status s = runParallel(jobs); !s) return s;
    for (const auto& t : jobTimes) times.encode += t[0], times.write += t[1];
    if (keptIndex) written.kept = std::move(composed[*keptIndex]);
    times.wall = since(start) + (precomposed ? precomposed->seconds : 0.0);
    return written;
}

bool FrameOutputs::readsDepth() const {
    if (depth) return true;
    return std::any_of(formats.begin(), formats.end(), [](const std::string& f) {
        auto info = composite::findFormat(f);
        return info && info->colourAndDepth;  // composed for the files or the video
    });
}

FrameOutputs frameOutputs(const Prepared& p) {
    FrameOutputs o;
    o.formats = p.formats;
    o.depth = p.write.depth;
    o.compose = p.compose;
    o.cameras = p.write.cameras;
    o.png = p.png;
    o.depthExr = p.depthExr;
    o.views = p.write.views;
    o.composites = p.write.composites;
    o.viewRange = p.viewRange;
    return o;
}

bool isComposedFileName(const std::filesystem::path& out) {
    std::string ext = out.extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    return ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".jps" || ext == ".mpo";
}

Result<std::filesystem::path> writeComposed(std::string_view format, std::span<const Image> views,
                                            const composite::ComposeOptions& options,
                                            const std::filesystem::path& out) {
    if (isComposedFileName(out)) {
        auto made = MadeFolders::make(out.has_parent_path() ? out.parent_path() : ".");
        if (!made) return made.status();
        StagedFiles staged = StagedFiles::elsewhere();
        auto temp = staged.stage(out);
        if (!temp) return temp.status();
        std::vector<std::string> paths{temp->string()};
        if (Status s = composite::writeCompositeFile(format, views, options, paths[0]); !s)
            return staged.withFinalNames(s);
        if (Status s = staged.commit(paths); !s) return s;
        made->keep();
        return out;
    }
    auto staged = StagedFiles::inFolder(out);
    if (!staged) return staged.status();
    auto path = composite::writeComposite(format, views, options, staged->folder());
    if (!path) return staged->withFinalNames(path.status());
    std::vector<std::string> paths{path->string()};
    if (Status s = staged->commit(paths); !s) return s;
    return std::filesystem::path(paths[0]);
}

bool writeTextFile(const std::string& path, const std::string& text) {
    std::FILE* f = std::fopen(path.c_str(), "wb");
    if (!f) return false;
    const bool ok = std::fwrite(text.data(), 1, text.size(), f) == text.size();
    return std::fclose(f) == 0 && ok;
}

Result<StereoSurfaces> buildSurfaces(const SurfaceRecipe& recipe, float hdrScale,
                                     Tonemap tonemap) {
    StereoSurfaces s;
    if (!recipe.sky.empty()) {
        auto loaded = loadSky(recipe.sky, hdrScale, tonemap);
        if (!loaded) return loaded.status();
        s.sky = std::move(*loaded);
    }
    s.floatingWindow = recipe.floatingWindow;
    if (recipe.letterbox != 0.0) {
        if (!(recipe.letterbox > 0.0 && recipe.letterbox < 50.0))
            return usageError(fmt::format("--letterbox {}: must be in (0, 50) percent of the height",
                                          recipe.letterbox));
        s.letterboxPercent = float(recipe.letterbox);
    }
    for (const std::string& spec : recipe.labels) {
        auto l = parseLabel(spec, false);
        if (!l) return l.status();
        s.labels.push_back(std::move(*l));
    }
    for (const std::string& spec : recipe.anchors) {
        auto l = parseLabel(spec, true);
        if (!l) return l.status();
        s.labels.push_back(std::move(*l));
    }
    return s;
}

bool isTransparentBackground(const std::string& background) {
    return background == "transparent";
}

Result<StereoSurfaces> buildSurfaces(const RenderRecipe& recipe, float hdrScale,
                                     Tonemap tonemap) {
    SurfaceRecipe surfaces = recipe.surfaces;
    std::optional<Sky> environmentSky;
    if (surfaces.sky == "environment") {  // the map that lights the scene, read as its light
        if (recipe.environment.empty())
            return usageError("--sky environment needs --environment MAP (the map to show)");
        auto sky = loadSky(recipe.environment, hdrScale, tonemap, true);
        if (!sky) return sky.status();
        environmentSky = std::move(*sky);
        surfaces.sky.clear();
    }
    auto s = buildSurfaces(surfaces, hdrScale, tonemap);
    if (s && environmentSky) s->sky = std::move(environmentSky);
    if (!s || !isTransparentBackground(recipe.background)) return s;
    const SurfaceRecipe& r = recipe.surfaces;
    for (const auto& [given, name] :
         {std::pair{!r.sky.empty(), "--sky"}, std::pair{r.floatingWindow, "--floating-window"},
          std::pair{r.letterbox != 0.0, "--letterbox"},
          std::pair{!r.labels.empty() || !r.anchors.empty(), "--label"}}) {
        if (given) {
            return usageError(fmt::format(
                "--background transparent: not with {} (it paints over the background)", name));
        }
    }
    s->transparentBackground = true;
    return s;
}

Status applySurfaces(const StereoSurfaces& surfaces, const Rig& rig, RenderOutput& out) {
    if (!surfaces.any()) return {};
    auto applied = applyStereoSurfaces(surfaces, rig, out);
    if (!applied) return applied.status();
    return {};
}

}  // namespace mvr::session
