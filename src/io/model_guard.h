// Internal: checks and limits around assimp for mvr::loadMesh(), each for a fault that fuzzing
// found in assimp 5.2.5 (Debian 12) and that mvr keeps from reaching it (tests/fuzz/).
#pragma once

#include <filesystem>
#include <string>

#include <assimp/DefaultIOSystem.h>
#include <nlohmann/json_fwd.hpp>

#include "mvr/core/status.h"
#include "mvr/io/mesh_io.h"

namespace mvr::detail {

/// A binary glTF (a file that starts with the "glTF" magic): its header's total length and
/// every chunk length must fit in the file. assimp allocates a chunk's claimed length before
/// reading it (a 1 KB file claiming a 4 GB JSON chunk is a 4 GB allocation). Other files: OK.
/// Errors: ErrorCode::Input, "WHAT: malformed GLB: ...".
Status checkGlbHeader(const std::filesystem::path& path, const std::string& what);

/// A glTF URI with its `%20`-style escapes decoded (buffers and images of .gltf files).
std::string uriDecode(const std::string& s);

/// A glTF 2.0 file (.gltf text or a .glb's JSON chunk): every buffer view lies inside its
/// buffer, every accessor (and a sparse accessor's indices and values) inside its buffer view,
/// and a buffer's bytes (the GLB's BIN chunk, a data URI, an external file) are at least its
/// byteLength. assimp 5.2.5 copies an accessor without checking it against its buffer view: a
/// byteOffset one byte too far reads past the buffer (tests/fuzz/regressions/glb/). An
/// accessor without a bufferView stands for at most 256 MiB of zeros (assimp allocates them).
/// So that assimp (rapidjson) and this check read one document, the JSON is read up to its
/// first NUL byte, as assimp does, and must be well-formed UTF-8 JSON with no key named twice
/// in one object; its asset.version must be 2.x (assimp's glTF 1.0 reader checks far less).
/// Image MIME types and data URI headers, and primitives (a POSITION each, no indexed
/// LINE_LOOP, strips and fans of at least one face) are checked where assimp crashes on them.
/// Errors: ErrorCode::Input, "WHAT: malformed glTF: accessor 3 ...", "WHAT: malformed glTF:
/// its JSON: parse error at line 1, column 9: ...", "WHAT: malformed glTF: glTF 1.0 is not
/// supported (mvr reads glTF 2.0)".
Status checkGltfBounds(const std::filesystem::path& path, const std::string& what);

/// The numbers of a glTF 2.0 document (checkGltfBounds() calls it): nodes' translation (3),
/// rotation (4), scale (3), matrix (16), mesh / camera / children indices; cameras'
/// yfov (0..pi), znear, zfar, aspectRatio (> 0), xmag, ymag; KHR_lights_punctual colors (3,
/// >= 0), intensity (>= 0), range (> 0), spot cone angles (0..pi/2); materials'
/// baseColorFactor (4), emissiveFactor (3) (colours >= 0), metallic and roughness factors (0..1), alphaCutoff
/// (>= 0), alphaMode, texture infos (every slot's texture coordinate set 0 or 1, the sets mvr
/// reads; KHR_texture_transform's offset (2), rotation, scale (2) and texCoord); samplers'
/// filters and wraps (glTF's enum values). Every number must be a float (finite, |x| <=
/// FLT_MAX). Errors: ErrorCode::Input, "WHAT: nodes[3].translation: expected 3 numbers, got
/// [\"abc\",0,0]", "WHAT: material 'Wood' (materials[0]):
/// pbrMetallicRoughness.baseColorTexture.extensions.KHR_texture_transform.offset: expected 2
/// finite numbers, got [1e+39,0]".
Status checkGltfValues(const nlohmann::json& doc, const std::string& what);

/// What preflightModel() learnt of a model file.
struct ModelPreflight {
    bool ply = false;  ///< PLY content: read by mvr's PLY reader (loadMesh), never assimp
    bool objAllZeroArea = false;  ///< an OBJ whose faces all have zero area (for assimp's failure)
};

/// loadMesh()'s checks before assimp reads a file, shared with loadScene() so that each file is
/// imported once: it exists, is a regular readable non-empty file; PLY content (or a .ply that
/// is not) is recognised (assimp's PLY reader hangs on truncated headers); an OBJ's vertices are
/// finite (the line is named); a GLB header fits the file (checkGlbHeader). Errors:
/// ErrorCode::Input, "WHAT: ...".
Result<ModelPreflight> preflightModel(const std::filesystem::path& path, const std::string& what);

/// The file system assimp sees while it loads `model`: everything except OBJ material
/// libraries (*.mtl). mvr draws no materials, and assimp's MTL parser writes out of bounds on
/// malformed files (tests/fuzz/regressions/mtl/); without its MTL the OBJ loads with assimp's
/// default material. The Importer owns it: importer.SetIOHandler(new ModelIOSystem(...)).
class ModelIOSystem : public Assimp::DefaultIOSystem {
public:
    explicit ModelIOSystem(std::filesystem::path model) : mModel(std::move(model)) {}
    bool Exists(const char* file) const override;
    Assimp::IOStream* Open(const char* file, const char* mode = "rb") override;

private:
    bool hidden(const char* file) const;
    std::filesystem::path mModel;
};

}  // namespace mvr::detail
