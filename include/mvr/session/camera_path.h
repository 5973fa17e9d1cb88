// mvr/session/camera_path.h — the keyframe file of a sequence's camera path (`mvr render
// --camera-path FILE`, docs/animation.md). Also its own small library, mvr_camera_path (mvr::core
// and nlohmann_json only), so that the fuzz target tests/fuzz/camera_path_fuzz.cpp reads files
// the way `mvr` does.
#pragma once

#include <string>

#include "mvr/core/animation.h"
#include "mvr/core/status.h"

namespace mvr::session {

/// Reads and validates (validateCameraPath()) a keyframe file. Errors (ErrorCode::Input) name
/// the option, the file and the key: "--camera-path p.json: key 1 position: expected [x, y, z]".
Result<CameraPath> readCameraPath(const std::string& file);

}  // namespace mvr::session
