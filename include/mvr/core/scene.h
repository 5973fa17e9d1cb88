// mvr/core/scene.h — scenes: meshes placed by transforms, a material each (optionally with a
// base color texture and glTF's texture transforms), lights, and optionally a camera from the
// file.
//
// World space is right-handed, +Y up. A light's `towardLight` is the world-space unit
// direction TOWARD the light (directional lights); point and spot lights also have a position
// (glTF KHR_lights_punctual). See lighting.h for the shading model every backend uses.
#pragma once

#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "mvr/core/image.h"
#include "mvr/core/mesh.h"

namespace mvr {

struct Environment;  // environment.h

enum class TextureFilter { Nearest, Linear };
enum class TextureWrap { Repeat, ClampToEdge, MirroredRepeat };

/// How a texture is sampled (glTF samplers; OBJ map_Kd gets the defaults).
struct TextureSampler {
    TextureFilter magFilter = TextureFilter::Linear;
    TextureFilter minFilter = TextureFilter::Linear;
    bool mipmaps = true;  ///< minification between mip levels (trilinear when both Linear)
    TextureWrap wrapS = TextureWrap::Repeat;
    TextureWrap wrapT = TextureWrap::Repeat;
};

/// A texture: 8-bit RGBA, straight alpha. Colour (base colour, emissive) is sRGB-encoded and
/// decoded to linear when sampled; data (`linear`: glTF's metallic-roughness and occlusion
/// maps) is sampled as it is (byte / 255). Texture coordinate (0, 0) is the top-left of the
/// image (row 0), as in glTF; loaders of other conventions (OBJ: v up) flip v when they load.
/// An image a file uses both as colour and as data is two Textures.
struct Texture {
    std::string name;  ///< the file, or "FILE: image N" for embedded images (for messages)
    Image image;
    bool linear = false;  ///< data, not colour: no sRGB decoding (appended for issue 39)
};

enum class AlphaMode { Opaque, Mask, Blend };

/// How a material is lit (lighting.h): Blinn-Phong (built-in scenes, OBJ, PLY, glTF primitives
/// without a material, and glTF materials whose metallic / roughness come from a texture or
/// that are specular-glossiness, until those are drawn), glTF 2.0's metallic-roughness BRDF
/// (Appendix B), or unlit (KHR_materials_unlit: the base colour as it is).
enum class MaterialModel { BlinnPhong = 0, MetallicRoughness = 1, Unlit = 2 };  // gl / vk GLSL use the numbers

/// Tone mapping of the lit colour (issue 39 item 2; lighting.h finishColor): none (clamped,
/// the papers' benches' pixels), Khronos PBR Neutral, or ACES (Narkowicz's fit).
enum class Tonemap { None = 0, KhrNeutral = 1, Aces = 2 };  // gl / vk GLSL use the numbers

/// glTF's KHR_texture_transform on one texture slot: an affine map of the slot's texture
/// coordinates (in Texture's convention: u right, v down from the image's top-left),
///
///     uv' = T(offset) · R(rotation) · S(scale) · uv,
///
///           | 1 0 offset.x |       |  cos r  sin r  0 |       | scale.x 0       0 |
///     T  =  | 0 1 offset.y |   R = | -sin r  cos r  0 |   S = | 0       scale.y 0 |
///           | 0 0 1        |       |  0      0      1 |       | 0       0       1 |
///
/// as the extension's README writes R (row by row; "the UVs rotated by r radians
/// counter-clockwise", its example of offset (0, 1), rotation π/2, scale 0.5 picking the
/// lower-left quadrant) and as Blender's glTF exporter, three.js and CesiumJS apply it.
/// Rotation in radians; offset and scale in units of the texture's size.
struct TextureTransform {
    glm::vec2 offset{0.0f, 0.0f};
    float rotation = 0.0f;
    glm::vec2 scale{1.0f, 1.0f};
    /// The extension's own `texCoord`, when given: it overrides the textureInfo's set.
    std::optional<int> texCoord;

