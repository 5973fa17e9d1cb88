// python/src/render.cpp — mvr.render() and mvr.render_sequence() (render.h).
#include "render.h"

#include <chrono>
#include <cstring>
#include <optional>

#include <fmt/core.h>

#include "mvr/composite/jpeg.h"
#include "mvr/session/cameras.h"
#include "mvr/session/direct.h"
#include "mvr/session/outputs.h"
#include "mvr/session/prepare.h"
#include "mvr/session/surfaces.h"

namespace mvr::python {

namespace {

/// An array over the caller-owned block the backend rendered into (RenderSettings::output):
/// its base is a capsule holding the block, so the pixels are never copied on the way out.
template <class E>
py::array adoptBlock(const std::shared_ptr<OutputBlock>& block, E* data,
                     std::vector<py::ssize_t> shape) {
    auto* owner = new std::shared_ptr<OutputBlock>(block);
    py::capsule base(owner, [](void* p) { delete static_cast<std::shared_ptr<OutputBlock>*>(p); });
    return py::array_t<E>(shape, data, base);
}

/// Puts every view the backend (or a post-process) left outside the block into its place and
/// frees the images (their in-place memory is the block's; freeing it is a no-op). Returns how
/// many views had to be copied (0 on every backend of this build; the tests check it).
template <class Img>
int settle(std::vector<Img>& views, OutputBlock& block) {
    int copied = 0;
    const std::size_t n = std::size_t(block.width()) * std::size_t(block.height());
    if (views.size() != std::size_t(block.views()))
        throwStatus(internalError(
            fmt::format("backend returned {} images for {} views", views.size(), block.views())));
    for (std::size_t v = 0; v < views.size(); ++v) {
        if (!block.inPlace(views[v], int(v))) {
            if (views[v].width != block.width() || views[v].height != block.height())
                throwStatus(internalError(fmt::format("backend returned view {} of {}x{} for {}x{}",
                                                      v, views[v].width, views[v].height,
                                                      block.width(), block.height())));
            ++copied;
            if constexpr (std::is_same_v<Img, Image>) {
                std::memcpy(block.color() + v * n * 4, views[v].rgba.data(), n * 4);
            } else {
                std::memcpy(block.depth() + v * n, views[v].depth.data(), n * sizeof(float));
            }
        }
    }
    views.clear();
    return copied;
}

}  // namespace

py::array imageArray(Image&& image) {
    const py::ssize_t h = image.height, w = image.width;
    return adopt(std::move(image.rgba), {h, w, 4});
}

std::mutex& gpuMutex() {
    static std::mutex m;
    return m;
}

/// Composes `views` as `format`: an array for image formats, bytes for jps / mpo.
py::object composeOne(const std::string& format, std::vector<Image>& views,
                      const composite::ComposeOptions& options, const Backend* backend, bool gpu) {
    const composite::FormatInfo info = check(composite::findFormat(format));
    Result<Image> image = usageError("");
    Result<std::vector<std::uint8_t>> bytes = usageError("");
    {
        py::gil_scoped_release release;
        std::unique_lock<std::mutex> lock(gpuMutex(), std::defer_lock);
        if (gpu && backend) lock.lock();
        if (info.extension == ".png") {
            image = backend ? composeFor(*backend, format, views, options)
                            : composite::compose(format, views, options);
        } else if (info.name == "mpo") {
            bytes = composite::encodeMpo(views, options);
        } else {
            Result<Image> picture = composite::compose(format, views, options);
            bytes = picture ? composite::encodeJpsPicture(*picture, options.jpegQuality)
                            : Result<std::vector<std::uint8_t>>(picture.status());
        }
    }
    if (info.extension == ".png") return imageArray(check(std::move(image)));
    std::vector<std::uint8_t> b = check(std::move(bytes));
    return py::bytes(reinterpret_cast<const char*>(b.data()), b.size());
}

// ---- one call: the recipe prepared, its backend and surfaces ------------------------------------
struct Job {
    RenderKeywords keywords;
    session::Prepared prepared;
    StereoSurfaces surfaces;
    std::unique_ptr<Backend> backend;
    std::string backendName, method;
    bool gpu = false;

