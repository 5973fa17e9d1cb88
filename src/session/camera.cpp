// src/session/camera.cpp — a recipe's viewpoint (CameraRecipe: orbit-style, eye and look-at,
// or a matrix) and field of view (focal length) onto the framing's parameters, and the
// background colour. Every error names the option and its value.
#include "mvr/session/camera.h"

#include <cmath>
#include <fstream>
#include <limits>
#include <regex>
#include <sstream>

#include <fmt/core.h>
#include <glm/gtc/matrix_access.hpp>

#include "mvr/core/input_file.h"

namespace mvr::session {
namespace {

/// Every number in `text` (separated by commas, whitespace, brackets), as written.
std::vector<std::string> numbersIn(const std::string& text) {
    std::vector<std::string> out;
    std::string cur;
    for (char c : text) {
        if (c == ',' || c == '[' || c == ']' || std::isspace(static_cast<unsigned char>(c))) {
            if (!cur.empty()) out.push_back(std::move(cur));
            cur.clear();
        } else {
            cur += c;
        }
    }
    if (!cur.empty()) out.push_back(std::move(cur));
    return out;
}

Result<double> number(const std::string& word, const std::string& option, const std::string& value) {
    try {
        std::size_t used = 0;
        const double v = std::stod(word, &used);
        if (used == word.size() && std::isfinite(v)) return v;
    } catch (const std::exception&) {
    }
    return usageError(fmt::format("{} {}: '{}' is not a finite number", option, value, word));
}

/// 16 numbers from the value itself, or from the file it names.
Result<std::vector<double>> matrixNumbers(const std::string& value) {
    std::vector<std::string> words = numbersIn(value);
    std::string where = value;
    if (words.size() != 16) {
        std::error_code ec;
        if (std::filesystem::exists(value, ec)) {  // a file: a regular one (no FIFO, device)
            if (Status s = checkRegularFile(value, "--camera-matrix " + value); !s) return s;
        }
        if (!std::filesystem::is_regular_file(value, ec)) {
            return usageError(fmt::format(
                "--camera-matrix {}: expected 16 numbers (row-major world-from-camera) or a file "
                "holding them",
                value));
        }
        std::ifstream in(value);
        std::stringstream text;
        text << in.rdbuf();
        if (text.str().size() > 65536)
            return inputError(fmt::format("--camera-matrix {}: not a matrix file (over 64 KiB)", value));
        words = numbersIn(text.str());
        if (words.size() != 16) {
            return inputError(fmt::format("--camera-matrix {}: the file holds {} numbers (expected 16)",
                                          value, words.size()));
        }
    }
    std::vector<double> out;
    for (const std::string& w : words) {
        auto n = number(w, "--camera-matrix", where);
        if (!n) return n.status();
        out.push_back(*n);
    }
    return out;
}

}  // namespace

Result<glm::vec3> vec3Of(const std::string& value, const std::string& option) {
    const std::vector<std::string> words = numbersIn(value);
    if (words.size() != 3)
        return usageError(fmt::format("{} {}: expected X,Y,Z (three numbers)", option, value));
    glm::vec3 v(0.0f);
    for (int i = 0; i < 3; ++i) {
        auto n = number(words[std::size_t(i)], option, value);
        if (!n) return n.status();
        if (std::abs(*n) > 1e15)
            return usageError(fmt::format("{} {}: beyond ±1e15", option, value));
        v[i] = float(*n);
    }
    return v;
}


Result<std::optional<Viewpoint>> viewpointOf(const CameraRecipe& c, const Scene& scene,
                                             float fovYDegrees, float aspect) {
    if (!c.given()) return std::optional<Viewpoint>{};
    const bool orbit = c.azimuth || c.elevation || c.distance || !c.target.empty();
    const bool eye = !c.position.empty() || !c.lookAt.empty() || !c.up.empty();
    const bool matrix = !c.matrix.empty();
    if (int(orbit) + int(eye) + int(matrix) > 1) {
        return usageError(
            "the camera is given twice: --azimuth / --elevation / --distance / --target, "
            "--camera-position / --look-at / --up and --camera-matrix exclude each other");
    }
    const Bounds bounds = scene.bounds();
    const glm::vec3 centre = bounds.center();
    Viewpoint vp;
    if (orbit) {
        vp.target = centre;
        if (!c.target.empty() && c.target != "centre" && c.target != "center") {
            auto t = vec3Of(c.target, "--target");
            if (!t) return t.status();
            vp.target = *t;
        }
        const double az = c.azimuth.value_or(0.0), el = c.elevation.value_or(0.0);
        if (!std::isfinite(az) || std::abs(az) > 36000.0)
            return usageError(fmt::format("--azimuth {} is out of range (expected degrees, |a| <= 36000)", az));
        if (!std::isfinite(el) || el < -90.0 || el > 90.0)
            return usageError(fmt::format("--elevation {} is out of range (expected -90..90 degrees)", el));
        double d = fitDistance(scene, fovYDegrees, aspect);
        if (c.distance) {
            d = *c.distance;
            if (!std::isfinite(d) || d <= 0.0 || d > 1e15)
                return usageError(fmt::format("--distance {} is out of range (expected > 0)", d));
        }
        const double a = glm::radians(az), e = glm::radians(el);
        const glm::vec3 dir(float(std::sin(a) * std::cos(e)), float(std::sin(e)),
                            float(std::cos(a) * std::cos(e)));
        vp.position = vp.target + float(d) * dir;
        // Straight above or below: "up" on the screen is away from the azimuth's side.
        if (std::abs(el) > 89.9)
            vp.up = float(el > 0 ? -1.0 : 1.0) * glm::vec3(float(std::sin(a)), 0.0f, float(std::cos(a)));
    } else if (eye) {
        if (c.position.empty()) return usageError("--look-at / --up need --camera-position");
        auto p = vec3Of(c.position, "--camera-position");
        if (!p) return p.status();
        vp.position = *p;
        vp.target = centre;
        if (!c.lookAt.empty()) {
            auto t = vec3Of(c.lookAt, "--look-at");
            if (!t) return t.status();
            vp.target = *t;
        }
        if (!c.up.empty()) {
            auto u = vec3Of(c.up, "--up");
            if (!u) return u.status();
            vp.up = *u;
        }
        if (glm::length(vp.target - vp.position) <= 0.0f) {
            return usageError(fmt::format("--camera-position {}: the camera looks at its own position",
                                          c.position));
        }
    } else {
        auto m = matrixNumbers(c.matrix);
        if (!m) return m.status();
        const std::vector<double>& v = *m;
        auto at = [&](int row, int col) { return float(v[std::size_t(4 * row + col)]); };
        if (std::abs(at(3, 0)) > 1e-6f || std::abs(at(3, 1)) > 1e-6f || std::abs(at(3, 2)) > 1e-6f ||
            std::abs(at(3, 3) - 1.0f) > 1e-6f) {
            return usageError(fmt::format(
                "--camera-matrix {}: the last row must be 0 0 0 1 (a rigid world-from-camera "
                "transform, row-major)", c.matrix));
        }
        vp.position = {at(0, 3), at(1, 3), at(2, 3)};
        const glm::vec3 forward = -glm::vec3(at(0, 2), at(1, 2), at(2, 2));
        vp.up = glm::vec3(at(0, 1), at(1, 1), at(2, 1));
        if (!(glm::length(forward) > 1e-6f) || !(glm::length(vp.up) > 1e-6f)) {
            return usageError(fmt::format("--camera-matrix {}: degenerate axes", c.matrix));
        }
        const glm::vec3 f = glm::normalize(forward);
        const float depth =
            std::max(glm::dot(centre - vp.position, f), std::max(bounds.radius(), 1e-3f));
        vp.target = vp.position + f * depth;
    }
    const glm::vec3 f = vp.target - vp.position;
    if (!(glm::length(glm::cross(glm::normalize(f), glm::normalize(vp.up))) > 1e-4f)) {
        return usageError("--up is parallel to the direction the camera looks (give another --up)");
    }
    return std::optional<Viewpoint>(vp);
}

Result<std::optional<double>> fovFromFocalLength(const CameraRecipe& c, double aspect) {
    if (!c.focalLengthMm) return std::optional<double>{};
    const double f = *c.focalLengthMm, s = c.sensorWidthMm;
    if (!std::isfinite(f) || f <= 0.0 || f > 1e6)
        return usageError(fmt::format("--focal-length-mm {} is out of range (expected > 0)", f));
    if (!std::isfinite(s) || s <= 0.0 || s > 1e6)
        return usageError(fmt::format("--sensor-width-mm {} is out of range (expected > 0)", s));
    const double halfX = std::atan(s / (2.0 * f));
    return std::optional<double>(2.0 * glm::degrees(std::atan(std::tan(halfX) / aspect)));
}

Result<std::optional<glm::vec3>> backgroundOf(const std::string& text) {
    if (text.empty()) return std::optional<glm::vec3>{};
    if (text.size() == 7 && text[0] == '#') {
        glm::vec3 c;
        for (int i = 0; i < 3; ++i) {
            const std::string hex = text.substr(std::size_t(1 + 2 * i), 2);
            if (!std::isxdigit(static_cast<unsigned char>(hex[0])) ||
                !std::isxdigit(static_cast<unsigned char>(hex[1])))
                return usageError(fmt::format("--background {}: expected #RRGGBB (hex digits)", text));
            c[i] = float(std::stoi(hex, nullptr, 16)) / 255.0f;
        }
        return std::optional<glm::vec3>(c);
    }
    const std::vector<std::string> words = numbersIn(text);
    if (words.size() != 3)
        return usageError(fmt::format("--background {}: expected R,G,B in 0..1 or #RRGGBB", text));
    glm::vec3 c(0.0f);
    for (int i = 0; i < 3; ++i) {
        auto n = number(words[std::size_t(i)], "--background", text);
        if (!n) return n.status();
        if (*n < 0.0 || *n > 1.0)
            return usageError(fmt::format("--background {}: each of R,G,B must be in 0..1", text));
        c[i] = float(*n);
    }
    return std::optional<glm::vec3>(c);
}

}  // namespace mvr::session
