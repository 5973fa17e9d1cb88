// Internal: mvr's own PLY reader (see ply.cpp for why not assimp's).
#pragma once

#include <string>
#include <vector>

#include "mvr/core/mesh.h"

namespace mvr::detail {

/// True when the file starts with the PLY magic line.
bool looksLikePly(const std::string& head);

/// Parses a whole PLY file held in memory. `what` prefixes error messages.
/// Header lines with a keyword PLY does not define (Blender 2.47 wrote "Created by Blender3D
/// 247 ..." without "comment") are skipped, each with a line in `warnings` when given.
Result<Mesh> loadPly(const std::string& data, const std::string& what,
                     std::vector<std::string>* warnings = nullptr);

}  // namespace mvr::detail