    ~Job() {  // the driver context goes on the thread that used it (called with the GIL held)
        if (!backend) return;
        py::gil_scoped_release release;
        std::unique_lock<std::mutex> lock(gpuMutex(), std::defer_lock);
        if (gpu) lock.lock();
        backend.reset();
    }
};

namespace {

/// Prepares the recipe, builds the surfaces, makes the backend and checks the method; errors in
/// that order (as mvr render reports them).
std::unique_ptr<Job> makeJob(RenderKeywords keywords) {
    auto job = std::make_unique<Job>();
    job->keywords = std::move(keywords);
    const session::RenderRecipe& recipe = job->keywords.recipe;
    job->backendName = !recipe.backend.empty()
                           ? recipe.backend
                           : (backendNames().empty() ? "" : backendNames().front());
    job->method = recipe.method;
    Result<session::Prepared> prepared = usageError("");
    Result<StereoSurfaces> surfaces = usageError("");
    Status failure;
    {
        py::gil_scoped_release release;
        prepared = session::prepare(recipe);
        surfaces = prepared ? session::buildSurfaces(recipe, *prepared)
                            : session::buildSurfaces(recipe);
        if (prepared && !surfaces) prepared = surfaces.status();
        if (prepared) {
            if (auto entry = findBackend(job->backendName)) job->gpu = (*entry)->gpu;
            std::unique_lock<std::mutex> lock(gpuMutex(), std::defer_lock);
            if (job->gpu) lock.lock();
            Result<std::unique_ptr<Backend>> made = makeBackend(job->backendName);
            if (!made) {
                failure = made.status();
            } else {
                job->backend = std::move(made).value();
                if (job->method.empty()) job->method = job->backend->defaultMethod();
                failure = job->backend->supports(job->method);
            }
        }
    }
    job->prepared = check(std::move(prepared));
    if (!failure) throwStatus(failure);
    job->surfaces = std::move(surfaces).value();
    return job;
}

/// What every result says of the render: method, backend, scene, size, time and the rig's
/// parameters (`.rig`, a dict the caller may add to).
RenderResult resultOf(const Job& job, const Rig& rig, const std::string& method,
                      const std::string& note, double ms) {
    const session::Prepared& p = job.prepared;
    RenderResult r;
    r.method = py::str(method);
    r.note = py::str(note);
    r.backend = py::str(job.backendName);
    r.scene = py::str(p.sceneName);
    r.triangles = py::int_(p.scene.triangleCount());
    r.size = py::make_tuple(p.settings.width, p.settings.height);
    r.shading = py::str(std::string(shadingName(p.settings.shading)));
    r.elapsedMs = py::float_(ms);
    py::dict rd;
    rd["kind"] = std::string(rigKindName(rig.kind));
    rd["columns"] = rig.columns;
    rd["rows"] = rig.rows;
    rd["views"] = rig.viewCount();
    rd["interaxial"] = rig.interaxial;
    rd["interaxial_y"] = rig.interaxialY;
    rd["convergence"] = rig.convergence;
    rd["separation"] = rig.separation();
    rd["fov"] = rig.camera.fovYDegrees;
    rd["aspect"] = rig.camera.aspect;
    rd["near"] = rig.camera.near;
    rd["far"] = rig.camera.far;
    py::list eyes;
    for (const View& v : rig.views)
        eyes.append(py::make_tuple(v.eyeWorld.x, v.eyeWorld.y, v.eyeWorld.z));
    rd["eyes"] = eyes;
    r.rig = rd;
    return r;
}

/// Renders one frame of the job — the prepared rig, or a sequence's frame `frame` (its scene and
/// rig) — into a fresh output block, and returns it as the result; output= writes its files
/// (the still's, or the sequence's frame folder).
RenderResult renderFrame(Job& job, const Scene& scene, const Rig& rig,
                         const session::SequencePlan* plan, int frame) {
    const session::Prepared& p = job.prepared;
    const session::RenderRecipe& recipe = job.keywords.recipe;
    std::shared_ptr<OutputBlock> block;
    Result<RenderOutput> rendered = usageError("");
    double ms = 0.0;
    {
        py::gil_scoped_release release;
        RenderSettings settings = p.settings;
        settings.depth = true;  // mvr.render returns the depth images
        // The views are rendered straight into the memory the arrays will own (zero copy),
        // when the request is within the budget every backend checks first.
        if (framebufferBytes(rig.viewCount(), settings.width, settings.height) <=
            kMaxFramebufferBytes) {
            block = std::make_shared<OutputBlock>(rig.viewCount(), settings.width, settings.height);
            settings.output = block.get();
        }
        std::unique_lock<std::mutex> lock(gpuMutex(), std::defer_lock);
        if (job.gpu) lock.lock();
        const auto start = std::chrono::steady_clock::now();
        rendered = session::renderViews(*job.backend, p, scene, rig, settings, job.method);
        if (rendered) {
            if (Status st = session::applySurfaces(job.surfaces, rig, *rendered); !st)
                rendered = st;
        }
        ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
                 .count();
    }
    RenderOutput out = check(std::move(rendered));
    // The formats with a display preset's (display=, as `mvr render --display`).
    const std::vector<std::string>& formats = p.formats;
    composite::ComposeOptions compose = p.compose;
    if (int(out.color.size()) != rig.viewCount())
        throwStatus(internalError(fmt::format("backend returned {} images for {} views",
                                              out.color.size(), rig.viewCount())));

    RenderResult r = resultOf(job, rig, out.method, out.note, ms);
    py::dict rd = r.rig;
    py::dict comfort;
    if (auto c = session::comfortReport(rig, out)) {
        comfort["min_parallax"] = c->range.minParallax;
        comfort["max_parallax"] = c->range.maxParallax;
        comfort["min_parallax_percent"] = 100.0 * c->range.minParallax;
        comfort["max_parallax_percent"] = 100.0 * c->range.maxParallax;
        comfort["nearest_distance"] = c->range.nearestDistance;
        comfort["farthest_distance"] = c->range.farthestDistance;
        comfort["comfortable"] = c->range.comfortable;
        comfort["why"] = c->range.why;
        comfort["text"] = c->line;
    }
    const std::optional<session::ComfortReport> range = session::comfortReport(rig, out);
    const std::optional<session::ScreenComfortReport> screen = session::screenComfortReport(p, range);
    if (screen) {  // screen_width= (and viewing_distance=): the report against the screen
        const ScreenComfort& s = screen->comfort;
        py::dict sd;
        sd["width_cm"] = s.screen.widthCm;
        sd["viewing_distance_cm"] = s.screen.viewingDistanceCm;
        sd["budget"] = s.budget.fraction;
        sd["budget_cm"] = s.budget.fraction * s.screen.widthCm;
        sd["desktop"] = s.budget.desktop;
        sd["pair_views"] = s.pairViews;
        sd["min_parallax_cm"] = s.minParallaxCm;
        sd["max_parallax_cm"] = s.maxParallaxCm;
        sd["infinity_parallax_cm"] = s.infinityParallaxCm;
        sd["separation_rule"] = s.separationRule;
        sd["nearest_vergence_deg"] = s.nearestVergenceDeg;
        sd["farthest_vergence_deg"] = s.farthestVergenceDeg;
        sd["screen_vergence_deg"] = s.screenVergenceDeg;
        sd["comfortable"] = s.comfortable;
        sd["why"] = s.why;
        sd["text"] = screen->line;
        comfort["screen"] = sd;
    }
    r.comfort = comfort;
    py::list notes;
    for (const std::string& n : p.notes) notes.append(n);
    for (const std::string& w : session::renderWarnings(p, out, range, screen)) notes.append(w);
    rd["notes"] = notes;  // what --convergence/--separation auto chose, and warnings
    rd["view_cone"] = p.viewConeDegrees;

    // Composites first (they read the views), then the views leave as arrays.
    compose.baseline = rig.interaxial;
    compose.convergence = rig.convergence;
    py::dict composites;
    for (const std::string& f : formats) {
        if (check(composite::findFormat(f)).colourAndDepth) {  // rgbd: the centre view's pair
            session::ColourAndDepth pair = check(session::colourAndDepthOf(out, rig, "format=" + f));
            composites[py::str(f)] = composeOne(f, pair.images, compose, nullptr, false);
            continue;
        }
        composites[py::str(f)] = composeOne(f, out.color, compose, job.backend.get(), job.gpu);
    }
    r.composites = composites;
    std::vector<std::string> written;
    // The images and a still's report are one set (all written, or none), as `mvr render`'s.
    const std::string& reportJson = recipe.outputs.reportJson;
    std::vector<session::ExtraFile> extra;
    if (!plan && !reportJson.empty())
        extra.push_back({reportJson, session::comfortJson(p, range, screen), "report_json"});
    if (const std::string& outDir = recipe.outputs.directory; !outDir.empty() || !extra.empty()) {
        Status s;
        {
            py::gil_scoped_release release;
            std::unique_lock<std::mutex> lock(gpuMutex(), std::defer_lock);
            if (job.gpu) lock.lock();
            session::FrameOutputs outputs = session::frameOutputs(p);
            outputs.formats = formats;
            outputs.compose = compose;
            if (outDir.empty()) outputs.views = outputs.composites = outputs.depth = outputs.cameras = false;
            auto files = plan ? session::writeFrameFolder(outDir, *plan, frame, out, p.rig,
                                                          outputs, job.backend.get())
                              : session::writeOutputs(outDir.empty() ? "." : outDir, out, p.rig,
                                                      outputs, job.backend.get(), {}, extra);
            if (files) written = std::move(files->paths);
            s = files ? Status() : files.status();
        }
        if (!s) throwStatus(s);
    }
    r.written = py::cast(written);
    if (plan) r.frame = py::int_(frame);
    const py::ssize_t n = py::ssize_t(out.color.size()), h = p.settings.height,
                      w = p.settings.width;
    const bool hasDepth = int(out.depth.size()) == n;
    if (!block) throwStatus(internalError("no output block for the views"));
    {
        py::gil_scoped_release release;
        r.copiedViews = settle(out.color, *block);
        if (hasDepth) r.copiedViews += settle(out.depth, *block);
    }
    r.color = adoptBlock(block, block->color(), {n, h, w, 4});
    r.depth = hasDepth ? py::object(adoptBlock(block, block->depth(), {n, h, w})) : py::none();
    // Every view's camera (mvr/session/cameras.h) and the depth as distances along the axis.
    const std::vector<session::ViewCamera> cams = session::viewCameras(rig, int(w), int(h));
    py::object ns = py::module_::import("types").attr("SimpleNamespace");
    auto matrix = [](const glm::mat4& m) {  // row-major numpy (4, 4)
        py::array_t<double> a({4, 4});
        auto v = a.mutable_unchecked<2>();
        for (int row = 0; row < 4; ++row)
            for (int col = 0; col < 4; ++col) v(row, col) = m[col][row];
        return a;
    };
    py::list views;
    for (const session::ViewCamera& c : cams) {
        py::array_t<double> k({3, 3});
        auto kv = k.mutable_unchecked<2>();
        for (int row = 0; row < 3; ++row)
            for (int col = 0; col < 3; ++col) kv(row, col) = 0.0;
        kv(0, 0) = c.fx, kv(1, 1) = c.fy, kv(0, 2) = c.cx, kv(1, 2) = c.cy, kv(2, 2) = 1.0;
        py::dict intrinsics;
        intrinsics["fx"] = c.fx, intrinsics["fy"] = c.fy, intrinsics["cx"] = c.cx,
        intrinsics["cy"] = c.cy, intrinsics["matrix"] = k;
        views.append(ns(py::arg("world_from_camera") = matrix(c.worldFromCamera),
                        py::arg("view_matrix") = matrix(c.viewMatrix),
                        py::arg("projection") = matrix(c.projection),
                        py::arg("intrinsics") = intrinsics, py::arg("near") = c.near,
                        py::arg("far") = c.far));
    }
    r.views = views;
    for (const session::ViewCamera& c : cams)
        r.depthToDistance.emplace_back(c.projection[2][2], c.projection[3][2]);
    return r;
}

}  // namespace

namespace {

/// direct=True (mvr/session/direct.h): the lenticular panel composed from the views' rows, as
/// `mvr render --direct`; the result holds it in composites["lenticular"], no views (color and
/// depth None).
RenderResult renderDirect(Job& job) {
    const session::Prepared& p = job.prepared;
    const session::RenderRecipe& recipe = job.keywords.recipe;
    session::FrameOutputs outputs = session::frameOutputs(p);
    const std::string& outDir = recipe.outputs.directory;
    if (outDir.empty()) outputs.views = outputs.depth = outputs.cameras = false;
    for (const auto& [given, keyword] :
         {std::pair{!recipe.outputs.reportJson.empty(), "report_json"},
          std::pair{!recipe.viewRange.empty(), "view_range"}}) {
        if (given)
            throwStatus(usageError(fmt::format(
                "direct: keeps no view, so {} has nothing to read (leave one of them out)",
                keyword)));
    }
    std::vector<std::string> notes = p.notes;
    if (Status s = session::checkDirect(p, outputs, job.surfaces, *job.backend, job.backendName,
                                        job.method, &notes);
        !s) {
        // The keyword's spelling in the message: direct=, not --direct.
        std::string m = s.message();
        if (m.rfind("--direct", 0) == 0) m = "direct" + m.substr(8);
        throwStatus(Status(s.code(), m));
    }
    Result<Image> panel = usageError("");
    double ms = 0.0;
    {
        py::gil_scoped_release release;
        const auto start = std::chrono::steady_clock::now();
        panel = session::renderDirectLenticular(*job.backend, p.scene, p.rig, p.settings,
                                                job.method, outputs.compose.lenticular);
        ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
                 .count();
    }
    Image image = check(std::move(panel));
    std::vector<std::string> written;
    if (!outDir.empty()) {
        Result<session::WrittenFrame> files = usageError("");
        {
            py::gil_scoped_release release;
            files = session::writeDirectPanel(outDir, image, p.rig, outputs, job.backend.get(),
                                              job.method);
        }
        written = check(std::move(files)).paths;
    }
    RenderResult r = resultOf(job, p.rig, job.method, "", ms);
    r.color = py::none();
    r.depth = py::none();
    py::dict rd = r.rig;
    py::list noteList;
    for (const std::string& n : notes) noteList.append(n);
    rd["notes"] = noteList;
    rd["view_cone"] = p.viewConeDegrees;
    r.comfort = py::dict();
    py::dict composites;
    composites["lenticular"] = imageArray(std::move(image));
    r.composites = composites;
    r.written = py::cast(written);
    r.views = py::list();
    return r;
}

}  // namespace

RenderResult render(const py::object& models, const py::kwargs& kwargs) {
    std::unique_ptr<Job> job = makeJob(renderKeywords(models, kwargs, /*sequence=*/false));
    if (job->keywords.recipe.outputs.direct) return renderDirect(*job);
    return renderFrame(*job, job->prepared.scene, job->prepared.rig, nullptr, 0);
}

Sequence::Sequence(const py::object& models, const py::kwargs& kwargs) {
    RenderKeywords keywords = renderKeywords(models, kwargs, /*sequence=*/true);
    if (keywords.recipe.outputs.direct)
        throwStatus(usageError("direct: renders a still; a sequence's frames need their views "
                               "(leave direct out)"));
    if (Status s = session::checkSequence(keywords.recipe.sequence); !s) throwStatus(s);
    mPlan = check(session::planSequence(keywords.recipe.sequence));
    mJob = makeJob(std::move(keywords));
    mStepper = std::make_unique<session::FrameStepper>(mJob->prepared, mPlan);
}

Sequence::~Sequence() = default;

RenderResult Sequence::next() {
    if (mNext >= mPlan.todo.size()) throw py::stop_iteration();
    const int f = mPlan.todo[mNext++];
    Result<Rig> rig = usageError("");
    {
        py::gil_scoped_release release;
        rig = mStepper->advance(f);
    }
    return renderFrame(*mJob, mStepper->scene(), check(std::move(rig)), &mPlan, f);
}

}  // namespace mvr::python
