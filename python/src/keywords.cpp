#include "keywords.h"
#include "mesh.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <map>
#include <span>
#include <vector>

#include <fmt/core.h>

#include "mvr/composite/lenticular.h"
#include "mvr/composite/rgbd.h"

namespace mvr::python {

PyObject* gParameterError = nullptr;

void throwParameter(const std::string& message) {
    PyErr_SetString(gParameterError, message.c_str());
    throw py::error_already_set();
}

void throwStatus(const Status& s) {
    PyObject* type = PyExc_RuntimeError;
    const std::string& m = s.message();
    switch (s.code()) {
        case ErrorCode::Usage: type = PyExc_ValueError; break;
        case ErrorCode::Input:
            type = m.find("not found") != std::string::npos ||
                           m.find("No such file") != std::string::npos ||
                           m.find("does not exist") != std::string::npos
                       ? PyExc_FileNotFoundError
                       : PyExc_OSError;
            break;
        case ErrorCode::Output: type = PyExc_OSError; break;
        default: type = PyExc_RuntimeError; break;
    }
    PyErr_SetString(type, m.c_str());
    throw py::error_already_set();
}

std::string pathOf(const py::handle& p, const char* what) {
    if (PyUnicode_Check(p.ptr())) return py::str(p);
    if (py::hasattr(p, "__fspath__")) {
        py::object s = py::module_::import("os").attr("fspath")(p);
        if (PyUnicode_Check(s.ptr())) return py::str(s);
    }
    throwParameter(fmt::format("{}: expected a file path (str or os.PathLike)", what));
}

namespace {

// ---- one keyword -----------------------------------------------------------------------------
enum class Kind {
    Flag,         ///< True / False
    Int,          ///< an integer (not a bool)
    Float,        ///< a number
    FloatOrAuto,  ///< a number or "auto" (a string holding a number is read as one)
    Text,         ///< a string, os.PathLike, or an (a, b) pair of integers for "axb"
    TextOrNumber, ///< a string, or a number (not a bool) as its shortest text ("auto" or 1.5)
    TextList,     ///< a string or a list of them (a repeatable option)
    File,         ///< Text naming a file that exists
    Numbers,      ///< a string ("1,2,3", a file name), or numbers: a sequence, nested ones
                  ///< (a 4x4 list) or a numpy array, as "n,n,..."
};

struct Spec {
    const char* name;
    Kind kind;
};

struct Value {
    bool flag = false;
    long long integer = 0;
    double number = 0.0;
    bool isAuto = false;
    std::string text;
    std::vector<std::string> list;
};

std::string typeName(const py::handle& v) {
    return py::str(py::type::handle_of(v).attr("__name__"));
}

std::string optionName(const std::string& key) {
    std::string name = "--" + key;
    std::replace(name.begin(), name.end(), '_', '-');
    return name;
}

double number(const std::string& key, const py::handle& v) {
    if (PyBool_Check(v.ptr())) throwParameter(fmt::format("{}: expected a number, got a bool", key));
    if (PyIndex_Check(v.ptr())) {
        py::object i = py::reinterpret_steal<py::object>(PyNumber_Index(v.ptr()));
        const double d = PyLong_AsDouble(i.ptr());
        if (d == -1.0 && PyErr_Occurred()) {
            PyErr_Clear();
            throwStatus(usageError(fmt::format("{} {} is out of range", optionName(key),
                                               std::string(py::str(i)))));
        }
        return d;
    }
    if (!PyFloat_Check(v.ptr()) && !py::hasattr(v, "__float__"))
        throwParameter(fmt::format("{}: expected a number, got {}", key, typeName(v)));
    const double d = PyFloat_AsDouble(v.ptr());
    if (d == -1.0 && PyErr_Occurred()) throw py::error_already_set();
    return d;
}

std::string text(const std::string& key, const py::handle& v, bool pairNote) {
    if (PyUnicode_Check(v.ptr())) return py::str(v);
    if (py::hasattr(v, "__fspath__")) {
        py::object p = py::module_::import("os").attr("fspath")(v);
        if (PyUnicode_Check(p.ptr())) return py::str(p);
    }
    // (W, H) / (C, R) pairs for size, view_grid, quilt, lenticular_screen.
    if ((PyTuple_Check(v.ptr()) || PyList_Check(v.ptr())) && py::len(v) == 2) {
        py::sequence s = py::reinterpret_borrow<py::sequence>(v);
        if (!PyBool_Check(s[0].ptr()) && !PyBool_Check(s[1].ptr()) && PyIndex_Check(s[0].ptr()) &&
            PyIndex_Check(s[1].ptr())) {
            auto index = [](const py::handle& h) {
                return std::string(py::str(py::reinterpret_steal<py::object>(PyNumber_Index(h.ptr()))));
            };
            return index(s[0]) + "x" + index(s[1]);
        }
    }
    throwParameter(fmt::format("{}: expected a string{}, got {}", key,
                               pairNote ? " (or a (width, height) pair)" : "", typeName(v)));
}

/// Kind::Numbers: the leaves of a (nested) sequence or array, in order, as "n,n,...".
std::string numbersText(const std::string& key, const py::handle& v) {
    if (PyUnicode_Check(v.ptr()) || py::hasattr(v, "__fspath__")) return text(key, v, false);
    py::object seq = py::reinterpret_borrow<py::object>(v);
    if (py::hasattr(seq, "tolist")) seq = seq.attr("tolist")();  // numpy
    std::string out;
    std::function<void(const py::handle&)> walk = [&](const py::handle& h) {
        if (PyTuple_Check(h.ptr()) || PyList_Check(h.ptr())) {
            for (py::handle item : h) walk(item);
            return;
        }
        if (PyBool_Check(h.ptr()) || !(PyFloat_Check(h.ptr()) || PyIndex_Check(h.ptr())))
            throwParameter(fmt::format("{}: expected numbers, got {}", key, typeName(h)));
        out += (out.empty() ? "" : ",") + fmt::format("{}", number(key, h));
    };
    walk(seq);
    return out;
}

/// The keywords, type-checked in the caller's order; None is "not given".
std::map<std::string, Value> readKeywords(const char* fn, std::span<const Spec> specs,
                                          const py::dict& kwargs) {
    std::map<std::string, Value> out;
    for (auto [k, v] : kwargs) {
        const std::string key = py::str(k);
        auto spec = std::find_if(specs.begin(), specs.end(),
                                 [&](const Spec& s) { return key == s.name; });
        if (spec == specs.end()) {
            std::string list;
            for (const Spec& s : specs) list += (list.empty() ? "" : ", ") + std::string(s.name);
            throwParameter(fmt::format("{}() got an unexpected keyword argument '{}' (options: {})",
                                       fn, key, list));
        }
        if (v.is_none()) continue;
        Value value;
        switch (spec->kind) {
            case Kind::Flag:
                if (!PyBool_Check(v.ptr()))
                    throwParameter(
                        fmt::format("{}: expected True or False, got {}", key, typeName(v)));
                value.flag = v.ptr() == Py_True;
                break;
            case Kind::Int: {
                if (PyBool_Check(v.ptr()))
                    throwParameter(fmt::format("{}: expected an integer, got a bool", key));
                if (!PyIndex_Check(v.ptr()))
                    throwParameter(
                        fmt::format("{}: expected an integer, got {}", key, typeName(v)));
                py::object i = py::reinterpret_steal<py::object>(PyNumber_Index(v.ptr()));
                int overflow = 0;
                value.integer = PyLong_AsLongLongAndOverflow(i.ptr(), &overflow);
                if (overflow || value.integer < INT_MIN || value.integer > INT_MAX)
                    throwStatus(usageError(fmt::format("{} {} is out of range", optionName(key),
                                                       std::string(py::str(i)))));
                break;
            }
            case Kind::Float: value.number = number(key, v); break;
            case Kind::FloatOrAuto:
                if (PyUnicode_Check(v.ptr())) {
                    value.text = py::str(v);
                    if (value.text == "auto") {
                        value.isAuto = true;
                        break;
                    }
                    try {
                        std::size_t used = 0;
                        value.number = std::stod(value.text, &used);
                        if (used != value.text.size()) throw std::invalid_argument(value.text);
                    } catch (const std::exception&) {
                        throwStatus(usageError(
                            fmt::format("{}: '{}' is not a number (expected a number or auto)",
                                        optionName(key), value.text)));
                    }
                    break;
                }
                value.number = number(key, v);
                break;
            case Kind::Text: value.text = text(key, v, true); break;
            case Kind::TextOrNumber:
                if (PyUnicode_Check(v.ptr())) {
                    value.text = py::str(v);
                } else {
                    value.number = number(key, v);
                    value.text = fmt::format("{}", value.number);
                }
                break;
            case Kind::Numbers: value.text = numbersText(key, v); break;
            case Kind::File: {
                value.text = text(key, v, false);
                std::error_code ec;
                if (!std::filesystem::exists(value.text, ec)) {
                    PyErr_SetString(PyExc_FileNotFoundError,
                                    fmt::format("{}: {}: file not found", key, value.text).c_str());
                    throw py::error_already_set();
                }
                break;
            }
            case Kind::TextList:
                if (PyUnicode_Check(v.ptr())) {
                    value.list.push_back(py::str(v));
                } else if (PyTuple_Check(v.ptr()) || PyList_Check(v.ptr())) {
                    for (py::handle item : v) value.list.push_back(text(key, item, false));
                } else {
                    throwParameter(fmt::format("{}: expected a string or a list of strings", key));
                }
                break;
        }
        out[key] = std::move(value);
    }
    return out;
}

// ---- the composite options (`mvr render` and `mvr compose`) -----------------------------------
constexpr Spec kComposeSpecs[] = {
    {"swap_eyes", Kind::Flag},          {"cross_eyed", Kind::Flag},
    {"quilt", Kind::Text},              {"jpeg_quality", Kind::Int},
    {"base_viewpoint", Kind::Int},      {"lenticular_calibration", Kind::File},
    {"lenticular_pitch", Kind::Float},  {"lenticular_slope", Kind::Float},
    {"lenticular_center", Kind::Float}, {"lenticular_dpi", Kind::Float},
    {"lenticular_screen", Kind::Text},  {"lenticular_bgr", Kind::Flag},
    {"lenticular_invert_views", Kind::Flag}, {"lenticular_flip_x", Kind::Flag},
    {"lenticular_flip_y", Kind::Flag}, {"rgbd_depth_position", Kind::Text},
    {"depthiness", Kind::Float},       {"focus", Kind::Float},
};

/// The CLI's range message (tools/cli/validators.h), as `mvr compose --jpeg-quality 500`
/// prints it: "--jpeg-quality: 500 is out of range (must be 1..100)".
template <class T>
void inRange(const char* option, T value, T lo, T hi) {
    if (!(value >= lo && value <= hi))
        throwStatus(usageError(
            fmt::format("{}: {} is out of range (must be {:g}..{:g})", option, value,
                        double(lo), double(hi))));
}

/// The composite options of `kw` into `o`: a calibration first, then the single values over it.
void composeOptions(const std::map<std::string, Value>& kw, composite::ComposeOptions& o,
                    bool withStereoMetadata) {
    auto get = [&](const char* name) -> const Value* {
        auto it = kw.find(name);
        return it == kw.end() ? nullptr : &it->second;
    };
    if (auto* v = get("swap_eyes")) o.swapEyes = v->flag;
    if (auto* v = get("cross_eyed")) o.crossEyed = v->flag;
    if (auto* v = get("quilt")) {
        auto grid = composite::parseQuiltGrid(v->text);
        if (!grid) throwStatus(grid.status());  // it names --quilt and the value
        o.quiltColumns = grid->first;
        o.quiltRows = grid->second;
    }
    if (auto* v = get("jpeg_quality")) {
        inRange("--jpeg-quality", v->integer, 1LL, 100LL);
        o.jpegQuality = int(v->integer);
    }
    if (auto* v = get("base_viewpoint")) {
        inRange("--base-viewpoint", v->integer, 1LL, 4096LL);
        o.baseViewpoint = int(v->integer);
    }
    if (withStereoMetadata) {
        if (auto* v = get("baseline")) {
            inRange("--baseline", v->number, 0.0, 1.0e6);
            o.baseline = v->number;
        }
        if (auto* v = get("convergence")) {
            inRange("--convergence", v->number, 0.0, 1.0e9);
            o.convergence = v->number;
        }
    }
    if (auto* v = get("rgbd_depth_position")) {
        auto p = composite::parseDepthPosition(v->text);
        if (!p) throwStatus(p.status());  // it names --rgbd-depth-position and the value
        o.rgbdDepth = *p;
    }
    if (auto* v = get("depthiness")) {
        inRange("--depthiness", v->number, 0.0, 2.0);
        o.depthiness = v->number;
    }
    if (auto* v = get("focus")) {
        inRange("--focus", v->number, -0.05, 0.05);
        o.focus = v->number;
    }
    composite::LenticularCalibration& cal = o.lenticular;
    if (auto* v = get("lenticular_calibration")) {
        auto loaded = composite::readLookingGlassCalibration(v->text);
        if (!loaded) throwStatus(usageError("--lenticular-calibration: " + loaded.status().message()));
        cal = *loaded;
    }
    auto positive = [](const char* option, double d, double most) {
        if (!(d > 0.0 && d <= most))
            throwStatus(usageError(fmt::format(
                "{}: {} is out of range (must be > 0 and at most {:g})", option, d, most)));
    };
    if (auto* v = get("lenticular_pitch")) {
        positive("--lenticular-pitch", v->number, composite::kMaxLenticularPitch);
        cal.pitch = v->number;
    }
    if (auto* v = get("lenticular_slope")) {
        if (!(std::abs(v->number) >= composite::kMinLenticularSlope &&
              std::abs(v->number) <= composite::kMaxLenticularSlope))
            throwStatus(usageError(fmt::format(
                "--lenticular-slope: {} is out of range (must be non-zero, {:g} <= |value| <= {:g})",
                v->number, composite::kMinLenticularSlope, composite::kMaxLenticularSlope)));
        cal.slope = v->number;
    }
    if (auto* v = get("lenticular_center")) {
        inRange("--lenticular-center", v->number, -composite::kMaxLenticularCenter,
                composite::kMaxLenticularCenter);
        cal.center = v->number;
    }
    if (auto* v = get("lenticular_dpi")) {
        positive("--lenticular-dpi", v->number, composite::kMaxLenticularDpi);
        cal.dpi = v->number;
    }
    if (auto* v = get("lenticular_screen")) {
        int w = 0, h = 0;
        char x = 0, extra = 0;
        if (std::sscanf(v->text.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 ||
            (x != 'x' && x != 'X') || w < 1 || h < 1 || w > 16384 || h > 16384)
            throwStatus(usageError(fmt::format(
                "--lenticular-screen: '{}' (expected WxH, 1..16384 each, e.g. 1536x2048)",
                v->text)));
        cal.screenWidth = w;
        cal.screenHeight = h;
    }
    if (auto* v = get("lenticular_bgr")) cal.bgr = v->flag;
    if (auto* v = get("lenticular_invert_views")) cal.invertViews = v->flag;
    if (auto* v = get("lenticular_flip_x")) cal.flipX = v->flag;
    if (auto* v = get("lenticular_flip_y")) cal.flipY = v->flag;
}

std::vector<std::string> modelPaths(const py::object& models,
                                    std::vector<session::InlineModel>& meshes) {
    std::vector<std::string> paths;
    if (models.is_none()) return paths;
    auto one = [&](const py::handle& m) -> std::string {
        if (py::isinstance<PyMesh>(m)) {
            meshes.push_back(m.cast<const PyMesh&>().model);
            return {};
        }
        if (PyUnicode_Check(m.ptr())) return py::str(m);
        if (py::hasattr(m, "__fspath__")) {
            py::object p = py::module_::import("os").attr("fspath")(m);
            if (PyUnicode_Check(p.ptr())) return py::str(p);
        }
        throwParameter(fmt::format(
            "models: expected file paths (str or os.PathLike) or mvr.Mesh, got {}", typeName(m)));
    };
    auto add = [&](const py::handle& m) {
        const bool mesh = py::isinstance<PyMesh>(m);
        std::string p = one(m);
        if (mesh) return;
        if (p.empty()) throwStatus(usageError("models: an empty file name"));
        paths.push_back(std::move(p));
    };
    if (PyUnicode_Check(models.ptr()) || py::hasattr(models, "__fspath__") ||
        py::isinstance<PyMesh>(models)) {
        add(models);
    } else if (PyTuple_Check(models.ptr()) || PyList_Check(models.ptr())) {
        for (py::handle m : models) add(m);
    } else {
        throwParameter("models: expected a list of file paths or mvr.Mesh");
    }
    return paths;
}

}  // namespace

RenderKeywords renderKeywords(const py::object& models, const py::dict& kwargs, bool sequence) {
    static const std::vector<Spec> stillSpecs = [] {
        std::vector<Spec> s = {
            {"scene", Kind::Text},           {"grid", Kind::Int},
            {"views", Kind::Int},            {"view_grid", Kind::Text},
            {"rig", Kind::Text},             {"interaxial", Kind::Float},
            {"separation", Kind::FloatOrAuto}, {"view_cone", Kind::Float},
            {"depth_percent", Kind::Float},
            {"convergence", Kind::FloatOrAuto}, {"fov", Kind::Float},
            {"no_file_camera", Kind::Flag},  {"exposure", Kind::FloatOrAuto},
            {"tonemap", Kind::Text},
            {"environment", Kind::File},
            {"size", Kind::Text},            {"display", Kind::Text},
            {"screen_width", Kind::Float},   {"viewing_distance", Kind::Float},
            {"shading", Kind::Text},         {"cull", Kind::Flag},
            {"specular", Kind::Text},
            {"wireframe", Kind::Flag},       {"shadows", Kind::Flag},
            {"shadow_map_size", Kind::Int},  {"aa", Kind::Int},  {"billboards", Kind::Int},
            {"synthesize", Kind::Int},       {"direct", Kind::Flag},
            {"billboard_size", Kind::Float}, {"backend", Kind::Text},
            {"method", Kind::Text},          {"output", Kind::Text},
            {"depth", Kind::Flag},           {"quiet", Kind::Flag},
            {"format", Kind::TextList},      {"report_json", Kind::Text},
            {"sky", Kind::Text},             {"floating_window", Kind::Flag},
            {"letterbox", Kind::Float},      {"label", Kind::TextList},
            {"label_anchor", Kind::TextList}, {"angular_aa", Kind::TextOrNumber},
            {"azimuth", Kind::Float},        {"elevation", Kind::Float},
            {"distance", Kind::FloatOrAuto}, {"target", Kind::Numbers},
            {"camera_position", Kind::Numbers}, {"look_at", Kind::Numbers},
            {"up", Kind::Numbers},           {"camera_matrix", Kind::Numbers},
            {"focal_length_mm", Kind::Float}, {"sensor_width_mm", Kind::Float},
            {"background", Kind::Numbers},   {"write_cameras", Kind::Flag},
            {"strict", Kind::Flag},          {"png_compression", Kind::Text},
            {"write", Kind::TextList},      {"depth_format", Kind::Text},
            {"view_range", Kind::Numbers},
            {"screen_mm", Kind::Numbers},    {"screen_corners", Kind::Numbers},
            {"eyes", Kind::Numbers},         {"head", Kind::Numbers},
            {"ipd_mm", Kind::Float},         {"depth_factor", Kind::Float},
            {"look_around", Kind::Float},    {"screen_tilt", Kind::Float},
        };
        s.insert(s.end(), std::begin(kComposeSpecs), std::end(kComposeSpecs));
        return s;
    }();
    static const std::vector<Spec> sequenceSpecs = [] {
        std::vector<Spec> s = stillSpecs;
        s.insert(s.end(), {{"frames", Kind::Int},
                           {"orbit", Kind::Float},
                           {"camera_path", Kind::Text},
                           {"frame_range", Kind::Text},
                           {"shard", Kind::Text},
                           {"fps", Kind::Float},
                           {"eye_track", Kind::File}});
        return s;
    }();
    const std::map<std::string, Value> kw = readKeywords(
        sequence ? "render_sequence" : "render", sequence ? sequenceSpecs : stillSpecs, kwargs);
    auto get = [&](const char* name) -> const Value* {
        auto it = kw.find(name);
        return it == kw.end() ? nullptr : &it->second;
    };
    RenderKeywords out;
    session::RenderRecipe& r = out.recipe;
    r.models = modelPaths(models, r.meshes);
    for (const auto& [key, value] : kw) r.given.push_back(optionName(key));
    // The options that exclude each other, as CLI11 says it.
    for (const auto& [a, b] : {std::pair{"views", "view_grid"}, std::pair{"interaxial", "separation"},
                               std::pair{"interaxial", "view_cone"}}) {
        if (get(a) && get(b))
            throwStatus(usageError(optionName(a) + " excludes " + optionName(b)));
    }
    if (auto* v = get("scene")) r.scene = v->text;
    if (auto* v = get("grid")) r.grid = int(v->integer);
    if (auto* v = get("views")) r.views = int(v->integer);
    if (auto* v = get("view_grid")) r.viewGrid = v->text;
    if (auto* v = get("view_range")) {  // (A, B) or "A:B", as --view-range A:B
        r.viewRange = v->text;
        if (const auto comma = r.viewRange.find(','); comma != std::string::npos &&
                                                      r.viewRange.find(':') == std::string::npos)
            r.viewRange[comma] = ':';
        if (r.viewRange.empty()) throwStatus(usageError("--view-range '': expected A:B"));
    }
    if (auto* v = get("rig")) r.rig = v->text;
    // --rig screen: points as "X,Y,Z;X,Y,Z" (numbers grouped in threes), the size as "WxH".
    auto points = [](std::string t) {
        if (t.find(';') != std::string::npos) return t;
        for (std::size_t i = 0, n = 0; i < t.size(); ++i)
            if (t[i] == ',' && ++n % 3 == 0) t[i] = ';';
        return t;
    };
    if (auto* v = get("screen_mm")) {
        r.screen.size = v->text;
        if (const auto c = r.screen.size.find(','); c != std::string::npos) r.screen.size[c] = 'x';
    }
    if (auto* v = get("screen_corners")) r.screen.corners = points(v->text);
    if (auto* v = get("eyes")) r.screen.eyes = points(v->text);
    if (auto* v = get("head")) r.screen.head = v->text;
    if (auto* v = get("ipd_mm")) r.screen.ipdMm = v->number;
    if (auto* v = get("depth_factor")) r.screen.depthFactor = v->number;
    if (auto* v = get("look_around")) r.screen.lookAround = v->number;
    if (auto* v = get("screen_tilt")) r.screen.tiltDegrees = v->number;
    if (auto* v = get("eye_track")) r.screen.eyeTrack = v->text;
    if (auto* v = get("interaxial")) r.interaxial = v->number;
    if (auto* v = get("separation")) {
        r.separationAuto = v->isAuto;
        if (!v->isAuto) r.separation = v->number;
    }
    if (auto* v = get("depth_percent")) r.depthPercent = v->number;
    if (auto* v = get("view_cone")) r.viewCone = v->number;
    if (auto* v = get("convergence")) {
        r.convergenceAuto = v->isAuto;
        if (!v->isAuto) r.convergence = v->number;
    }
    if (auto* v = get("fov")) r.fov = v->number;
    if (auto* v = get("no_file_camera")) r.noFileCamera = v->flag;
    if (auto* v = get("strict")) r.strict = v->flag;
    if (auto* v = get("azimuth")) r.camera.azimuth = v->number;
    if (auto* v = get("elevation")) r.camera.elevation = v->number;
    if (auto* v = get("distance"); v && !v->isAuto) r.camera.distance = v->number;
    if (auto* v = get("target")) r.camera.target = v->text;
    if (auto* v = get("camera_position")) r.camera.position = v->text;
    if (auto* v = get("look_at")) r.camera.lookAt = v->text;
    if (auto* v = get("up")) r.camera.up = v->text;
    if (auto* v = get("camera_matrix")) r.camera.matrix = v->text;
    if (auto* v = get("focal_length_mm")) r.camera.focalLengthMm = v->number;
    if (auto* v = get("sensor_width_mm")) r.camera.sensorWidthMm = v->number;
    if (auto* v = get("background")) r.background = v->text;
    if (auto* v = get("exposure")) {
        r.exposureAuto = v->isAuto;
        if (!v->isAuto) r.exposure = v->number;
    }
    if (auto* v = get("tonemap")) r.tonemap = v->text;
    if (auto* v = get("environment")) r.environment = v->text;
    if (auto* v = get("size")) r.size = v->text;
    if (auto* v = get("display")) r.display = v->text;
    if (auto* v = get("screen_width")) r.screenWidthCm = v->number;
    if (auto* v = get("viewing_distance")) r.viewingDistanceCm = v->number;
    if (auto* v = get("shading")) r.shading = v->text;
    if (auto* v = get("specular")) r.specular = v->text;
    if (auto* v = get("cull")) r.cull = v->flag;
    if (auto* v = get("wireframe")) r.wireframe = v->flag;
    if (auto* v = get("shadows")) r.shadows = v->flag;
    if (auto* v = get("shadow_map_size")) r.shadowMapSize = int(v->integer);
    if (auto* v = get("aa")) r.aa = int(v->integer);
    if (auto* v = get("synthesize")) r.synthesize = int(v->integer);
    if (auto* v = get("billboards")) r.billboards = int(v->integer);
    if (auto* v = get("billboard_size")) r.billboardSize = v->number;
    if (auto* v = get("backend")) r.backend = v->text;
    if (auto* v = get("method")) r.method = v->text;
    if (auto* v = get("output")) r.outputs.directory = v->text;
    if (auto* v = get("direct")) r.outputs.direct = v->flag;
    if (auto* v = get("depth")) r.outputs.depth = v->flag;
    if (auto* v = get("write_cameras")) r.outputs.cameras = v->flag;
    if (auto* v = get("png_compression")) r.outputs.pngCompression = v->text;
    if (auto* v = get("depth_format")) r.outputs.depthFormat = v->text;
    if (auto* v = get("write")) {  // write=["views", "depth"] or "views,depth", as --write
        std::string list;
        for (const std::string& w : v->list) list += (list.empty() ? "" : ",") + w;
        if (list.empty()) throwStatus(usageError("--write: an empty list (nothing to write)"));
        r.outputs.write = list;
    }
    if (auto* v = get("quiet")) out.quiet = v->flag;
    if (auto* v = get("format")) {
        const std::vector<std::string> names = composite::formatNames();
        for (const std::string& f : v->list) {
            if (std::find(names.begin(), names.end(), f) == names.end()) {
                std::string set;
                for (const std::string& n : names) set += (set.empty() ? "" : ",") + n;
                throwStatus(usageError(fmt::format("--format: {} not in {{{}}}", f, set)));
            }
        }
        r.outputs.formats = v->list;
    }
    if (auto* v = get("report_json")) r.outputs.reportJson = v->text;
    if (auto* v = get("sky")) r.surfaces.sky = v->text;
    if (auto* v = get("floating_window")) r.surfaces.floatingWindow = v->flag;
    if (auto* v = get("letterbox")) r.surfaces.letterbox = v->number;
    if (auto* v = get("label")) r.surfaces.labels = v->list;
    if (auto* v = get("label_anchor")) r.surfaces.anchors = v->list;
    if (auto* v = get("angular_aa")) r.surfaces.angularAA = v->text;
    if (auto* v = get("frames")) r.sequence.frames = int(v->integer);
    if (auto* v = get("orbit")) r.sequence.orbit = v->number;
    if (auto* v = get("camera_path")) r.sequence.cameraPath = v->text;
    if (auto* v = get("frame_range")) r.sequence.frameRange = v->text;
    if (auto* v = get("shard")) r.sequence.shard = v->text;
    if (auto* v = get("fps")) r.sequence.fps = v->number;
    composeOptions(kw, r.outputs.compose, /*withStereoMetadata=*/false);
    r.outputs.calibrationGiven = get("lenticular_calibration") != nullptr;
    r.outputs.quiltGiven = get("quilt") != nullptr;
    if (r.outputs.calibrationGiven && r.outputs.compose.lenticular.viewCone > 0.0)
        r.calibrationViewCone = r.outputs.compose.lenticular.viewCone;
    return out;
}

ComposeKeywords composeKeywords(const py::dict& kwargs) {
    static const std::vector<Spec> specs = [] {
        std::vector<Spec> s = {{"output", Kind::Text}, {"quiet", Kind::Flag}};
        s.insert(s.end(), std::begin(kComposeSpecs), std::end(kComposeSpecs));
        s.push_back({"baseline", Kind::Float});
        s.push_back({"convergence", Kind::Float});
        return s;
    }();
    const std::map<std::string, Value> kw = readKeywords("compose", specs, kwargs);
    ComposeKeywords out;
    if (auto it = kw.find("output"); it != kw.end()) out.output = it->second.text;
    if (auto it = kw.find("quiet"); it != kw.end()) out.quiet = it->second.flag;
    composeOptions(kw, out.compose, /*withStereoMetadata=*/true);
    return out;
}

}  // namespace mvr::python