    /// `uv` transformed (the formula above).
    glm::vec2 apply(glm::vec2 uv) const {
        const float c = std::cos(rotation), s = std::sin(rotation);
        const glm::vec2 scaled = scale * uv;
        return offset + glm::vec2(c * scaled.x + s * scaled.y, -s * scaled.x + c * scaled.y);
    }
};

struct Material {
    Material() = default;
    Material(glm::vec3 albedo_, float specular_ = 0.25f, float shininess_ = 32.0f)
        : albedo(albedo_), specular(specular_), shininess(shininess_) {}

    glm::vec3 albedo{0.8f, 0.8f, 0.8f};  ///< diffuse color, linear [0, 1] (glTF baseColorFactor)
    float specular = 0.25f;              ///< specular intensity
    float shininess = 32.0f;             ///< Blinn-Phong exponent
    // Appended for textured scenes (issue 14); the defaults keep untextured scenes unchanged.
    float alpha = 1.0f;         ///< baseColorFactor's alpha
    int baseColorTexture = -1;  ///< index into Scene::textures, or -1; multiplies albedo/alpha
    TextureSampler sampler;
    AlphaMode alphaMode = AlphaMode::Opaque;
    float alphaCutoff = 0.5f;  ///< AlphaMode::Mask: fragments with alpha < cutoff are discarded
    bool doubleSided = false;  ///< back faces are drawn (with the normal flipped) when culling
    std::string name;          ///< for messages
    // Appended for glTF's texture coordinate sets and KHR_texture_transform (issue 39 item 4).
    // A record of what the file says, per texture slot: no renderer applies these. loadScene()
    // bakes the base colour slot's set and transform into Mesh::texcoords (the one array every
    // backend samples), so a loaded mesh's texcoords are already transformed. The other slots
    // (not drawn yet) are checked and recorded with their transform; one that uses another
    // transform or set than the base colour's would need its own coordinates.
    int baseColorTexCoord = 0;  ///< the set the base colour texture reads (0 or 1)
    std::optional<TextureTransform> baseColorTransform;
    std::optional<TextureTransform> metallicRoughnessTransform;
    std::optional<TextureTransform> normalTransform;
    std::optional<TextureTransform> occlusionTransform;
    std::optional<TextureTransform> emissiveTransform;
    // Appended for glTF's metallic-roughness materials (issue 39 item 1). `specular` and
    // `shininess` are Blinn-Phong's only; metallic, roughness and emissive MetallicRoughness's
    // only (lighting.h).
    MaterialModel model = MaterialModel::BlinnPhong;
    float metallic = 1.0f;          ///< glTF metallicFactor, [0, 1]
    float roughness = 1.0f;         ///< glTF roughnessFactor (perceptual), [0, 1]
    glm::vec3 emissive{0.0f};       ///< emissiveFactor × KHR_materials_emissive_strength, linear
    // Appended for glTF's other texture slots (issue 39 item 1; lighting.h SurfaceMaps). Each
    // indexes Scene::textures or is -1, reads Mesh::texcoords (the base colour's set and
    // transform: loadScene() drops a slot that reads others, with a warning) through `sampler`.
    int metallicRoughnessTexture = -1;  ///< linear: roughness × G, metallic × B
    int occlusionTexture = -1;          ///< linear: R, the ambient term's occlusion
    float occlusionStrength = 1.0f;     ///< occlusion = 1 + strength · (R − 1)
    int emissiveTexture = -1;           ///< sRGB: emissive × texel
    /// Linear: a tangent-space normal (lighting.h perturbedNormal), per pixel, on meshes with
    /// Mesh::tangents.
    int normalTexture = -1;
    float normalScale = 1.0f;  ///< glTF normalTexture.scale: the normal's x and y × scale
};

/// Whether a material samples any texture (every slot reads Mesh::texcoords).
inline bool hasTexture(const Material& m) {
    return m.baseColorTexture >= 0 || m.metallicRoughnessTexture >= 0 ||
           m.occlusionTexture >= 0 || m.emissiveTexture >= 0 || m.normalTexture >= 0;
}

struct Instance {
    int mesh = 0;  ///< index into Scene::meshes
    glm::mat4 worldFromModel{1.0f};
    Material material;
};

enum class LightType { Directional, Point, Spot };

/// A light. Directional by default (the only kind the built-in scenes use); files may add
/// point and spot lights (KHR_lights_punctual). For a spot, `towardLight` is the negated spot
/// axis (the axis points from the light into the scene).
struct Light {
    glm::vec3 towardLight{0.0f, 0.0f, 1.0f};  ///< unit, world space
    glm::vec3 color{1.0f};                    ///< linear, intensity already applied
    // Appended for lights from files and shadows (issues 14, 15).
    LightType type = LightType::Directional;
    glm::vec3 position{0.0f};          ///< Point / Spot: world space
    float range = 0.0f;                ///< Point / Spot: 0 = infinite (glTF's range)
    float innerConeCos = 1.0f;         ///< Spot: cos(innerConeAngle)
    float outerConeCos = 0.70710678f;  ///< Spot: cos(outerConeAngle), glTF default π/4
    bool castsShadow = false;          ///< --shadows (issue 15)
};
using DirectionalLight = Light;  ///< the name every backend used before point and spot lights

inline constexpr int kMaxLights = 4;

/// Where a scene is meant to be seen from, when it says so (the default scene does).
struct SceneViewpoint {
    glm::vec3 position{0.0f, 0.0f, 5.0f};
    glm::vec3 target{0.0f};
};

/// A camera from the file (glTF's first camera of the scene, perspective): becomes the rig's
/// centre camera unless the command line overrides it.
struct SceneCamera {
    glm::mat4 worldFromCamera{1.0f};  ///< the camera looks down its −Z, +Y up
    float yfovRadians = 0.8f;
    float aspect = 0.0f;  ///< 0 = not given (the output size's aspect is used)
    float znear = 0.1f;
    float zfar = 0.0f;  ///< 0 = infinite / not given (framing chooses)
    std::string name;
};

struct Scene {
    std::vector<Mesh> meshes;
    std::vector<Instance> instances;
    std::vector<DirectionalLight> lights;  ///< at most kMaxLights
    glm::vec3 ambient{0.12f};
    glm::vec3 background{0.08f};              ///< clear colour, linear [0, 1]
    Tonemap tonemap = Tonemap::None;          ///< applied to every lit colour (lighting.h)
    std::optional<SceneViewpoint> viewpoint;  ///< absent: framing fits the bounds (framing.h)
    std::vector<Texture> textures;            ///< Material's texture slots index these
    std::optional<SceneCamera> camera;        ///< from the file, if it has one
    /// Image lighting (issue 39 item 2, `--environment MAP`; environment.h, lighting.h), or none.
    std::shared_ptr<const Environment> environment;

