// mvr/core/billboards.h — camera-facing quads for particles and foliage (issue 15, Deliver 6).
//
// nvidia-gtc2010 ("Stereo rendering surfaces", billboards): in stereo a billboard must lie in a
// plane PARALLEL TO THE SCREEN (not turned toward each eye), so that every view sees the same
// flat quad and its parallax is the parallax of its depth. The quads are built once, facing the
// rig's centre camera (spanned by its right and up axes; on an off-axis rig every view shares
// that orientation, so the quad is parallel to every view's screen), and appended to the scene
// as ordinary geometry: every backend then draws them into every view with that view's stereo
// projection — a billboard at distance w has parallax separation · (1 − convergence / w).
// Textured when the scene has textures (texture 0, uv (0,0) at the quad's top left).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "mvr/core/mesh.h"
#include "mvr/core/rig.h"
#include "mvr/core/scene.h"

namespace mvr {

struct Billboard {
    glm::vec3 center{0.0f};
    float size = 0.1f;  ///< side of the square, world units
};

/// Appends one mesh (two triangles per billboard, normals toward the camera) and one instance
/// of it (material: `albedo`; texture 0 when the scene has textures) to `scene`.
/// Does nothing for an empty list.
void appendBillboards(Scene& scene, std::span<const Billboard> billboards, const Camera& camera,
                      glm::vec3 albedo = glm::vec3(1.0f, 0.85f, 0.55f));

/// `count` billboards of side `size` at deterministic pseudo-random points inside `bounds`
/// (seeded: the same list every run).
std::vector<Billboard> scatterBillboards(const Bounds& bounds, int count, float size,
                                         std::uint32_t seed = 1);

}  // namespace mvr
