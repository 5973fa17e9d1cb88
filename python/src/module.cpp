// python/src/module.cpp — mvr._core, the pybind11 module behind `import mvr`.
//
// The keywords of render() and compose() are the options of `mvr render` / `mvr compose`: they
// are read into the session library's RenderRecipe / ComposeOptions (keywords.cpp, no
// command-line code), and session::prepare() and session::writeOutputs() do what they do for
// `mvr render`, so the scene, the rig, the validation, the images and the files are the
// tool's. Images leave as numpy arrays
// whose base is a capsule owning the C++ memory the backend rendered into: render() hands the
// backend an OutputBlock (RenderSettings::output), N views back to back, and returns it as the
// (N, H, W, 4) and (N, H, W) arrays without a copy (RenderResult.copied_views counts views a
// backend left elsewhere and that were copied in: none on the backends of this build). The GIL is released while a
// scene loads, renders and composes; every call makes its own backend, and renders on a GPU
// backend (one driver context per thread) are serialised.
#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include <fmt/core.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "keywords.h"

#include "mvr/backends.h"
#include "mvr/composite/compose.h"
#include "mvr/composite/jpeg.h"
#include "mvr/core/image.h"
#include "mvr/core/mesh.h"
#include "mvr/session/outputs.h"
#include "mvr/session/prepare.h"
#include "mvr/session/surfaces.h"

namespace py = pybind11;

