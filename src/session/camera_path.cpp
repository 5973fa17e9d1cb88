// src/session/camera_path.cpp — the keyframe file of --camera-path (mvr/session/camera_path.h).
#include "mvr/session/camera_path.h"

#include <exception>
#include <filesystem>
#include <fstream>
#include <system_error>

#include <fmt/core.h>
#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

#include "mvr/core/input_file.h"

namespace mvr::session {

namespace {

Result<glm::vec3> vec3Of(const nlohmann::json& j, const std::string& where) {
    if (!j.is_array() || j.size() != 3) return usageError(where + ": expected [x, y, z]");
    glm::vec3 v;
    for (int i = 0; i < 3; ++i) {
        if (!j[i].is_number()) return usageError(where + ": expected [x, y, z] numbers");
        v[i] = j[i].get<float>();
    }
    return v;
}

}  // namespace

Result<CameraPath> readCameraPath(const std::string& file) {
    std::error_code ec;
    if (!std::filesystem::exists(file, ec))
        return inputError(fmt::format("--camera-path {}: file not found", file));
    if (Status s = checkRegularFile(file, "--camera-path " + file); !s) return s;
    std::ifstream in(file);
    if (!in) return inputError(fmt::format("--camera-path {}: cannot read the file", file));
    nlohmann::json doc;
    try {
        // libstdc++'s filebuf throws on a read error (a file that vanished, a bad disk), even
        // with parse()'s exceptions off.
        doc = nlohmann::json::parse(in, nullptr, false);
    } catch (const std::exception& e) {
        return inputError(fmt::format("--camera-path {}: cannot read the file ({})", file, e.what()));
    }
    if (doc.is_discarded()) return inputError(fmt::format("--camera-path {}: not JSON", file));
    const nlohmann::json& keys = doc.is_object() && doc.contains("keys") ? doc["keys"] : doc;
    if (!keys.is_array() || keys.empty()) {
        return inputError(
            fmt::format("--camera-path {}: expected a non-empty \"keys\" array", file));
    }
    CameraPath path;
    for (std::size_t i = 0; i < keys.size(); ++i) {
        const nlohmann::json& k = keys[i];
        const std::string where = fmt::format("--camera-path {}: key {}", file, i);
        if (!k.is_object() || !k.contains("time") || !k["time"].is_number() ||
            !k.contains("position") || !k.contains("target")) {
            return inputError(where + ": needs \"time\", \"position\" and \"target\"");
        }
        CameraKey key;
        key.time = k["time"].get<double>();
        auto pos = vec3Of(k["position"], where + " position");
        if (!pos) return inputError(pos.status().message());
        auto tgt = vec3Of(k["target"], where + " target");
        if (!tgt) return inputError(tgt.status().message());
        key.position = *pos;
        key.target = *tgt;
        if (k.contains("fov")) {
            if (!k["fov"].is_number()) return inputError(where + ": \"fov\" is not a number");
            key.fovYDegrees = k["fov"].get<float>();
        }
        path.keys.push_back(key);
    }
    if (Status s = validateCameraPath(path); !s) {
        return inputError(fmt::format("--camera-path {}: {}", file, s.message()));
    }
    return path;
}

}  // namespace mvr::session
