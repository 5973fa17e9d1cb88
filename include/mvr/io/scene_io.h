// mvr/io/scene_io.h — model files as whole scenes (issue 14): glTF 2.0 (.gltf with external
// or data-URI buffers and images, .glb) with its node hierarchy, materials, base color
// textures, first camera and KHR_lights_punctual lights; OBJ with its MTL (usemtl: Kd, d,
// map_Kd); PLY and anything else assimp reads as plain meshes. loadMesh() (io/mesh_io.h) stays
// for callers that want one merged mesh. Library mvr::io (JPEG textures through its
// libjpeg-turbo decoder, io/jpeg.h; PNG through its libpng reader, io/png.h).
//
// Mapping (docs/architecture.md, "Scenes from files"):
// - every mesh instance of a node → one Instance per primitive, worldFromModel = the node's
//   world transform; each primitive → one Mesh (shared by the nodes that instance it). A
//   skinned one (glTF skins: assimp's bones, up to 8 influences a vertex) is posed by its joints in
//   the file's root space (poseSkin; the node's own transform does not place it, glTF's rule),
//   its Instance at the root.
// - baseColorFactor → Material::albedo + alpha; baseColorTexture → a Texture and its sampler
//   (filters, wrap); alphaMode / alphaCutoff; doubleSided. A glTF material is
//   MaterialModel::MetallicRoughness (lighting.h, the specification's BRDF) with its
//   metallicFactor / roughnessFactor (glTF's defaults 1, 1) and emissiveFactor ×
//   KHR_materials_emissive_strength, read from the file's JSON; KHR_materials_unlit makes it
//   MaterialModel::Unlit. Its metallicRoughnessTexture and occlusionTexture (with its
//   strength) become linear Textures (Texture::linear), its emissiveTexture an sRGB one
//   (Material's slots, lighting.h SurfaceMaps). A map whose file is missing is not drawn (a
//   warning), and the neutral factor exporters write beside it goes with it (no emissive
//   without its map; Blinn-Phong without the metallic-roughness map: alone, factors 1 and 1
//   are a rough metal). Its normalTexture (with its scale) is a linear Texture drawn on meshes
//   with tangents: the file's TANGENT, else assimp's aiProcess_CalcTangentSpace (run when a
//   material has a normal map; not MikkTSpace, which glTF asks for: the two agree on smooth,
//   well-parameterised meshes and differ across uv seams). A KHR_materials_pbrSpecularGlossiness
//   material keeps Blinn-Phong. OBJ, PLY and primitives without a material: Blinn-Phong,
//   specular 0.25 / shininess 32 as every built-in material.
// - texture coordinate sets 0 and 1 (TEXCOORD_0, TEXCOORD_1; another set is an error naming
//   the material) and KHR_texture_transform on every slot, read from the file's JSON: each
//   slot's transform is recorded on the Material (baseColorTransform, normalTransform, ...);
//   a mesh's texcoords are the set its material's first texture reads (base colour, else
//   metallic-roughness, occlusion, emissive, normal), with that slot's transform baked in
//   (TextureTransform, scene.h: uv' = T · R · S · uv), and the material's sampler is that
//   slot's. Every slot drawn reads those coordinates: a slot reading another set or transform
//   is not drawn (a warning naming the file, material and slot). A set the mesh lacks: a
//   warning naming the file, material, set and mesh, set 0 used (info->strict: an error).
// - texture coordinates follow Texture's convention (uv (0, 0) = top-left): glTF's as written,
//   OBJ's v flipped.
// - the first camera (perspective: yfov, aspectRatio, znear, zfar) → Scene::camera.
// - KHR_lights_punctual: color × intensity → Light::color (directional: lux read as a unitless
//   scale, 1 = the color at full strength; point / spot: candela, attenuated by the shading's
//   1/d²; no exposure: Blender's exporter writes 683 × W-based values, README); direction =
//   the node's −Z; spot cone angles → cosines; range (absent: 0 = infinite). assimp 5.2.5
//   drops range, so color, intensity, range and the cone angles are read from the file's JSON
//   (nlohmann_json), light i of the extension being assimp's mLights[i]. A file without
//   lights gets defaultLights(); lights past kMaxLights are dropped with a warning.
// - an unreadable or corrupt texture is an error naming the model, the material and the
//   image; a missing one a warning (info->strict: an error).
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "mvr/core/animation.h"
#include "mvr/core/environment.h"
#include "mvr/core/scene.h"
#include "mvr/core/stereo_surfaces.h"
#include "mvr/core/status.h"