namespace mvr::python {
namespace {

// ---- arrays that own C++ buffers -------------------------------------------------------------
template <class V>
py::array adopt(V&& data, std::vector<py::ssize_t> shape) {
    using E = typename std::decay_t<V>::value_type;
    auto* owner = new std::decay_t<V>(std::move(data));
    py::capsule base(owner, [](void* p) { delete static_cast<std::decay_t<V>*>(p); });
    return py::array_t<E>(shape, owner->data(), base);
}

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

py::array imageArray(Image&& image) {
    const py::ssize_t h = image.height, w = image.width;
    return adopt(std::move(image.rgba), {h, w, 4});
}

// ---- rendering -------------------------------------------------------------------------------
std::mutex& gpuMutex() {
    static std::mutex m;
    return m;
}

struct RenderResult {
    py::object color, depth, method, note, backend, rig, comfort, composites, scene, triangles;
    py::object size, shading, elapsedMs, written;
    int copiedViews = 0;  ///< images the backend left outside the output block (copied in)
};

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

RenderResult render(const py::object& models, const py::kwargs& kwargs) {
    const RenderKeywords keywords = renderKeywords(models, kwargs);
    const session::RenderRecipe& recipe = keywords.recipe;
    std::string backendName =
        !recipe.backend.empty() ? recipe.backend
                                : (backendNames().empty() ? "" : backendNames().front());
    std::string method = recipe.method;

    Result<session::Prepared> prepared = usageError("");
    std::shared_ptr<OutputBlock> block;
    Result<RenderOutput> rendered = usageError("");
    std::unique_ptr<Backend> backend;
    double ms = 0.0;
    bool gpu = false;
    {
        py::gil_scoped_release release;
        prepared = session::prepare(recipe);
        // The views are rendered straight into the memory the arrays will own (zero copy),
        // when the request is within the budget every backend checks first.
        if (prepared && framebufferBytes(prepared->rig.viewCount(), prepared->settings.width,
                                         prepared->settings.height) <= kMaxFramebufferBytes) {
            block = std::make_shared<OutputBlock>(
                prepared->rig.viewCount(), prepared->settings.width, prepared->settings.height);
            prepared->settings.output = block.get();
        }
        Result<StereoSurfaces> surfaces = session::buildSurfaces(recipe.surfaces);
        if (prepared && !surfaces) prepared = surfaces.status();
        if (prepared) {
            if (auto entry = findBackend(backendName)) gpu = (*entry)->gpu;
            std::unique_lock<std::mutex> lock(gpuMutex(), std::defer_lock);
            if (gpu) lock.lock();
            Result<std::unique_ptr<Backend>> made = makeBackend(backendName);
            if (!made) {
                rendered = made.status();
            } else {
                backend = std::move(made).value();
                if (method.empty()) method = backend->defaultMethod();
                if (Status s = backend->supports(method); !s) {
                    rendered = s;
                } else {
                    const auto start = std::chrono::steady_clock::now();
                    rendered =
                        backend->render(prepared->scene, prepared->rig, prepared->settings, method);
                    if (rendered) {
                        if (Status st = session::applySurfaces(*surfaces, prepared->rig, *rendered);
                            !st)
                            rendered = st;
                    }
                    ms = std::chrono::duration<double, std::milli>(
                             std::chrono::steady_clock::now() - start)
                             .count();
                }
            }
        }
    }
    const session::Prepared& p = check(std::move(prepared));
    RenderOutput out = check(std::move(rendered));
    // The formats with a display preset's (display=, as `mvr render --display`).
    const std::vector<std::string>& formats = p.formats;
    composite::ComposeOptions compose = p.compose;
    if (int(out.color.size()) != p.rig.viewCount())
        throwStatus(internalError(fmt::format("backend returned {} images for {} views",
                                              out.color.size(), p.rig.viewCount())));

    RenderResult r;
    r.method = py::str(out.method);
    r.note = py::str(out.note);
    r.backend = py::str(backendName);
    r.scene = py::str(p.sceneName);
    r.triangles = py::int_(p.scene.triangleCount());
    r.size = py::make_tuple(p.settings.width, p.settings.height);
    r.shading = py::str(std::string(shadingName(p.settings.shading)));
    r.elapsedMs = py::float_(ms);
    const Rig& rig = p.rig;
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
    for (const std::string& f : formats)
        composites[py::str(f)] = composeOne(f, out.color, compose, backend.get(), gpu);
    r.composites = composites;
    std::vector<std::string> written;
    if (const std::string& outDir = recipe.outputs.directory; !outDir.empty()) {
        Status s;
        {
            py::gil_scoped_release release;
            std::unique_lock<std::mutex> lock(gpuMutex(), std::defer_lock);
            if (gpu) lock.lock();
            auto files = session::writeOutputs(
                outDir, out, p.rig, {formats, recipe.outputs.depth, compose}, backend.get());
            if (files) written = std::move(files->paths);
            s = files ? Status() : files.status();
        }
        if (!s) throwStatus(s);
    }
    // The report after the files, as `mvr render` writes it (its folder may be the output's).
    const std::string& reportJson = recipe.outputs.reportJson;
    if (!reportJson.empty() &&
        !session::writeTextFile(reportJson, session::comfortJson(p, range, screen)))
        throwStatus(outputError("report_json: cannot write " + reportJson));
    r.written = py::cast(written);
    {
        py::gil_scoped_release release;
        std::unique_lock<std::mutex> lock(gpuMutex(), std::defer_lock);
        if (gpu) lock.lock();
        backend.reset();  // the driver context goes on the thread that used it
    }
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
    return r;
}

// ---- compose ---------------------------------------------------------------------------------
Image imageFromArray(const py::handle& obj, const std::string& what) {
    if (!py::isinstance<py::array>(obj))
        throwParameter(
            fmt::format("{}: expected a numpy array or a file path, got {}", what,
                        std::string(py::str(py::type::handle_of(obj).attr("__name__")))));
    py::array a = py::reinterpret_borrow<py::array>(obj);
    if (!a.dtype().is(py::dtype::of<std::uint8_t>()))
        throwParameter(
            fmt::format("{}: expected dtype uint8, got {}", what, std::string(py::str(a.dtype()))));
    if (a.ndim() != 3 || (a.shape(2) != 3 && a.shape(2) != 4))
        throwStatus(usageError(fmt::format(
            "{}: expected an array of shape (height, width, 4) or (height, width, 3)", what)));
    if (a.shape(0) < 1 || a.shape(1) < 1 || a.shape(0) > 65536 || a.shape(1) > 65536)
        throwStatus(usageError(
            fmt::format("{}: empty or too large image ({}x{})", what, a.shape(1), a.shape(0))));
    auto c = py::array_t<std::uint8_t, py::array::c_style>::ensure(a);
    Image img;
    img.width = int(a.shape(1));
    img.height = int(a.shape(0));
    const std::size_t n = std::size_t(img.width) * img.height;
    const std::uint8_t* src = c.data();
    if (a.shape(2) == 4) {
        img.rgba.assign(src, src + n * 4);
    } else {
        img.rgba.resize(n * 4);
        for (std::size_t i = 0; i < n; ++i) {
            std::memcpy(&img.rgba[i * 4], src + i * 3, 3);
            img.rgba[i * 4 + 3] = 255;
        }
    }
    return img;
}

std::vector<Image> viewsFrom(const py::object& views) {
    std::vector<Image> out;
    if (py::isinstance<py::array>(views)) {
        py::array a = py::reinterpret_borrow<py::array>(views);
        if (a.ndim() == 4) {
            for (py::ssize_t i = 0; i < a.shape(0); ++i)
                out.push_back(imageFromArray(views[py::int_(i)], fmt::format("views[{}]", i)));
            return out;
        }
        throwStatus(
            usageError("views: expected an array of shape (N, height, width, 4) or a list "
                       "of views"));
    }
    if (PyUnicode_Check(views.ptr()) || !py::isinstance<py::sequence>(views))
        throwParameter("views: expected a list of arrays or file paths, or an (N, H, W, 4) array");
    py::sequence seq = py::reinterpret_borrow<py::sequence>(views);
    for (std::size_t i = 0; i < seq.size(); ++i) {
        py::object v = seq[i];
        if (PyUnicode_Check(v.ptr()) || py::hasattr(v, "__fspath__")) {
            std::string path = py::str(py::module_::import("os").attr("fspath")(v));
            Result<std::vector<Image>> read = usageError("");
            {
                py::gil_scoped_release release;
                read = composite::readViewFile(path);
            }
            for (Image& img : check(std::move(read))) out.push_back(std::move(img));
        } else {
            out.push_back(imageFromArray(v, fmt::format("views[{}]", i)));
        }
    }
    return out;
}

py::object composeViews(const py::object& formatObj, const py::object& views,
                        const py::kwargs& kwargs) {
    if (!PyUnicode_Check(formatObj.ptr())) throwParameter("format: expected a string");
    const std::string format = py::str(formatObj);
    ComposeKeywords keywords = composeKeywords(kwargs);
    composite::ComposeOptions& compose = keywords.compose;
    const std::string& output = keywords.output;
    const composite::FormatInfo info = check(composite::findFormat(format));
    std::vector<Image> imgs = viewsFrom(views);
    for (std::size_t i = 1; i < imgs.size(); ++i) {
        if (imgs[i].width != imgs[0].width || imgs[i].height != imgs[0].height)
            throwStatus(usageError(
                fmt::format("views differ in size: view {} is {}x{} but view 0 is {}x{} "
                            "(expected all views of one size)",
                            i, imgs[i].width, imgs[i].height, imgs[0].width, imgs[0].height)));
    }
    const int n = int(imgs.size());
    if (n < info.minViews || n > info.maxViews) {
        const std::string expected = info.minViews == info.maxViews
                                         ? fmt::format("exactly {}", info.minViews)
                                     : info.maxViews >= composite::kAnyViewCount
                                         ? fmt::format("at least {}", info.minViews)
                                         : fmt::format("{} to {}", info.minViews, info.maxViews);
        throwStatus(usageError(fmt::format("format {}: {} view{} given (expected {} views)",
                                           info.name, n, n == 1 ? "" : "s", expected)));
    }
    if (!output
             .empty()) {  // as `mvr compose -o`: a file name (.png .jpg .jpeg .jps .mpo) or a folder
        Status s;
        {
            py::gil_scoped_release release;
            const std::filesystem::path out(output);
            std::string ext = out.extension().string();
            for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
            std::error_code ec;
            if (ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".jps" ||
                ext == ".mpo") {
                if (out.has_parent_path())
                    std::filesystem::create_directories(out.parent_path(), ec);
                s = ec ? outputError(fmt::format("cannot create directory '{}': {}",
                                                 out.parent_path().string(), ec.message()))
                       : composite::writeCompositeFile(format, imgs, compose, out);
            } else {
                std::filesystem::create_directories(out, ec);
                if (ec || !std::filesystem::is_directory(out)) {
                    s = outputError(fmt::format("cannot create output directory '{}': {}",
                                                out.string(),
                                                ec ? ec.message() : "not a directory"));
                } else if (auto path = composite::writeComposite(format, imgs, compose, out);
                           !path) {
                    s = path.status();
                }
            }
        }
        if (!s) throwStatus(s);
    }
    return composeOne(format, imgs, compose, nullptr, false);
}

// ---- the rest --------------------------------------------------------------------------------
py::dict loadMeshPy(const py::object& pathObj) {
    const std::string path = pathOf(pathObj, "path");
    Result<Mesh> loaded = usageError("");
    {
        py::gil_scoped_release release;
        loaded = loadMesh(path);
    }
    Mesh mesh = check(std::move(loaded));
    py::dict d;
    const py::ssize_t v = py::ssize_t(mesh.positions.size());
    auto floats = [](auto& vec, py::ssize_t rows, py::ssize_t cols) {
        std::vector<float> f(reinterpret_cast<const float*>(vec.data()),
                             reinterpret_cast<const float*>(vec.data()) + rows * cols);
        return adopt(std::move(f), {rows, cols});
    };
    d["path"] = path;
    d["positions"] = floats(mesh.positions, v, 3);
    d["normals"] = floats(mesh.normals, py::ssize_t(mesh.normals.size()), 3);
    d["texcoords"] = floats(mesh.texcoords, py::ssize_t(mesh.texcoords.size()), 2);
    const py::ssize_t t = py::ssize_t(mesh.triangleCount());
    mesh.indices.resize(std::size_t(t) * 3);
    d["indices"] = adopt(std::move(mesh.indices), {t, 3});
    d["triangles"] = t;
    return d;
}

py::dict info() {
    py::dict d;
    d["version"] = MVR_VERSION;
    py::dict limits;
    limits["max_views"] = kMaxViews;
    limits["max_view_size"] = 16384;
    limits["max_framebuffer_bytes"] = kMaxFramebufferBytes;
    limits["max_lights"] = kMaxLights;
    d["limits"] = limits;
    py::list list;
    for (const BackendEntry& e : backends()) {
        py::dict b;
        b["name"] = e.name;
        b["description"] = e.description;
        b["gpu"] = e.gpu;
        Result<std::unique_ptr<Backend>> made = usageError("");
        {
            py::gil_scoped_release release;
            std::unique_lock<std::mutex> lock(gpuMutex(), std::defer_lock);
            if (e.gpu) lock.lock();
            made = makeBackend(e.name);
        }
        b["available"] = bool(made);
        if (!made) {
            b["error"] = made.status().message();
            list.append(b);
            continue;
        }
        std::unique_ptr<Backend> be = std::move(made).value();
        py::list lines, methods;
        std::string def;
        std::vector<std::pair<std::string, Status>> ms;
        std::vector<std::string> infoLines;
        {
            py::gil_scoped_release release;
            std::unique_lock<std::mutex> lock(gpuMutex(), std::defer_lock);
            if (e.gpu) lock.lock();
            infoLines = be->info();
            def = be->defaultMethod();
            for (const std::string& m : be->methods()) ms.emplace_back(m, be->supports(m));
            be.reset();
        }
        for (const std::string& l : infoLines) lines.append(l);
        for (const auto& [m, s] : ms) {
            py::dict md;
            md["name"] = m;
            md["supported"] = bool(s);
            md["reason"] = s ? std::string() : s.message();
            methods.append(md);
        }
        b["default_method"] = def;
        b["info"] = lines;
        b["methods"] = methods;
        list.append(b);
    }
    d["backends"] = list;
    py::list fmts;
    for (const composite::FormatInfo& f : composite::formats()) {
        py::dict fd;
        fd["name"] = std::string(f.name);
        fd["min_views"] = f.minViews;
        fd["max_views"] = f.maxViews;
        fd["extension"] = std::string(f.extension);
        fd["summary"] = std::string(f.summary);
        fmts.append(fd);
    }
    d["formats"] = fmts;
    return d;
}

void writePngPy(const py::object& pathObj, const py::object& arrayObj) {
    const std::string path = pathOf(pathObj, "path");
    if (!py::isinstance<py::array>(arrayObj)) throwParameter("array: expected a numpy array");
    py::array a = py::reinterpret_borrow<py::array>(arrayObj);
    Status s;
    if (a.dtype().kind() == 'f') {
        if (a.ndim() != 2 || a.shape(0) < 1 || a.shape(1) < 1 || a.shape(0) > 65536 ||
            a.shape(1) > 65536)
            throwStatus(usageError("array: a depth image must be (height, width) float"));
        auto c = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(a);
        DepthImage d(int(a.shape(1)), int(a.shape(0)));
        const float* src = c.data();
        for (std::size_t i = 0; i < d.depth.size(); ++i)  // NaN: nothing drawn
            d.depth[i] = std::isnan(src[i]) ? 1.0f : src[i];
        py::gil_scoped_release release;
        s = writeDepthPng(path, d);
    } else {
        Image img;
        if (a.ndim() == 2 && a.dtype().is(py::dtype::of<std::uint8_t>())) {
            py::array rgb = py::module_::import("numpy").attr("repeat")(
                a.attr("reshape")(a.shape(0), a.shape(1), 1), 3, 2);
            img = imageFromArray(rgb, "array");
        } else {
            img = imageFromArray(a, "array");
        }
        py::gil_scoped_release release;
        s = writePng(path, img);
    }
    if (!s) throwStatus(s);
}

}  // namespace
}  // namespace mvr::python

