// screen.cpp — `--rig screen`'s options (mvr/session/screen.h).
#include "mvr/session/screen.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <tuple>
#include <regex>
#include <vector>

#include <fmt/core.h>

#include "mvr/session/camera.h"

namespace mvr::session {
namespace {

/// "A;B;C" as `count` points, each "X,Y,Z".
Result<std::vector<glm::vec3>> pointsOf(const std::string& value, const std::string& option,
                                        std::size_t count, const char* form) {
    std::vector<std::string> parts;
    std::size_t start = 0;
    for (;;) {
        const std::size_t semi = value.find(';', start);
        parts.push_back(value.substr(start, semi - start));
        if (semi == std::string::npos) break;
        start = semi + 1;
    }
    if (parts.size() != count) {
        return usageError(fmt::format("{} {}: expected {} ({} points X,Y,Z separated by ';')",
                                      option, value, form, count));
    }
    std::vector<glm::vec3> out;
    for (const std::string& p : parts) {
        auto v = vec3Of(p, option);
        if (!v) return usageError(fmt::format("{} {}: '{}' is not X,Y,Z (three numbers)", option, value, p));
        out.push_back(*v);
    }
    return out;
}

}  // namespace

std::optional<std::string> screenStretchNote(const ScreenCorners& screen, int width, int height) {
    const float viewAspect = float(width) / float(height);
    const float screenAspect = screen.width() / screen.height();
    if (std::abs(screenAspect / viewAspect - 1.0f) <= 0.01f) return std::nullopt;
    return fmt::format(
        "warning: the views are {}x{} (aspect {:.4g}) but the screen is {:.4g} x {:.4g} mm (aspect "
        "{:.4g}): each view fills the screen, stretched; --size {}x{} keeps the pixels square",
        width, height, viewAspect, screen.width(), screen.height(), screenAspect, width,
        std::max(1, int(std::lround(width / screenAspect))));
}

ScreenEyes EyeFactors::apply(ScreenEyes eyes) const {
    const glm::vec3 mid = 0.5f * (eyes.leftEye + eyes.rightEye);
    const glm::vec3 half = 0.5f * (eyes.rightEye - eyes.leftEye);
    const glm::vec3 m = home + lookAround * (mid - home);
    eyes.leftEye = m - depth * half;
    eyes.rightEye = m + depth * half;
    return eyes;
}

ScreenEyes EyeTrack::at(double t, const ScreenCorners& screen) const {
    ScreenEyes eyes;
    eyes.screen = screen;
    auto after = std::upper_bound(samples.begin(), samples.end(), t,
                                  [](double time, const Sample& s) { return time < s.t; });
    if (after == samples.begin() || after == samples.end()) {
        const Sample& s = after == samples.begin() ? samples.front() : samples.back();
        eyes.leftEye = s.left;
        eyes.rightEye = s.right;
        return factors.apply(eyes);
    }
    const Sample& a = *(after - 1);
    const Sample& b = *after;
    const float w = float((t - a.t) / (b.t - a.t));
    eyes.leftEye = glm::mix(a.left, b.left, w);
    eyes.rightEye = glm::mix(a.right, b.right, w);
    return factors.apply(eyes);
}

Result<EyeTrack> readEyeTrack(const std::string& file, const ScreenCorners& screen) {
    const std::string what = "--eye-track " + file;
    std::error_code ec;
    if (!std::filesystem::is_regular_file(file, ec))
        return inputError(fmt::format("{}: file not found", what));
    std::ifstream in(file);
    if (!in) return inputError(fmt::format("{}: cannot read the file", what));
    EyeTrack track;
    bool header = false;
    std::string line;
    for (int number = 1; std::getline(in, line); ++number) {
        if (!line.empty() && line.back() == '\r') line.pop_back();
        const std::size_t first = line.find_first_not_of(" \t");
        if (first == std::string::npos || line[first] == '#') continue;
        std::vector<double> v;
        std::stringstream row(line);
        std::string cell;
        bool numeric = true;
        while (std::getline(row, cell, ',')) {
            char* end = nullptr;
            const double x = std::strtod(cell.c_str(), &end);
            numeric = numeric && end != cell.c_str() &&
                      cell.find_first_not_of(" \t", std::size_t(end - cell.c_str())) == std::string::npos;
            v.push_back(x);
        }
        if (!numeric) {
            if (track.samples.empty() && !header) {  // the first row: a header
                header = true;
                continue;
            }
            return inputError(fmt::format("{}: line {}: '{}' is not numbers t,lx,ly,lz,rx,ry,rz", what, number, line));
        }
        if (v.size() != 7)
            return inputError(fmt::format("{}: line {}: expected 7 numbers t,lx,ly,lz,rx,ry,rz, got {}", what, number, v.size()));
        for (double x : v) {
            if (!std::isfinite(x) || std::abs(x) > 1e6)
                return inputError(fmt::format("{}: line {}: {} is not a finite number within 1e6", what, number, x));
        }
        if (!track.samples.empty() && !(v[0] > track.samples.back().t))
            return inputError(fmt::format("{}: line {}: time {} does not follow {} (times must increase)", what, number, v[0], track.samples.back().t));
        EyeTrack::Sample s;
        s.t = v[0];
        s.left = glm::vec3(float(v[1]), float(v[2]), float(v[3]));
        s.right = glm::vec3(float(v[4]), float(v[5]), float(v[6]));
        ScreenEyes eyes{screen, s.left, s.right};
        if (Status st = validateScreenEyes(eyes, fmt::format("{}: line {}", what, number)); !st)
            return inputError(st.message());
        track.samples.push_back(s);
    }
    if (track.samples.empty()) return inputError(fmt::format("{}: no samples (rows t,lx,ly,lz,rx,ry,rz)", what));
    return track;
}

ScreenGeometry screenGeometryOf(const ScreenEyes& eyes) {
    ScreenGeometry g;
    g.widthCm = eyes.screen.width() / 10.0f;
    const glm::vec3 mid = 0.5f * (eyes.leftEye + eyes.rightEye);
    g.viewingDistanceCm = glm::dot(mid - eyes.screen.lowerLeft, eyes.screen.normal()) / 10.0f;
    g.interocularCm = glm::length(eyes.rightEye - eyes.leftEye) / 10.0f;
    return g;
}

bool usesScreenRig(const RenderRecipe& r, const DisplayPreset* display) {
    return r.rig == "screen" || (r.rig == "offaxis" && display && display->tracked());
}

Status checkScreenOptions(const RenderRecipe& r, int views, bool screenRig) {
    if (!screenRig) {
        if (r.screen.given()) {
            return usageError(
                "the screen options (--screen-mm, --screen-corners, --eyes, --ipd-mm, --head, "
                "--eye-track, --depth-factor, --look-around, --screen-tilt) need --rig screen");
        }
        return {};
    }
    if (!r.viewGrid.empty())
        return usageError(fmt::format("--rig screen excludes --view-grid {} (two eyes, two views)", r.viewGrid));
    if (!r.screen.eyeTrack.empty() && !r.sequence.active()) {
        return usageError(fmt::format(
            "--eye-track {} needs a sequence (--frames F: frame f takes the eyes at time f/--fps)",
            r.screen.eyeTrack));
    }
    if (views != 2)
        return usageError(fmt::format("--rig screen renders two views (the eyes), not --views {}", views));
    if (r.viewCone) return usageError(fmt::format("--rig screen excludes --view-cone {}", *r.viewCone));
    if (r.interaxial) return usageError(fmt::format("--rig screen excludes --interaxial {} (--eyes or --ipd-mm give the spacing)", *r.interaxial));
    if (r.separation) return usageError(fmt::format("--rig screen excludes --separation {} (--eyes or --ipd-mm give the spacing)", *r.separation));
    if (r.separationAuto) return usageError("--rig screen excludes --separation auto (--eyes or --ipd-mm give the spacing)");
    return {};
}

Result<ScreenEyes> screenEyesOf(const RenderRecipe& r, float viewAspect,
                                std::shared_ptr<const EyeTrack>* track,
                                const DisplayPreset* display) {
    const ScreenRecipe& s = r.screen;
    ScreenCorners screen;
    float tilt = display && display->tracked() ? display->screenTiltDegrees : 0.0f;
    if (s.tiltDegrees) {
        if (!(std::isfinite(*s.tiltDegrees) && std::abs(*s.tiltDegrees) <= 85.0))
            return usageError(fmt::format("--screen-tilt {} is out of range (expected -85 .. 85 degrees)", *s.tiltDegrees));
        tilt = float(*s.tiltDegrees);
    }
    if (!s.corners.empty()) {
        if (!s.size.empty()) return usageError(fmt::format("--screen-corners excludes --screen-mm {}", s.size));
        if (s.tiltDegrees) return usageError(fmt::format("--screen-corners excludes --screen-tilt {} (the corners give the tilt)", *s.tiltDegrees));
        auto p = pointsOf(s.corners, "--screen-corners", 3, "lower-left;lower-right;upper-left");
        if (!p) return p.status();
        screen = {(*p)[0], (*p)[1], (*p)[2]};
        if (Status st = validateScreen(screen, "--screen-corners " + s.corners); !st) return st;
    } else if (!s.size.empty()) {
        static const std::regex kSize(R"(\s*([0-9.eE+-]+)\s*[xX]\s*([0-9.eE+-]+)\s*)");
        std::smatch m;
        double w = 0.0, h = 0.0;
        bool ok = std::regex_match(s.size, m, kSize);
        if (ok) {
            try {
                std::size_t uw = 0, uh = 0;
                w = std::stod(m[1].str(), &uw);
                h = std::stod(m[2].str(), &uh);
                ok = uw == m[1].str().size() && uh == m[2].str().size();
            } catch (const std::exception&) {
                ok = false;
            }
        }
        if (!ok) return usageError(fmt::format("--screen-mm {}: expected WxH in millimetres (e.g. 597.9x336.3)", s.size));
        if (!(w >= 1.0 && h >= 1.0 && w <= 1e5 && h <= 1e5))
            return usageError(fmt::format("--screen-mm {}: out of range (expected 1 .. 100000 mm a side)", s.size));
        screen = screenOfSize(float(w), float(h), tilt);
    } else if (r.screenWidthCm) {
        const float w = float(*r.screenWidthCm) * 10.0f;
        screen = screenOfSize(w, w / viewAspect, tilt);
    } else if (display && display->tracked()) {
        screen = screenOfSize(display->screenWidthMm, display->screenHeightMm, tilt);
    } else {
        screen = screenOfSize(597.9f, 336.3f, tilt);
    }
    EyeFactors factors;
    factors.home = screen.centre() +
                   screen.normal() * float(r.viewingDistanceCm ? *r.viewingDistanceCm * 10.0 : 600.0);
    for (const auto& [name, value, low] : {std::tuple{"--depth-factor", s.depthFactor, 1e-3},
                                           std::tuple{"--look-around", s.lookAround, 0.0}}) {
        if (value && !(std::isfinite(*value) && *value >= low && *value <= 10.0))
            return usageError(fmt::format("{} {} is out of range (expected {} .. 10)", name, *value, low > 0 ? "> 0" : "0"));
    }
    factors.depth = float(s.depthFactor.value_or(1.0));
    factors.lookAround = float(s.lookAround.value_or(1.0));
    ScreenEyes eyes;
    if (!s.eyeTrack.empty()) {
        if (!s.eyes.empty() || s.ipdMm || !s.head.empty())
            return usageError(fmt::format("--eye-track excludes {}", !s.eyes.empty() ? "--eyes" : s.ipdMm ? "--ipd-mm" : "--head"));
        auto read = readEyeTrack(s.eyeTrack, screen);
        if (!read) return read.status();
        read->factors = factors;
        for (const EyeTrack::Sample& sample : read->samples) {  // in front, the factors applied
            if (Status st = validateScreenEyes(read->at(sample.t, screen), "--eye-track " + s.eyeTrack); !st)
                return st;
        }
        eyes = read->at(0.0, screen);
        if (track) *track = std::make_shared<const EyeTrack>(std::move(read).value());
        return eyes;
    }
    if (!s.eyes.empty()) {
        if (s.ipdMm || !s.head.empty())
            return usageError(fmt::format("--eyes excludes {}", s.ipdMm ? "--ipd-mm" : "--head"));
        auto p = pointsOf(s.eyes, "--eyes", 2, "left;right");
        if (!p) return p.status();
        eyes.screen = screen;
        eyes.leftEye = (*p)[0];
        eyes.rightEye = (*p)[1];
    } else {
        const double ipd = s.ipdMm.value_or(63.0);
        if (!std::isfinite(ipd) || ipd < 0.0 || ipd > 1000.0)
            return usageError(fmt::format("--ipd-mm {} is out of range (expected 0 .. 1000 mm)", ipd));
        glm::vec3 head = factors.home;
        if (!s.head.empty()) {
            auto h = vec3Of(s.head, "--head");
            if (!h) return h.status();
            head = *h;
        }
        if (ipd < 1e-3) return usageError(fmt::format("--ipd-mm {}: the eyes would be at one point (expected > 0)", ipd));
        eyes = eyesAtHead(screen, head, float(ipd));
    }
    eyes = factors.apply(eyes);
    const std::string what = !s.eyes.empty()  ? "--eyes " + s.eyes
                             : !s.head.empty() ? "--head " + s.head
                                               : "--rig screen";
    if (Status st = validateScreenEyes(eyes, what); !st) return st;
    return eyes;
}

}  // namespace mvr::session
