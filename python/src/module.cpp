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
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <fmt/core.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "keywords.h"
#include "mesh.h"
#include "render.h"

#include "mvr/backends.h"
#include "mvr/composite/compose.h"
#include "mvr/composite/jpeg.h"
#include "mvr/core/image.h"
#include "mvr/core/mesh.h"
#include "mvr/io/mesh_io.h"
#include "mvr/io/png.h"
#include "mvr/session/cameras.h"
#include "mvr/session/outputs.h"
#include "mvr/session/prepare.h"
#include "mvr/session/rgbd_input.h"
#include "mvr/session/surfaces.h"

namespace py = pybind11;

namespace mvr::python {
namespace {

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
    if (!output.empty()) {
        Status s;
        {
            py::gil_scoped_release release;
            // As `mvr compose -o`: a file name (.png .jpg .jpeg .jps .mpo) or a folder, whole or
            // not at all.
            auto path = session::writeComposed(format, imgs, compose, output);
            if (!path) s = path.status();
        }
        if (!s) throwStatus(s);
    }
    return composeOne(format, imgs, compose, nullptr, false);
}

// ---- from_rgbd: `mvr compose --from-rgbd --display NAME`'s views ---------------------------------
py::array fromRgbd(const py::object& filesObj, const py::object& displayObj,
                   const py::object& depthinessObj, const py::object& focusObj,
                   const py::object& positionObj) {
    std::vector<std::string> files;
    if (PyUnicode_Check(filesObj.ptr()) || py::isinstance<py::bytes>(filesObj) ||
        py::hasattr(filesObj, "__fspath__")) {
        files.push_back(pathOf(filesObj, "files"));
    } else {
        if (!py::isinstance<py::sequence>(filesObj))
            throwParameter("files: expected a file name, or a list of one or two (colour, depth)");
        for (const py::handle& f : filesObj) files.push_back(pathOf(f, "files"));
    }
    if (!PyUnicode_Check(displayObj.ptr())) throwParameter("display: expected a display name");
    const DisplayPreset display = check(findDisplay(std::string(py::str(displayObj))));
    std::optional<composite::DepthPosition> position;
    if (!positionObj.is_none()) {
        if (!PyUnicode_Check(positionObj.ptr()))
            throwParameter("rgbd_depth_position: expected right, left, top or bottom");
        position = check(composite::parseDepthPosition(std::string(py::str(positionObj))));
    }
    auto number = [](const py::object& o, const char* name, double lo,
                     double hi) -> std::optional<double> {
        if (o.is_none()) return std::nullopt;
        if (!py::isinstance<py::float_>(o) && !py::isinstance<py::int_>(o))
            throwParameter(fmt::format("{}: expected a number", name));
        const double v = o.cast<double>();
        if (!(v >= lo && v <= hi))
            throwStatus(usageError(fmt::format("{} {} is out of range (expected {}..{})", name, v,
                                               lo, hi)));
        return v;
    };
    const std::optional<double> depthinessGiven = number(depthinessObj, "depthiness", 0.0, 2.0);
    const std::optional<double> focusGiven = number(focusObj, "focus", -0.05, 0.05);
    Result<std::vector<Image>> views = usageError("");
    {
        py::gil_scoped_release release;
        Result<session::RgbdInput> input = session::readRgbdInput(files, position);
        if (!input) {
            views = input.status();
        } else {
            const session::RgbdLook look = session::rgbdLook(*input, depthinessGiven, focusGiven);
            views = session::viewsFromRgbd(*input, display, look.depthiness, look.focus);
        }
    }
    std::vector<Image> imgs = check(std::move(views));
    const py::ssize_t n = py::ssize_t(imgs.size()), h = imgs[0].height, w = imgs[0].width;
    py::array_t<std::uint8_t> out({n, h, w, py::ssize_t(4)});
    for (py::ssize_t i = 0; i < n; ++i)
        std::memcpy(out.mutable_data(i), imgs[std::size_t(i)].rgba.data(),
                    imgs[std::size_t(i)].rgba.size());
    return out;
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
    // What backend= takes: the backends below, then "auto" (the fastest of them per request).
    d["backend_choices"] = backendChoices();
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

void writePngPy(const py::object& pathObj, const py::object& arrayObj,
                const std::string& compression) {
    const std::string path = pathOf(pathObj, "path");
    const PngCompression mode = check(parsePngCompression(compression));
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
        s = writeDepthPng(path, d, mode);
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
        s = writePng(path, img, mode);
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
        .def_readonly("color", &RenderResult::color,
                      "uint8 (N, H, W, 4): the views, RGBA (None with direct=True: the panel "
                      "is composites['lenticular'])")
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
        .def_readonly("views", &RenderResult::views,
                      "per view: world_from_camera, view_matrix, projection (4x4 row-major, "
                      "OpenGL camera: -Z forward, +Y up), intrinsics (fx, fy, cx, cy, matrix: "
                      "OpenCV pinhole, pixel (0, 0)'s centre at (0, 0)), near, far")
        .def_property_readonly(
            "distance",
            [](const RenderResult& r) -> py::object {
                if (r.depth.is_none()) return py::none();
                auto depth = py::array_t<float, py::array::c_style | py::array::forcecast>(r.depth);
                if (depth.ndim() != 3 || std::size_t(depth.shape(0)) != r.depthToDistance.size())
                    return py::none();
                py::array_t<float> out({depth.shape(0), depth.shape(1), depth.shape(2)});
                const std::size_t pixels = std::size_t(depth.shape(1)) * std::size_t(depth.shape(2));
                const float* src = depth.data();
                float* dst = out.mutable_data();
                {
                    py::gil_scoped_release release;
                    for (std::size_t v = 0; v < r.depthToDistance.size(); ++v) {
                        const auto [p22, p32] = r.depthToDistance[v];
                        for (std::size_t i = 0; i < pixels; ++i)
                            dst[v * pixels + i] =
                                mvr::session::distanceOfDepth(p22, p32, src[v * pixels + i]);
                    }
                }
                return out;
            },
            "float32 (N, H, W), computed on access from .depth: eye-space distance along the "
            "view axis, world units; inf where nothing was drawn (None without depth)")
        .def_readonly("size", &RenderResult::size, "(width, height) of one view")
        .def_readonly("shading", &RenderResult::shading)
        .def_readonly("elapsed_ms", &RenderResult::elapsedMs)
        .def_readonly("written", &RenderResult::written,
                      "the files written for output=DIR, as `mvr render -o DIR` writes them")
        .def_readonly("frame", &RenderResult::frame,
                      "the frame of a sequence (mvr.render_sequence()); None for mvr.render()")
        .def("__len__", [](const RenderResult& r) { return py::len(r.color); })
        .def("__repr__", [](const RenderResult& r) {
            return fmt::format("<mvr.RenderResult {} views of {}x{}, {}:{}>", py::len(r.color),
                               py::cast<int>(r.size[py::int_(0)]),
                               py::cast<int>(r.size[py::int_(1)]), std::string(py::str(r.backend)),
                               std::string(py::str(r.method)));
        });
    m.def("render", &render, py::arg("models") = py::none());
    py::class_<Sequence>(m, "RenderSequence",
                        "What mvr.render_sequence() returns: one RenderResult per frame.")
        .def(py::init<const py::object&, const py::kwargs&>(), py::arg("models") = py::none())
        .def("__iter__", [](Sequence& s) -> Sequence& { return s; })
        .def("__next__", &Sequence::next)
        .def("__len__", &Sequence::size)
        .def_property_readonly("frames", &Sequence::frames, "the frames it renders, in order");
    m.def("compose", &composeViews, py::arg("format"), py::arg("views"));
    m.def("from_rgbd", &fromRgbd, py::arg("files"), py::arg("display"),
          py::arg("depthiness") = py::none(), py::arg("focus") = py::none(),
          py::arg("rgbd_depth_position") = py::none());
    m.def("load_mesh", &loadMeshPy, py::arg("path"));
    defineMesh(m);
    m.def("info", &info);
    m.def("write_png", &writePngPy, py::arg("path"), py::arg("array"),
          py::arg("png_compression") = "fast");
}