PYBIND11_MODULE(_core, m) {
    using namespace mvr::python;
    m.doc() = "mvr's C++ library (the _core module behind `import mvr`)";
    static PyObject* err = PyErr_NewExceptionWithDoc(
        "mvr.ParameterError",
        "A keyword of the wrong type or an unknown keyword (both a TypeError and a ValueError).",
        py::make_tuple(py::handle(PyExc_TypeError), py::handle(PyExc_ValueError)).ptr(), nullptr);
    gParameterError = err;
    m.attr("ParameterError") = py::handle(err);

    py::class_<RenderResult>(m, "RenderResult", "What mvr.render() returns.")
        .def_readonly("color", &RenderResult::color, "uint8 (N, H, W, 4): the views, RGBA")
        .def_readonly("depth", &RenderResult::depth,
                      "float32 (N, H, W): window depth in [0, 1] (1 = nothing drawn)")
        .def_readonly("method", &RenderResult::method, "the method that ran")
        .def_readonly("note", &RenderResult::note, "e.g. why 'auto' picked that method")
        .def_readonly("backend", &RenderResult::backend)
        .def_readonly("rig", &RenderResult::rig, "the rig's parameters (dict)")
        .def_readonly("comfort", &RenderResult::comfort,
                      "the comfort report of `mvr render` (dict; empty for one column of views)")
        .def_readonly("composites", &RenderResult::composites,
                      "format name -> array (bytes for mpo / jps), for format=[...]")
        .def_readonly("scene", &RenderResult::scene)
        .def_readonly("copied_views", &RenderResult::copiedViews,
                      "How many view images (colour and depth) were copied into the returned "
                      "arrays because the backend did not render them in place; 0 means the "
                      "arrays are the memory the backend rendered into (no copy).")
        .def_readonly("triangles", &RenderResult::triangles)
        .def_readonly("size", &RenderResult::size, "(width, height) of one view")
        .def_readonly("shading", &RenderResult::shading)
        .def_readonly("elapsed_ms", &RenderResult::elapsedMs)
        .def_readonly("written", &RenderResult::written,
                      "the files written for output=DIR, as `mvr render -o DIR` writes them")
        .def("__len__", [](const RenderResult& r) { return py::len(r.color); })
        .def("__repr__", [](const RenderResult& r) {
            return fmt::format("<mvr.RenderResult {} views of {}x{}, {}:{}>", py::len(r.color),
                               py::cast<int>(r.size[py::int_(0)]),
                               py::cast<int>(r.size[py::int_(1)]), std::string(py::str(r.backend)),
                               std::string(py::str(r.method)));
        });
    m.def("render", &render, py::arg("models") = py::none());
    m.def("compose", &composeViews, py::arg("format"), py::arg("views"));
    m.def("load_mesh", &loadMeshPy, py::arg("path"));
    m.def("info", &info);
    m.def("write_png", &writePngPy, py::arg("path"), py::arg("array"));
}