    std::size_t triangleCount() const;  ///< over all instances
    Bounds bounds() const;              ///< world-space bounds of all instances
};

/// The three lights every built-in scene uses (key, fill, rim).
std::vector<DirectionalLight> defaultLights();

/// A procedural scene that needs no data files: a ground plane, spheres, a torus and boxes
/// spread in depth around the origin (some in front of, some behind a convergence plane
/// through the origin), lit by defaultLights().
Scene makeDefaultScene();

/// A procedural textured scene that needs no data files (for tests and benches of textured
/// shading): a checker-textured ground, a textured sphere and boxes (generated textures with
/// texture coordinates that exercise wrap and minification), lit by defaultLights().
Scene makeTexturedScene();

/// A generated RGBA8 checker texture: `size`×`size`, `checks`×`checks` squares alternating
/// between two colors, with a thin colored border on each square (so orientation is visible).
Texture makeCheckerTexture(int size, int checks, Rgba8 a, Rgba8 b, const std::string& name);

/// Lays out `copies` copies of the given meshes (all of them form one "model", placed side by
/// side) in a near-square grid on the XY plane, as sorbier2008 did with 1, 3, 5 and 9 bunnies.
/// Each copy gets its own color. Precondition: copies >= 1 and meshes not empty.
Scene makeGridScene(std::vector<Mesh> meshes, int copies);

/// Checks a scene before rendering (non-empty, mesh indices valid, <= kMaxLights lights).
Status validateScene(const Scene& scene);

}  // namespace mvr
