// mvr/io/mesh_io.h — model files (OBJ, PLY, glTF; assimp and mvr's PLY reader) as one mvr::Mesh,
// and the load-time locality pass (meshoptimizer). Part of mvr::io; the mesh type is core's.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "mvr/core/mesh.h"
#include "mvr/core/status.h"

namespace mvr {

/// Reorders triangles and vertices for post-transform cache and fetch locality
/// (meshopt_optimizeVertexCache + meshopt_optimizeVertexFetch). Pixels do not change.
void optimizeMeshLocality(Mesh& mesh);

/// Loads every mesh in a model file (OBJ, PLY, glTF 2.0 .gltf/.glb; whatever assimp reads) and
/// merges them into one mesh with node transforms applied. Triangulates, generates smooth
/// normals when absent, validates, and reorders for locality.
/// Errors: ErrorCode::Input — "mvr::loadMesh(): PATH: file not found" / "not a regular file (a
/// FIFO)" (the model, or a glTF's external buffer: never opened) / "not a readable model
/// (assimp: ...)" / "has no triangles" / ...
/// `warnings`: what was skipped (unknown PLY header lines), when given.
Result<Mesh> loadMesh(const std::filesystem::path& path,
                      std::vector<std::string>* warnings = nullptr);

}  // namespace mvr
