// mvr/core/mesh.h — triangle meshes, loaded from OBJ, PLY and glTF 2.0 through assimp.
//
// Conventions: right-handed, counter-clockwise front faces, model units as in the file.
// Every mesh that leaves the loader has: at least one triangle, finite positions, a unit
// normal per vertex (smooth normals are generated when the file has none), and indices that
// are all < positions.size(). Vertex order is optimized for locality with meshoptimizer.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/type_precision.hpp>

#include "mvr/core/status.h"

namespace mvr {

struct Bounds {
    glm::vec3 min{std::numeric_limits<float>::max()};
    glm::vec3 max{-std::numeric_limits<float>::max()};
    bool empty() const { return min.x > max.x; }
    void extend(const glm::vec3& p) {
        min = glm::min(min, p);
        max = glm::max(max, p);
    }
    void extend(const Bounds& b) {
        if (!b.empty()) {
            extend(b.min);
            extend(b.max);
        }
    }
    glm::vec3 center() const { return (min + max) * 0.5f; }
    float radius() const { return glm::length(max - min) * 0.5f; }
};

/// One glTF morph target (glTF 2.0 §3.7.2.2): per vertex the displacement of its position
/// and of its normal (empty: the target moves no normal).
struct MorphTarget {
    std::vector<glm::vec3> positions;
    std::vector<glm::vec3> normals;
};

struct Mesh {
    std::string name;
    std::vector<glm::vec3> positions;
    std::vector<glm::vec3> normals;      ///< one per position, unit length
    std::vector<glm::vec2> texcoords;    ///< empty, or one per position
    /// Empty, or one per position: linear RGBA in [0, 1] that multiplies the material's base
    /// colour and alpha (glTF's COLOR_0; OBJ's `v x y z r g b` and PLY's red/green/blue,
    /// sRGB-decoded by the readers), interpolated across each triangle like a texture.
    std::vector<glm::vec4> colors;
    std::vector<std::uint32_t> indices;  ///< 3 per triangle, counter-clockwise = front
    /// Empty, or one per position (appended for normal maps, issue 39): glTF's TANGENT, unit
    /// xyz along the texture's +u, w = ±1 the handedness: the bitangent w · cross(normal,
    /// xyz) runs up the texture image (lighting.h perturbedNormal).
    std::vector<glm::vec4> tangents;
    /// Skinning (glTF skins, issue 39 item 3): empty, or one per position: up to 4 joints
    /// (indices into the skin's joint list, SceneAnimation::Skin) and their weights, summing
    /// to 1 with joints1 / weights1's (all 0: the vertex is not skinned). `basePositions` /
    /// `baseNormals` then hold the unskinned (bind) pose, which poseSkin() deforms (after the
    /// morph targets).
    std::vector<glm::u16vec4> joints;
    std::vector<glm::vec4> weights;
    std::vector<glm::vec4> baseTangents;  ///< a skinned mesh's unskinned `tangents`, or empty
    /// Influences 5 to 8 (glTF's JOINTS_1 / WEIGHTS_1): empty when no vertex has more than 4,
    /// else one per position (0 weights where a vertex has fewer).
    std::vector<glm::u16vec4> joints1;
    std::vector<glm::vec4> weights1;
    /// Morph targets (glTF's `targets`): empty, or each with one displacement per position.
    /// `positions` / `normals` then hold the mesh at `morphWeights` (applyMorphWeights()),
    /// `basePositions` / `baseNormals` the mesh at weights 0.
    std::vector<MorphTarget> morphTargets;
    std::vector<float> morphWeights;  ///< the weights positions / normals hold, one per target
    std::vector<glm::vec3> basePositions, baseNormals;
    /// The normals were computed from the triangles (the file had none): a morph recomputes
    /// them rather than displacing them.
    bool computedNormals = false;

    std::size_t triangleCount() const { return indices.size() / 3; }
    Bounds bounds() const;
};

/// A 64-bit hash of the mesh's contents (positions, normals, texcoords, colors, indices; FNV-style, 8
/// bytes a step, not cryptographic): the GPU backends' key for meshes they keep uploaded.
std::uint64_t contentHash(const Mesh& mesh);

/// The largest vertex coordinate magnitude the readers accept (OBJ, PLY, glTF, Python's
/// meshes): 1e12. A scene must be framed with squared distances that fit a float (~3e38); with
/// a placement's scale and offset (at most 1e6 each, scene_io.h) a vertex stays within ~1e18.
/// validateMesh() refuses a vertex beyond it (ErrorCode::Input, naming the vertex).
inline constexpr double kMaxCoordinate = 1.0e12;

/// Checks the invariants above. Errors: ErrorCode::Input naming `what` and the problem
/// ("has no triangles", "index 9 out of range for 5 vertices", "non-finite position").
Status validateMesh(const Mesh& mesh, const std::string& what);

/// A vertex colour as files other than glTF hold it (sRGB-encoded, straight alpha) as
/// Mesh::colors holds it: each channel clamped to 0..1, RGB decoded with the exact
/// IEC 61966-2-1 curve, alpha unchanged; a NaN channel becomes 0.
glm::vec4 decodeSrgbColor(glm::vec4 encoded);

/// Sets the mesh to the morph `weights` (one per target; missing ones 0, extra ones ignored):
/// positions = base + Σ wᵢ · Δpᵢ, normals = normalize(base + Σ wᵢ · Δnᵢ) (glTF 2.0 §3.7.2.2;
/// computed normals are recomputed instead). No-op for a mesh without morph targets.
void applyMorphWeights(Mesh& mesh, const std::vector<float>& weights);

/// glTF's skinning: `positions` / `normals` from the unskinned pose (basePositions /
/// baseNormals, morphed at `morphWeights` when the mesh has targets) as Σ weight ·
/// jointMatrices[joint] · p per vertex (normals through each matrix's cofactor, i.e. its
/// inverse transpose up to scale, then normalised; tangents from baseTangents through the
/// matrices' linear parts, normalised, their handedness kept). A vertex whose weights are all
/// 0 keeps its unskinned pose. A joint index past `jointMatrices` counts as the identity. No-op for a mesh
/// without Mesh::joints.
void poseSkin(Mesh& mesh, const std::vector<glm::mat4>& jointMatrices);

/// Computes area-weighted smooth vertex normals (degenerate triangles contribute nothing; a
/// vertex with no usable triangle gets +Z).
void computeSmoothNormals(Mesh& mesh);

}  // namespace mvr
