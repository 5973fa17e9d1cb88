// Internal: mvr's own PLY reader (see ply.cpp for why not assimp's).
#pragma once

#include <string>

#include "mvr/core/mesh.h"

namespace mvr::detail {

/// True when the file starts with the PLY magic line.
bool looksLikePly(const std::string& head);

/// Parses a whole PLY file held in memory. `what` prefixes error messages.
Result<Mesh> loadPly(const std::string& data, const std::string& what);

}  // namespace mvr::detail
