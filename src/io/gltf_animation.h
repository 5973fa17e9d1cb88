// gltf_animation.h — a glTF file's node hierarchy and first animation, read from its JSON and
// buffers (internal to mvr::io).
//
// assimp 5.2.5's glTF2 importer turns every sampler into plain keys and drops the
// interpolation (STEP plays as LINEAR, CUBICSPLINE's tangents are lost), so mvr reads the
// animation itself: the JSON (.gltf, or a .glb's JSON chunk), the buffers (a .glb's BIN chunk,
// data: URIs, files beside the model), the accessors of each sampler. scene_io.cpp binds the
// nodes to assimp's (same hierarchy, walked in the same order).
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "mvr/core/animation.h"
#include "mvr/core/status.h"

namespace mvr::detail {

struct GltfAnimationFile {
    /// Nodes of the default scene in depth-first order (parents before children); the
    /// instances / camera of SceneAnimation are left for the caller to bind.
    SceneAnimation animation;
    std::vector<std::vector<int>> children;  ///< per node (indices into animation.nodes)
    std::vector<int> roots;                  ///< the scene's root nodes
    std::vector<std::string> warnings;       ///< channels not played (weights, sparse, ...)
};

/// The file's first animation, or nullopt when it has none (or is not glTF). Errors:
/// ErrorCode::Input, "WHAT: animation 'A': channel C: ..." for malformed animation data.
Result<std::optional<GltfAnimationFile>> readGltfAnimation(const std::filesystem::path& path,
                                                           const std::string& what);

}  // namespace mvr::detail
