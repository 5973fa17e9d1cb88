// src/gl/materials.cpp — the gl backend's materials: scene textures on the GPU (sRGB colour or
// linear data, mip chains), sampler objects, the per-instance state a material asks for (its
// textures and sampler, double-sided culling, alpha blending) and the draw order that blending
// needs.
#include <algorithm>
#include <array>
#include <cstring>

#include <fmt/format.h>

#include "mvr/core/content_hash.h"
#include "renderer.h"

namespace mvr::gl::detail {

namespace {

GLint wrapMode(TextureWrap w) {
    switch (w) {
        case TextureWrap::ClampToEdge: return GL_CLAMP_TO_EDGE;
        case TextureWrap::MirroredRepeat: return GL_MIRRORED_REPEAT;
        case TextureWrap::Repeat: break;
    }
    return GL_REPEAT;
}

/// The texture units of a material's slots, in materialSlots' order (shaders.cpp's
/// uBaseColor, uMetallicRoughnessMap, uOcclusionMap, uEmissiveMap, uNormalMap bindings). Units 0
/// and 1 are the methods' and read-back's own (sorbier2008's depth map, composites), 3 the
/// shadow maps.
constexpr GLuint kSlotUnits[5] = {2, 4, 5, 6, 7};

/// A material's texture slots (Scene::textures indices or -1) in kSlotUnits' order.
std::array<int, 5> materialSlots(const Material& m) {
    return {m.baseColorTexture, m.metallicRoughnessTexture, m.occlusionTexture, m.emissiveTexture,
            m.normalTexture};
}

/// Mixed into a linear texture's cache key: the same image may be uploaded twice, as colour
/// (sRGB) and as data (linear), which are different GL textures.
constexpr std::uint64_t kLinearKeySalt = 0x6C696E6561720001ull;

int mipLevels(int w, int h) {
    int levels = 1;
    for (int s = std::max(w, h); s > 1; s >>= 1) ++levels;
    return levels;
}

}  // namespace

std::vector<int> drawOrder(const Scene& scene) {
    std::vector<int> order, blended;
    for (std::size_t i = 0; i < scene.instances.size(); ++i) {
        const bool blend = scene.instances[i].material.alphaMode == AlphaMode::Blend;
        (blend ? blended : order).push_back(static_cast<int>(i));
    }
    order.insert(order.end(), blended.begin(), blended.end());
    return order;
}

Status Renderer::prepareTextures(const Scene& scene, Frame& frame, std::uint64_t& sceneKey) {
    frame.textures.assign(scene.textures.size(), 0);
    for (std::size_t i = 0; i < scene.textures.size(); ++i) {
        const mvr::Texture& src = scene.textures[i];
        const std::uint64_t key = contentHash(src.image) ^ (src.linear ? kLinearKeySalt : 0);
        sceneKey = (sceneKey ^ key) * 0x100000001B3ull;
        auto it = mGpu->textures.find(key);
        if (it == mGpu->textures.end()) {
            evictLeastRecentlyUsed(mGpu->textures, kTexturesKept, mUseCounter);
            const int w = src.image.width, h = src.image.height;
            if (w <= 0 || h <= 0 || w > mCaps.maxTextureSize || h > mCaps.maxTextureSize) {
                return unsupportedError(
                    fmt::format("gl: texture '{}' is {}x{} (GL_MAX_TEXTURE_SIZE = {})", src.name, w,
                                h, mCaps.maxTextureSize));
            }
            GpuTexture g;
            g.texture = createTexture(GL_TEXTURE_2D);
            // sRGB-encoded colour: the sampler decodes to linear before filtering; data
            // (metallic-roughness, occlusion, normal) is sampled as stored. The mip chain is the
            // driver's box filter (glGenerateMipmap) either way.
            glTextureStorage2D(g.texture.get(), mipLevels(w, h),
                               src.linear ? GL_RGBA8 : GL_SRGB8_ALPHA8, w, h);
            glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
            glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
            // Row 0 of the image = texture coordinate t = 0 (glTF's v = 0 is the top row).
            glTextureSubImage2D(g.texture.get(), 0, 0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE,
                                src.image.rgba.data());
            glGenerateTextureMipmap(g.texture.get());
            if (Status s = checkGlError("uploading a texture"); !s) return s;
            it = mGpu->textures.emplace(key, std::move(g)).first;
        }
        it->second.lastUse = mUseCounter;
        frame.textures[i] = it->second.texture.get();
    }
    return Status::ok();
}

Status Renderer::prepareEnvironment(const Scene& scene) {
    const std::shared_ptr<const Environment>& env = scene.environment;
    if (!env) return Status::ok();
    if (!mGpu->splitSum) {
        // environment.h splitSum(): texture() of the table, bilinear, clamped; row 0 (t = 0) is
        // roughness 0, column 0 (s = 0) n·v 0.
        const auto& table = splitSumTable();
        Texture t = createTexture(GL_TEXTURE_2D);
        glTextureStorage2D(t.get(), 1, GL_RG32F, kBrdfSize, kBrdfSize);
        glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
        glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
        glTextureSubImage2D(t.get(), 0, 0, 0, kBrdfSize, kBrdfSize, GL_RG, GL_FLOAT, table.data());
        glTextureParameteri(t.get(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        glTextureParameteri(t.get(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        glTextureParameteri(t.get(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glTextureParameteri(t.get(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
        glTextureParameteri(t.get(), GL_TEXTURE_MAX_LEVEL, 0);
        if (Status s = checkGlError("uploading the split sum's table"); !s) return s;
        mGpu->splitSum = std::move(t);
    }
    // The same Environment object as the one uploaded (alive since, so not another one at its
    // address) with the same coefficients: nothing to do (a render sequence's every frame).
    if (mGpu->environment && mGpu->environmentSource.lock() == env &&
        mGpu->environmentSh == env->sh)
        return Status::ok();
    constexpr int kLevels = Environment::kLevels;
    const int w = env->levels[0].width, h = env->levels[0].height;
    if (w <= 0 || h <= 0 || w > mCaps.maxTextureSize || h > mCaps.maxTextureSize) {
        return unsupportedError(
            fmt::format("gl: environment '{}' is {}x{} (GL_MAX_TEXTURE_SIZE = {})", env->name, w,
                        h, mCaps.maxTextureSize));
    }
    for (int k = 0; k < kLevels; ++k) {
        const Environment::Level& l = env->levels[std::size_t(k)];
        // GL's mip chain: level k is max(1, size >> k), as buildEnvironment makes it.
        if (l.width != std::max(1, w >> k) || l.height != std::max(1, h >> k) ||
            l.texels.size() != std::size_t(l.width) * std::size_t(l.height)) {
            return internalError(fmt::format(
                "gl: environment '{}': level {} is {}x{} ({} texels), not a mip level of {}x{}",
                env->name, k, l.width, l.height, l.texels.size(), w, h));
        }
    }
    // environment.h prefiltered(): textureLod(map, equirectUv(R), roughness · (kLevels − 1))
    // with LINEAR_MIPMAP_LINEAR, REPEAT in s, CLAMP_TO_EDGE in t; row 0 (t = 0) straight up.
    Texture t = createTexture(GL_TEXTURE_2D);
    glTextureStorage2D(t.get(), kLevels, GL_RGBA32F, w, h);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
    for (int k = 0; k < kLevels; ++k) {
        const Environment::Level& l = env->levels[std::size_t(k)];
        glTextureSubImage2D(t.get(), k, 0, 0, l.width, l.height, GL_RGBA, GL_FLOAT,
                            l.texels.data());
    }
    glTextureParameteri(t.get(), GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTextureParameteri(t.get(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTextureParameteri(t.get(), GL_TEXTURE_WRAP_S, GL_REPEAT);
    glTextureParameteri(t.get(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glTextureParameteri(t.get(), GL_TEXTURE_BASE_LEVEL, 0);
    glTextureParameteri(t.get(), GL_TEXTURE_MAX_LEVEL, kLevels - 1);
    if (Status s = checkGlError("uploading the environment map"); !s) return s;
    mGpu->environment = std::move(t);  // the previous one (if any) deleted: the context is current
    mGpu->environmentSource = env;
    mGpu->environmentSh = env->sh;
    return Status::ok();
}

void Renderer::bindEnvironment() const {
    // Texture parameters only: no sampler object on these units (0 unbinds any).
    glBindSampler(kEnvironmentUnit, 0);
    glBindSampler(kSplitSumUnit, 0);
    glBindTextureUnit(kEnvironmentUnit, mGpu->environment.get());
    glBindTextureUnit(kSplitSumUnit, mGpu->splitSum.get());
}

GLuint Renderer::sampler(const TextureSampler& s) {
    const int key = int(s.magFilter) | int(s.minFilter) << 1 | int(s.mipmaps) << 2 |
                    int(s.wrapS) << 3 | int(s.wrapT) << 5;
    auto it = mGpu->samplers.find(key);
    if (it != mGpu->samplers.end()) return it->second.get();
    Sampler smp = createSampler();
    const GLuint n = smp.get();
    const bool linMin = s.minFilter == TextureFilter::Linear;
    const GLint minFilter = !s.mipmaps
                                ? (linMin ? GL_LINEAR : GL_NEAREST)
                                : (linMin ? GL_LINEAR_MIPMAP_LINEAR : GL_NEAREST_MIPMAP_LINEAR);
    glSamplerParameteri(n, GL_TEXTURE_MIN_FILTER, minFilter);
    glSamplerParameteri(n, GL_TEXTURE_MAG_FILTER,
                        s.magFilter == TextureFilter::Linear ? GL_LINEAR : GL_NEAREST);
    glSamplerParameteri(n, GL_TEXTURE_WRAP_S, wrapMode(s.wrapS));
    glSamplerParameteri(n, GL_TEXTURE_WRAP_T, wrapMode(s.wrapT));
    mGpu->samplers.emplace(key, std::move(smp));
    return n;
}

void Renderer::setInstanceState(const Frame& f, const Instance& inst) {
    const Material& m = inst.material;
    // Every slot through the material's one sampler (scene.h); an absent slot keeps whatever
    // is bound, which the shader does not sample (uMatFlags.x's bits).
    const std::array<int, 5> slots = materialSlots(m);
    for (std::size_t k = 0; k < slots.size(); ++k) {
        if (slots[k] < 0 || static_cast<std::size_t>(slots[k]) >= f.textures.size()) continue;
        glBindTextureUnit(kSlotUnits[k], f.textures[static_cast<std::size_t>(slots[k])]);
        glBindSampler(kSlotUnits[k], sampler(m.sampler));
    }
    if (f.settings->cullBackFaces && !m.doubleSided) {
        glEnable(GL_CULL_FACE);
    } else {
        glDisable(GL_CULL_FACE);
    }
    // sorbier2008's MRT methods blend every fragment already (their eye flag is the alpha).
    if (f.method->target == TargetKind::Mrt) return;
    if (m.alphaMode == AlphaMode::Blend) {
        glEnable(GL_BLEND);
        glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
        glDepthMask(GL_FALSE);
    } else {
        glDisable(GL_BLEND);
        glDepthMask(GL_TRUE);
    }
}

void Renderer::endInstanceState(const Frame& f) {
    if (f.settings->cullBackFaces) {
        glEnable(GL_CULL_FACE);
    } else {
        glDisable(GL_CULL_FACE);
    }
    for (GLuint unit : kSlotUnits) {
        glBindSampler(unit, 0);
        glBindTextureUnit(unit, 0);
    }
    if (f.method->target == TargetKind::Mrt) return;
    glDisable(GL_BLEND);
    glDepthMask(GL_TRUE);
}

}  // namespace mvr::gl::detail
