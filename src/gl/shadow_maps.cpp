// src/gl/shadow_maps.cpp — shadows (issue 15) in the gl backend: the maps of mvr/core/
// shadows.h (rendered once per frame for all views, through this backend's own methods, as one
// multi-view pass whose views are the lights) uploaded as an R32F texture array and sampled by
// every method's shaders (shaders.cpp: shadowFactor, the GLSL of shadows.h's).
#include <vector>

#include "mvr/core/shadows.h"
#include "renderer.h"

namespace mvr::gl::detail {

void Renderer::setShadows(const ShadowSet* set, const std::vector<Light>& lights) {
    mShadows = set && !set->empty() ? set : nullptr;
    mShadowLights = lights;
    if (!mShadows) return;
    const int size = mShadows->maps.front().size;
    const int layers = int(mShadows->maps.size());
    mGpu->shadowMaps = createTexture(GL_TEXTURE_2D_ARRAY);
    glTextureStorage3D(mGpu->shadowMaps.get(), 1, GL_R32F, size, size, layers);
    for (int k = 0; k < layers; ++k) {
        glTextureSubImage3D(mGpu->shadowMaps.get(), 0, 0, 0, k, size, size, 1, GL_RED, GL_FLOAT,
                            mShadows->maps[std::size_t(k)].depth.data());
    }
    glTextureParameteri(mGpu->shadowMaps.get(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(mGpu->shadowMaps.get(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
}

std::string Renderer::shadowPassMethod(const std::string& method) const {
    const GlMethod* m = findMethod(method);
    if (m && m->exact() && m->target != TargetKind::Mrt) return m->name;
    return glMethods().front().name;  // the reference row
}

void Renderer::setShadowUniforms(GLuint prog) const {
    glm::mat4 clip[kMaxLights];
    glm::vec4 info[kMaxLights], texel[kMaxLights];
    for (int k = 0; k < kMaxLights; ++k) {
        clip[k] = glm::mat4(1.0f);
        info[k] = glm::vec4(-1.0f, 0.0f, 0.0f, 1.0f);
        texel[k] = glm::vec4(0.0f, 1.0f, 0.0f, 0.0f);
        const int m = mShadows->mapOfLight[std::size_t(k)];
        if (m < 0) continue;
        const ShadowMap& sm = mShadows->maps[std::size_t(m)];
        clip[k] = sm.clipFromWorld;
        info[k] = glm::vec4(float(m), sm.perspective ? 1.0f : 0.0f, sm.near, sm.far);
        texel[k] = glm::vec4(sm.texelWorld, float(sm.size), 0.0f, 0.0f);
    }
    glProgramUniformMatrix4fv(prog, 8, kMaxLights, GL_FALSE, &clip[0][0][0]);
    glProgramUniform4fv(prog, 12, kMaxLights, &info[0][0]);
    glProgramUniform4fv(prog, 16, kMaxLights, &texel[0][0]);
    // The lights' positions come from the Frame block (uLightPos); units 2 and 4–7 are the
    // material's textures (materials.cpp kSlotUnits).
    glBindTextureUnit(3, mGpu->shadowMaps.get());
}

}  // namespace mvr::gl::detail