namespace mvr {

struct SceneLoadInfo {
    /// In: a texture file that is not there is an error (else a warning, the base colour used).
    bool strict = false;
    std::vector<std::string> warnings;  ///< one line each, no newline (dropped lights, ...)
    bool fromMaterials = false;   ///< the file has materials of its own (glTF, OBJ with mtllib)
    bool lightsFromFile = false;  ///< Scene::lights are the file's (else defaultLights())
    /// glTF: the file's first animation bound to the scene's instances and camera (its camera
    /// node's keys move Scene::camera); absent when the file has none. Play it with
    /// animateScene() (animation.h). The scene itself is loaded in the file's rest pose.
    std::optional<SceneAnimation> animation;
};

/// Loads a model file as a scene (see above), importing it once: glTF and OBJ + MTL pass
/// loadMesh()'s checks (its messages, "mvr::loadScene(): PATH" in front) and are read here;
/// anything else is loadMesh()'s merged mesh (its messages as they are). Errors:
/// ErrorCode::Input — those; "PATH: material 'M': texture 'T': ..."
/// for a bad texture (a missing one only when info->strict: else a warning, and the material
/// keeps its base colour); "PATH: material 'M': its base colour texture reads texture
/// coordinate set 1 (TEXCOORD_1), which mesh 'X' does not have" (only when info->strict: else
/// the same line as a warning, set 0 used); "PATH: has no triangles". Texture paths with
/// Windows separators ('.\tex.jpg', as LightWave's MTL writes them) are found with '/'.
Result<Scene> loadScene(const std::filesystem::path& path, SceneLoadInfo* info = nullptr);

/// A sky for StereoSurfaces (stereo_surfaces.h): "gradient", or a PNG / JPEG file decoded by
/// mvr's own readers (libpng, libjpeg; as textures are: at most 256 MiB, a header that claims
/// more pixels than the bytes can hold refused before decoding): 2:1 → Equirect, 4:3 →
/// CubeCross; or a high-dynamic-range map (Radiance .hdr or OpenEXR, read as
/// loadEnvironmentMap reads it, a cube cross made equirectangular) shown as the scene's lit
/// colours are: its radiance × `hdrScale` (2^EV of --exposure) through `tonemap`
/// (lighting.h finishColor), clamped and quantized — so a sky and an --environment of the same
/// map agree. Errors: Input naming the file ("--sky 'F': file not found …", "not a PNG,
/// JPEG, Radiance or OpenEXR image", the decoder's reason), Usage for another aspect ratio.
/// `asRadiance`: read even a PNG / JPEG as loadEnvironmentMap does (sRGB decoded, then shown
/// as lit colours are), as `--sky environment` does, so that the sky and the light agree.
Result<Sky> loadSky(const std::string& spec, float hdrScale = 1.0f,
                    Tonemap tonemap = Tonemap::None, bool asRadiance = false);

/// An environment map for image lighting (issue 39 item 2, `--environment MAP`;
/// mvr/core/environment.h): a Radiance RGBE (.hdr: FORMAT=32-bit_rle_rgbe, rows top down,
/// flat or run-length scanlines; decoded by mvr, see radiance.cpp), an OpenEXR (R, G, B or Y,
/// half or float, through OpenEXR) or a PNG / JPEG (sRGB decoded to linear) file, told apart
/// by their bytes, not their names: equirectangular (2:1) as it is, or a horizontal cube cross
/// (4:3, the sky's layout) resampled to a 4s × 2s equirectangular map. Negative texels read 0,
/// texels above kMaxRadiance read kMaxRadiance. At most 512 MiB and 8192 × 4096 texels in
/// every format. RadianceMap::contentHash: a hash of the file's bytes. Errors: Input naming the file ("--environment 'F':
/// file not found", "not a Radiance (.hdr), OpenEXR, PNG or JPEG image", "scanline 7 of 64: the
/// file ends early", "texel (3, 5) is not finite", the decoder's reason), Usage for another
/// aspect ratio.
/// `option` names the file in messages ("--sky" when the sky reads it).
Result<RadianceMap> loadEnvironmentMap(const std::string& path,
                                       const std::string& option = "--environment");
/// The hash loadEnvironmentMap gives the file's bytes (RadianceMap::contentHash), without
/// decoding them; 0 when the file cannot be read (a cache key: the session's, prepare.cpp).
std::uint64_t environmentFileHash(const std::string& path);

/// A model's placement in the scene: translation, uniform scale and rotation about +Y.
/// FILE@X,Y,Z[,SCALE[,YAW]] is bounded: |X|, |Y|, |Z| <= kMaxPlacementOffset, SCALE in
/// kMinPlacementScale..kMaxPlacementScale, |YAW| <= 360 degrees. With the readers' bound on a
/// vertex (kMaxCoordinate, mesh.h: 1e12) a placed vertex stays within ~1e18, where the framing's
/// squared distances still fit a float.
inline constexpr double kMaxPlacementOffset = 1.0e6;
inline constexpr double kMinPlacementScale = 1.0e-6;
inline constexpr double kMaxPlacementScale = 1.0e6;
inline constexpr double kMaxPlacementYaw = 360.0;
struct Placement {
    glm::vec3 position{0.0f};
    float scale = 1.0f;
    float yawDegrees = 0.0f;
    glm::mat4 matrix() const;  ///< T(position) · R_y(yaw) · S(scale)
};

/// Applies `worldFromScene` to every instance, light and the camera of `scene`.
void transformScene(Scene& scene, const glm::mat4& worldFromScene);

/// Appends `other`'s meshes, textures, instances (indices remapped) and lights to `scene`;
/// the camera is kept from `scene` when it has one, else taken from `other`.
void appendScene(Scene& scene, Scene other);

}  // namespace mvr
