// tools/cli/camera_path.h — the keyframe file of `mvr render --camera-path FILE`: the session
// library's reader (mvr/session/camera_path.h, library mvr_camera_path), under the tool's name.
#pragma once

#include "mvr/session/camera_path.h"

namespace mvr::cli {

using session::readCameraPath;

}  // namespace mvr::cli
