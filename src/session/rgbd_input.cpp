// src/session/rgbd_input.cpp — RGB-D in, a display's views out (mvr/session/rgbd_input.h).
#include "mvr/session/rgbd_input.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "mvr/composite/jpeg.h"
#include "mvr/composite/rgbd.h"
#include "mvr/core/rig.h"
#include "mvr/core/synthesize.h"

namespace mvr::session {
namespace {

namespace fs = std::filesystem;

/// The sidecar's number at `key` of `block` ({"value": x} or x), if any. Errors: Input naming
/// the file and the key when present but not a finite number.
Result<std::optional<double>> sidecarNumber(const nlohmann::json& block, const char* key,
                                            const std::string& file, const char* blockName) {
    if (!block.is_object() || !block.contains(key)) return std::optional<double>();
    const nlohmann::json* v = &block[key];
    if (v->is_object() && v->contains("value")) v = &(*v)["value"];
    if (!v->is_number() || !std::isfinite(v->get<double>()))
        return inputError(fmt::format("{}: \"{}\".\"{}\" is not a number", file, blockName, key));
    return std::optional<double>(v->get<double>());
}

/// Reads FILE.json beside FILE into `in` (nothing when there is none).
Status readSidecar(const fs::path& image, RgbdInput& in, std::optional<int>& depthLoc,
                   bool& inverted) {
    fs::path json = image;
    json.replace_extension(".json");
    std::error_code ec;
    if (!fs::is_regular_file(json, ec)) return {};
    in.sidecar = json.string();
    Result<std::vector<std::uint8_t>> bytes = composite::readFileBytes(json);
    if (!bytes) return bytes.status();
    nlohmann::json doc;
    try {
        doc = nlohmann::json::parse(bytes->begin(), bytes->end());
    } catch (const nlohmann::json::exception& e) {
        return inputError(fmt::format("{}: not JSON ({}); expected an RGB-D sidecar such as "
                                      "mvr render --format rgbd writes",
                                      in.sidecar, e.what()));
    }
    if (!doc.is_object())
        return inputError(fmt::format("{}: not a JSON object (expected an RGB-D sidecar)",
                                      in.sidecar));
    const nlohmann::json settings = doc.value("settings", nlohmann::json::object());
    auto number = [&](const nlohmann::json& block, const char* key, const char* name,
                      std::optional<double>& out) -> Status {
        Result<std::optional<double>> v = sidecarNumber(block, key, in.sidecar, name);
        if (!v) return v.status();
        out = *v;
        return {};
    };
    std::optional<double> loc, inversion;
    if (Status s = number(settings, "depthiness", "settings", in.depthiness); !s) return s;
    if (Status s = number(settings, "focus", "settings", in.focus); !s) return s;
    if (Status s = number(settings, "depth_loc", "settings", loc); !s) return s;
    if (Status s = number(settings, "depth_inversion", "settings", inversion); !s) return s;
    if (loc) {
        if (*loc != 0 && *loc != 1 && *loc != 2 && *loc != 3)
            return inputError(fmt::format("{}: \"settings\".\"depth_loc\" is {} (expected 0 top, "
                                          "1 bottom, 2 right or 3 left)",
                                          in.sidecar, *loc));
        depthLoc = int(*loc);
    }
    inverted = inversion && *inversion != 0.0;
    if (in.depthiness && !(*in.depthiness >= 0.0 && *in.depthiness <= 2.0))
        return inputError(fmt::format("{}: \"settings\".\"depthiness\" is {} (expected 0..2)",
                                      in.sidecar, *in.depthiness));
    if (in.focus && !(std::abs(*in.focus) <= 0.05))
        return inputError(fmt::format("{}: \"settings\".\"focus\" is {} (expected -0.05..0.05)",
                                      in.sidecar, *in.focus));
    const nlohmann::json block = doc.value("mvr", nlohmann::json::object());
    std::optional<double> near, far, convergence, fov;
    if (Status s = number(block, "near", "mvr", near); !s) return s;
    if (Status s = number(block, "far", "mvr", far); !s) return s;
    if (Status s = number(block, "convergence", "mvr", convergence); !s) return s;
    if (Status s = number(block, "fov_y_degrees", "mvr", fov); !s) return s;
    if (!near || !far || !convergence || !fov) return {};  // no camera: a foreign depth map
    if (!(*near > 0.0 && *far > *near))
        return inputError(fmt::format("{}: \"mvr\" near {} and far {} (expected 0 < near < far)",
                                      in.sidecar, *near, *far));
    if (!(*convergence > 0.0))
        return inputError(fmt::format("{}: \"mvr\".\"convergence\" is {} (expected > 0)",
                                      in.sidecar, *convergence));
    if (!(*fov > 0.0 && *fov < 180.0))
        return inputError(fmt::format("{}: \"mvr\".\"fov_y_degrees\" is {} (expected 0 < fov < "
                                      "180)",
                                      in.sidecar, *fov));
    in.measured = true;
    in.near = *near, in.far = *far, in.convergence = *convergence, in.fovYDegrees = *fov;
    return {};
}

Result<Image> readOne(const std::string& file) {
    Result<std::vector<Image>> read = composite::readViewFile(file);
    if (!read) return read.status();
    if (read->size() != 1)
        return inputError(fmt::format("{}: holds {} images (expected one RGB-D picture)", file,
                                      read->size()));
    return std::move(read->front());
}

/// The part of `image` at (x, y) of w×h.
Image crop(const Image& image, int x, int y, int w, int h) {
    Image out(w, h);
    for (int r = 0; r < h; ++r)
        std::copy_n(image.row(y + r) + 4 * x, 4 * std::size_t(w), out.row(r));
    return out;
}

/// Area average of `src` (channels floats a pixel, width sw) over the box [x0, x1) × [y0, y1)
/// in source pixels: every source pixel the box touches, weighted by the overlap.
void boxAverage(const float* src, int sw, int sh, int channels, double x0, double x1, double y0,
                double y1, float* out) {
    std::fill(out, out + channels, 0.0f);
    double total = 0.0;
    for (int y = std::max(0, int(std::floor(y0))); y < std::min(sh, int(std::ceil(y1))); ++y) {
        const double wy = std::min(y1, y + 1.0) - std::max(y0, double(y));
        for (int x = std::max(0, int(std::floor(x0))); x < std::min(sw, int(std::ceil(x1))); ++x) {
            const double wgt = wy * (std::min(x1, x + 1.0) - std::max(x0, double(x)));
            if (wgt <= 0.0) continue;
            total += wgt;
            for (int c = 0; c < channels; ++c)
                out[c] += float(wgt * src[(std::size_t(y) * sw + x) * channels + c]);
        }
    }
    if (total > 0.0)
        for (int c = 0; c < channels; ++c) out[c] = float(out[c] / total);
}

/// `src` (channels floats a pixel) cropped about its centre to `aspect` and resampled to w×h.
std::vector<float> resample(const std::vector<float>& src, int sw, int sh, int channels,
                            double aspect, int w, int h) {
    double cw = sw, ch = sh;
    if (cw / ch > aspect)
        cw = ch * aspect;
    else
        ch = cw / aspect;
    const double ox = (sw - cw) / 2.0, oy = (sh - ch) / 2.0;
    const double sx = cw / w, sy = ch / h;
    std::vector<float> out(std::size_t(w) * h * channels);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            boxAverage(src.data(), sw, sh, channels, ox + x * sx, ox + (x + 1) * sx,
                       oy + y * sy, oy + (y + 1) * sy,
                       out.data() + (std::size_t(y) * w + x) * channels);
    return out;
}

}  // namespace

Result<RgbdInput> readRgbdInput(const std::vector<std::string>& files,
                                std::optional<composite::DepthPosition> position) {
    if (files.size() != 1 && files.size() != 2)
        return usageError(fmt::format("--from-rgbd: {} files given (expected one RGB-D picture, "
                                      "colour and depth side by side, or two: colour then depth)",
                                      files.size()));
    RgbdInput in;
    Image depth;
    bool inverted = false;
    if (files.size() == 1) {
        Result<Image> both = readOne(files[0]);
        if (!both) return both.status();
        std::optional<int> depthLoc;
        if (Status s = readSidecar(files[0], in, depthLoc, inverted); !s) return s;
        using composite::DepthPosition;
        DepthPosition where = DepthPosition::Right;
        if (position)
            where = *position;
        else if (depthLoc)  // Bridge's depth_loc: 0 top, 1 bottom, 2 right, 3 left
            where = *depthLoc == 0   ? DepthPosition::Top
                    : *depthLoc == 1 ? DepthPosition::Bottom
                    : *depthLoc == 2 ? DepthPosition::Right
                                     : DepthPosition::Left;
        const bool across = where == DepthPosition::Right || where == DepthPosition::Left;
        const int w = both->width, h = both->height;
        if ((across ? w : h) % 2 != 0 || (across ? w : h) < 2)
            return inputError(fmt::format(
                "{}: {}x{} cannot hold colour and depth side by side with the depth {} (expected "
                "an even {}; --rgbd-depth-position says where the depth lies)",
                files[0], w, h, composite::depthPositionName(where), across ? "width" : "height"));
        const int cw = across ? w / 2 : w, ch = across ? h : h / 2;
        const bool depthFirst = where == DepthPosition::Left || where == DepthPosition::Top;
        const int dx = across && !depthFirst ? cw : 0, dy = !across && !depthFirst ? ch : 0;
        const int colx = across && depthFirst ? cw : 0, coly = !across && depthFirst ? ch : 0;
        in.colour = crop(*both, colx, coly, cw, ch);
        depth = crop(*both, dx, dy, cw, ch);
    } else {
        Result<Image> colour = readOne(files[0]);
        if (!colour) return colour.status();
        Result<Image> d = readOne(files[1]);
        if (!d) return d.status();
        // A depth map of another size (phones and estimators write them smaller) is taken
        // over the same frame: its aspect must be the colour's.
        const double ca = double(colour->width) / colour->height, da = double(d->width) / d->height;
        if (std::abs(da / ca - 1.0) > 0.01)
            return inputError(fmt::format(
                "{} is {}x{} but the colour {} is {}x{} (expected a depth map of the colour's "
                "frame: the same aspect, any size)",
                files[1], d->width, d->height, files[0], colour->width, colour->height));
        in.colour = std::move(*colour);
        depth = std::move(*d);
    }
    std::vector<float> grey(std::size_t(depth.width) * depth.height);
    for (std::size_t i = 0; i < grey.size(); ++i) {
        const std::uint8_t* p = depth.rgba.data() + 4 * i;
        const float g = float(int(p[0]) + int(p[1]) + int(p[2])) / (3.0f * 255.0f);
        grey[i] = inverted ? 1.0f - g : g;
    }
    const int w = in.colour.width, h = in.colour.height;
    in.grey = depth.width == w && depth.height == h
                  ? std::move(grey)
                  : resample(grey, depth.width, depth.height, 1,
                             double(depth.width) / depth.height, w, h);
    return in;
}

RgbdLook rgbdLook(const RgbdInput& in, std::optional<double> depthiness,
                  std::optional<double> focus) {
    // An mvr sidecar's camera already holds the render's focal plane: its settings are Bridge's
    // alone. A foreign picture's sidecar speaks for it where the caller does not.
    RgbdLook look;
    look.depthiness = depthiness ? *depthiness : !in.measured && in.depthiness ? *in.depthiness : 1.0;
    look.focus = focus ? *focus : !in.measured && in.focus ? *in.focus : 0.0;
    return look;
}

Result<std::vector<Image>> viewsFromRgbd(const RgbdInput& in, const DisplayPreset& display,
                                         double depthiness, double focus, int threads) {
    if (display.viewConeDegrees <= 0.0f || display.views < 2 || display.viewWidth < 1)
        return usageError(fmt::format(
            "--display {}: --from-rgbd needs a light-field display (a view cone; `mvr info "
            "--displays` lists them)",
            display.name));
    const int w = display.viewWidth, h = display.viewHeight;
    const int sw = in.colour.width, sh = in.colour.height;
    // The picture at the view size: as it is, or cropped to the display's aspect and resampled.
    Image resampledColour;
    std::vector<float> resampledGrey;
    const bool asIs = sw == w && sh == h;
    if (!asIs) {
        const std::vector<float> rgba(in.colour.rgba.begin(), in.colour.rgba.end());
        const double aspect = display.aspect > 0.0f ? display.aspect : double(w) / h;
        const std::vector<float> c = resample(rgba, sw, sh, 4, aspect, w, h);
        resampledGrey = resample(in.grey, sw, sh, 1, aspect, w, h);
        resampledColour = Image(w, h);
        for (std::size_t i = 0; i < c.size(); ++i)
            resampledColour.rgba[i] = std::uint8_t(std::clamp(std::lround(c[i]), 0L, 255L));
    }
    const Image& colour = asIs ? in.colour : resampledColour;
    const std::vector<float>& grey = asIs ? in.grey : resampledGrey;
    // The camera: mvr's own (measured) or mvr's default one at a unit focal distance.
    Camera camera;
    camera.fovYDegrees = in.measured ? float(in.fovYDegrees) : 45.0f;
    camera.aspect = display.aspect > 0.0f ? display.aspect : float(w) / float(h);
    const double focal = in.measured ? in.convergence : 1.0;
    camera.position = glm::vec3(0.0f, 0.0f, float(focal));
    camera.near = float(focal) / 100.0f;
    camera.far = float(focal) * 1000.0f;
    RigParams params;
    params.kind = RigKind::OffAxis;
    params.columns = display.views;
    params.rows = 1;
    params.convergence = float(focal);
    params.viewConeDegrees = display.viewConeDegrees;
    params.coneSpread = float(depthiness);
    Result<Rig> rig = makeRig(camera, params);
    if (!rig) return rig.status();
    std::vector<float> shears;
    for (const View& v : rig->views) shears.push_back(v.clipShear ? v.clipShear->x : 0.0f);
    // Per pixel the parallax factor a = 1 − C / w and an order depth (nearer smaller, < 1).
    std::vector<float> factor(grey.size());
    DepthImage order(w, h);
    const double c = in.measured ? in.convergence - focus * (in.far - in.near) : 0.0;
    for (std::size_t i = 0; i < grey.size(); ++i) {
        const double g = std::clamp(double(grey[i]), 0.0, 1.0);
        factor[i] = in.measured ? float(1.0 - c / (in.far - g * (in.far - in.near)))
                                : float(0.5 + focus - g);
        // mvr's depth is 0 where nothing was drawn: background, never joined to a surface.
        order.depth[i] = in.measured && grey[i] <= 0.0f ? 1.0f : float(0.001 + 0.998 * (1.0 - g));
    }
    return warpFromView(colour, order, factor, shears, 2.0f, threads);
}

}  // namespace mvr::session
