// mvr/io/mtl.h — mvr's own reader of Wavefront material libraries (.mtl), the part an OBJ's
// `mtllib` / `usemtl` need for color: the diffuse color Kd, its texture map_Kd and the
// dissolve d / Tr. assimp never sees MTL files (model_guard.h: its MTL parser crashed on
// malformed input); this reader is small, bounded and fuzzed (tests/fuzz/mtl_reader_fuzz.cpp).
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "mvr/core/status.h"

namespace mvr {

/// One `newmtl` block of an MTL file.
struct MtlMaterial {
    std::string name;
    glm::vec3 diffuse{0.8f};  ///< Kd, as written (clamped to [0, 1])
    float dissolve = 1.0f;    ///< d, or 1 - Tr; clamped to [0, 1]
    std::string diffuseMap;   ///< map_Kd's file name as written (options removed); empty: none
};

/// Parses MTL text. Keywords other than newmtl, Kd, d, Tr and map_Kd are ignored (Ka, Ks, Ns,
/// illum, map_Bump, ...). Errors: ErrorCode::Input "mvr::parseMtl(): WHAT:LINE: ..." for a
/// material statement before any newmtl, a newmtl without a name, a Kd / d / Tr whose values
/// are not finite numbers, a map_Kd without a file name.
Result<std::vector<MtlMaterial>> parseMtl(std::string_view text, const std::string& what);

/// Reads and parses an MTL file (at most 16 MiB). Errors as parseMtl(), plus
/// "mvr::loadMtl(): PATH: file not found" / "not a regular file (a FIFO)" / "cannot be read" /
/// "is larger than 16 MiB".
Result<std::vector<MtlMaterial>> loadMtl(const std::filesystem::path& path);

/// The materials of every `mtllib` an OBJ file names (paths relative to the OBJ's folder), in
/// order. Errors: the OBJ cannot be read, or one of its libraries fails loadMtl().
Result<std::vector<MtlMaterial>> loadObjMaterials(const std::filesystem::path& objPath);

/// The first material named `name`, or nullptr.
const MtlMaterial* findMtl(const std::vector<MtlMaterial>& materials, std::string_view name);

}  // namespace mvr
