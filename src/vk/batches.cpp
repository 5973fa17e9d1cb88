// The vk backend's frame: scene upload, batch targets, pipelines, the recorded batches and
// their read-back (renderer.h).
#include <algorithm>
#include <chrono>
#include <cstring>

#include <fmt/format.h>
#include <glm/gtc/matrix_inverse.hpp>

#include "mvr/core/environment.h"
#include "mvr/core/rig.h"
#include "mvr/core/scene.h"
#include "renderer.h"

namespace mvr::vk::detail {

namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

struct FrameData {
    glm::vec4 lightDir[kMaxLights], lightColor[kMaxLights], lightPos[kMaxLights],
        lightCone[kMaxLights];
    glm::vec4 ambient, centerEye;
    glm::ivec4 counts;
    glm::mat4 clipFromWorld[kMaxViews];
    glm::mat4 shadowClip[kMaxLights];
    glm::vec4 shadowInfo[kMaxLights], shadowTexel[kMaxLights];
    glm::vec4 viewEye[kMaxViews];  ///< --specular per-view: each view's eye (counts.z = 1)
    glm::vec4 envSh[9];  ///< image lighting: Environment::sh (counts.w = 1), rgb
};
struct InstanceData {
    glm::mat4 worldFromModel, normalFromModel, cofactor;
    glm::vec4 material;
    glm::vec4 params;    ///< shininess, alpha, mask cutoff, occlusion strength
    glm::ivec4 flags;    ///< texture slots (kSlot* bits), alpha mode, double-sided, vertex colours
    glm::vec4 pbr;       ///< metallic, roughness, MaterialModel, normal map scale (common.glsl)
    glm::vec4 emissive;  ///< rgb, w: −1 where worldFromModel mirrors (tangent handedness), else 1
};
// common.glsl's std430 InstanceData: three mat4, five vec4-sized members, no padding.
static_assert(sizeof(InstanceData) == 3 * 64 + 5 * 16);
struct Push {
    std::int32_t instance = 0, viewBase = 0;
};
/// InstanceData::flags.x: the texture slots a material samples (common.glsl's SLOT_*), one bit
/// each; any of them (scene.h hasTexture) splits the lighting into D and S.
constexpr int kSlotBaseColor = 1, kSlotMetallicRoughness = 2, kSlotOcclusion = 4, kSlotEmissive = 8,
              kSlotNormal = 16;

constexpr VkFormat kColorFormat = VK_FORMAT_R8G8B8A8_UNORM;
constexpr VkFormat kDepthFormat = VK_FORMAT_D32_SFLOAT;
constexpr std::size_t kMeshesKept = 32;
/// A vertex of GpuMesh::vertices (position, normal, linear RGBA colour, texture coordinates)
/// and of GpuMesh::flat (position, face edge cross product, face centroid, colour, texture
/// coordinates).
constexpr std::uint32_t kVertexBytes = 48, kFlatVertexBytes = 60;
/// GpuMesh::tangents (binding 1, pixel shading): Mesh::tangents' xyzw.
constexpr std::uint32_t kTangentBytes = 16;

/// Opaque and masked instances in scene order, then the blended ones (lighting.h).
std::vector<int> drawOrder(const Scene& scene) {
    std::vector<int> order;
    for (int pass = 0; pass < 2; ++pass) {
        for (std::size_t i = 0; i < scene.instances.size(); ++i) {
            const bool blend = scene.instances[i].material.alphaMode == AlphaMode::Blend;
            if (blend == (pass == 1)) order.push_back(int(i));
        }
    }
    return order;
}

Result<Framebuffer> makeFramebuffer(VkDevice device, VkRenderPass pass, VkImageView color,
                                    VkImageView depth, int w, int h, int layers) {
    VkImageView views[2] = {color, depth};
    VkFramebufferCreateInfo ci{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
    ci.renderPass = pass;
    ci.attachmentCount = 2;
    ci.pAttachments = views;
    ci.width = std::uint32_t(w);
    ci.height = std::uint32_t(h);
    ci.layers = std::uint32_t(layers);
    VkFramebuffer fb = VK_NULL_HANDLE;
    if (Status s = check(vkCreateFramebuffer(device, &ci, nullptr, &fb), "vkCreateFramebuffer"); !s)
        return s;
    return Framebuffer(device, fb);
}

// The caller's memory for view `view` (RenderSettings::output), or nullptr (heap).
OutputBlock* blockFor(const RenderSettings& s, std::size_t views) {
    OutputBlock* b = s.output;
    return b && std::size_t(b->views()) == views && b->width() == s.width &&
                   b->height() == s.height
               ? b
               : nullptr;
}

}  // namespace

Result<VkRenderPass> Renderer::multiviewPass(int views) {
    auto it = mMultiviewPasses.find(views);
    if (it != mMultiviewPasses.end()) return it->second.get();
    auto pass = makeRenderPassFor(mContext->device(), (1u << views) - 1u);
    if (!pass) return pass.status();
    return mMultiviewPasses.emplace(views, std::move(*pass)).first->second.get();
}

Status Renderer::ensureSlots(int w, int h, int layers) {
    VkDevice d = mContext->device();
    for (Slot& slot : mSlots) {
        if (slot.w == w && slot.h == h && slot.layers >= layers) continue;
        slot.arrays.clear();
        slot.layerFb.clear();
        slot.colorLayer.clear();
        slot.depthLayer.clear();
        slot.color = {};
        slot.depth = {};
        slot.staging = {};
        slot.w = slot.h = slot.layers = 0;
        VkImageCreateInfo ci{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
        ci.imageType = VK_IMAGE_TYPE_2D;
        ci.extent = {std::uint32_t(w), std::uint32_t(h), 1};
        ci.mipLevels = 1;
        ci.arrayLayers = std::uint32_t(layers);
        ci.samples = VK_SAMPLE_COUNT_1_BIT;
        ci.tiling = VK_IMAGE_TILING_OPTIMAL;
        ci.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
        ci.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
        ci.format = kColorFormat;
        ci.usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
        auto color = mContext->makeImage(ci);
        if (!color) return color.status();
        ci.format = kDepthFormat;
        ci.usage = VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
        auto depth = mContext->makeImage(ci);
        if (!depth) return depth.status();
        slot.color = std::move(*color);
        slot.depth = std::move(*depth);
        for (int l = 0; l < layers; ++l) {
            auto cv = makeView(d, slot.color.image.get(), kColorFormat, VK_IMAGE_ASPECT_COLOR_BIT,
                               l, 1, false);
            if (!cv) return cv.status();
            auto dv = makeView(d, slot.depth.image.get(), kDepthFormat, VK_IMAGE_ASPECT_DEPTH_BIT,
                               l, 1, false);
            if (!dv) return dv.status();
            auto fb = makeFramebuffer(d, mSinglePass.get(), cv->get(), dv->get(), w, h, 1);
            if (!fb) return fb.status();
            slot.colorLayer.push_back(std::move(*cv));
            slot.depthLayer.push_back(std::move(*dv));
            slot.layerFb.push_back(std::move(*fb));
        }
        // Colour then depth of every layer: 8 bytes a pixel.
        auto staging = mContext->makeBuffer(VkDeviceSize(w) * h * 8 * layers,
                                            VK_BUFFER_USAGE_TRANSFER_DST_BIT, true);
        if (!staging) return staging.status();
        slot.staging = std::move(*staging);
        slot.w = w, slot.h = h, slot.layers = layers;
    }
    return {};
}

Result<ArrayTarget*> Renderer::arrayTarget(Slot& slot, int layers, Method m) {
    ArrayTarget& t = slot.arrays[layers];
    VkDevice d = mContext->device();
    if (!t.color) {
        auto cv = makeView(d, slot.color.image.get(), kColorFormat, VK_IMAGE_ASPECT_COLOR_BIT, 0,
                           layers, true);
        if (!cv) return cv.status();
        auto dv = makeView(d, slot.depth.image.get(), kDepthFormat, VK_IMAGE_ASPECT_DEPTH_BIT, 0,
                           layers, true);
        if (!dv) return dv.status();
        t.color = std::move(*cv);
        t.depth = std::move(*dv);
    }
    if (m == Method::Multiview && !t.multiview) {
        auto pass = multiviewPass(layers);
        if (!pass) return pass.status();
        auto fb = makeFramebuffer(d, *pass, t.color.get(), t.depth.get(), slot.w, slot.h, 1);
        if (!fb) return fb.status();
        t.multiview = std::move(*fb);
    }
    if (m == Method::InstancedLayer && !t.layered) {
        auto fb = makeFramebuffer(d, mSinglePass.get(), t.color.get(), t.depth.get(), slot.w,
                                  slot.h, layers);
        if (!fb) return fb.status();
        t.layered = std::move(*fb);
    }
    return &t;
}

Result<VkPipeline> Renderer::pipeline(Method m, Shading shading, int views, bool cull, bool blend,
                                      bool wire) {
    const std::uint32_t key = std::uint32_t(m) | std::uint32_t(shading) << 2 |
                              std::uint32_t(cull) << 4 | std::uint32_t(blend) << 5 |
                              std::uint32_t(wire) << 6 |
                              std::uint32_t(m == Method::Multiview ? views : 0) << 8;
    if (auto it = mPipelines.find(key); it != mPipelines.end()) return it->second.get();
    VkDevice d = mContext->device();
    const ViewSource source = m == Method::Multipass   ? ViewSource::Pass
                              : m == Method::Multiview ? ViewSource::Multiview
                                                       : ViewSource::Layer;
    auto module = [&](int id, std::span<const std::uint32_t> code) -> Result<VkShaderModule> {
        if (auto it = mModules.find(id); it != mModules.end()) return it->second.get();
        VkShaderModuleCreateInfo ci{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
        ci.codeSize = code.size_bytes();
        ci.pCode = code.data();
        VkShaderModule sm = VK_NULL_HANDLE;
        if (Status s = check(vkCreateShaderModule(d, &ci, nullptr, &sm), "vkCreateShaderModule");
            !s)
            return s;
        return mModules.emplace(id, ShaderModule(d, sm)).first->second.get();
    };
    auto vs = module(int(shading) * 4 + int(source), sceneVertexSpirv(shading, source));
    if (!vs) return vs.status();
    auto fs = module(100 + int(shading), sceneFragmentSpirv(shading));
    if (!fs) return fs.status();
    VkPipelineShaderStageCreateInfo stages[2]{};
    stages[0] = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO, nullptr, 0,
                 VK_SHADER_STAGE_VERTEX_BIT, *vs, "main", nullptr};
    stages[1] = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO, nullptr, 0,
                 VK_SHADER_STAGE_FRAGMENT_BIT, *fs, "main", nullptr};
    // Smooth: position, normal, colour, uv; flat: the unrolled triangles' position, edge cross
    // product, centroid, colour, uv (GpuMesh); pixel shading adds the tangent (binding 1: the
    // mesh's, or the shared (0, 0, 0, 1) of mNoTangents).
    const bool flat = shading == Shading::Flat;
    const bool pixel = shading == Shading::Pixel;
    const VkVertexInputBindingDescription bindings[2] = {
        {0, flat ? kFlatVertexBytes : kVertexBytes, VK_VERTEX_INPUT_RATE_VERTEX},
        {1, kTangentBytes, VK_VERTEX_INPUT_RATE_VERTEX}};
    const VkVertexInputAttributeDescription attrs[5] = {
        {0, 0, VK_FORMAT_R32G32B32_SFLOAT, 0},
        {1, 0, VK_FORMAT_R32G32B32_SFLOAT, 12},
        {3, 0, VK_FORMAT_R32G32B32A32_SFLOAT, flat ? 36u : 24u},
        {4, 0, VK_FORMAT_R32G32_SFLOAT, flat ? 52u : 40u},
        flat ? VkVertexInputAttributeDescription{2, 0, VK_FORMAT_R32G32B32_SFLOAT, 24}
             : VkVertexInputAttributeDescription{5, 1, VK_FORMAT_R32G32B32A32_SFLOAT, 0}};
    VkPipelineVertexInputStateCreateInfo vi{VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
    vi.vertexBindingDescriptionCount = pixel ? 2 : 1;
    vi.pVertexBindingDescriptions = bindings;
    vi.vertexAttributeDescriptionCount = flat || pixel ? 5 : 4;
    vi.pVertexAttributeDescriptions = attrs;
    VkPipelineInputAssemblyStateCreateInfo ia{
        VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
    ia.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
    VkPipelineViewportStateCreateInfo vp{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
    vp.viewportCount = 1;
    vp.scissorCount = 1;
    VkPipelineRasterizationStateCreateInfo rs{
        VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
    rs.polygonMode = wire ? VK_POLYGON_MODE_LINE : VK_POLYGON_MODE_FILL;
    rs.cullMode = cull ? VK_CULL_MODE_BACK_BIT : VK_CULL_MODE_NONE;
    // Counter-clockwise as seen in the image (Vulkan's facing is computed in framebuffer
    // coordinates, whose y points down, as the flipped clip y does): GL's front faces.
    rs.frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE;
    rs.lineWidth = 1.0f;
    VkPipelineMultisampleStateCreateInfo ms{VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
    ms.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
    VkPipelineDepthStencilStateCreateInfo ds{
        VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
    ds.depthTestEnable = VK_TRUE;
    ds.depthWriteEnable = blend ? VK_FALSE : VK_TRUE;
    ds.depthCompareOp = VK_COMPARE_OP_LESS;
    VkPipelineColorBlendAttachmentState cb{};
    cb.colorWriteMask = VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT |
                        VK_COLOR_COMPONENT_B_BIT | VK_COLOR_COMPONENT_A_BIT;
    if (blend) {  // gl: glBlendFuncSeparate(SRC_ALPHA, ONE_MINUS_SRC_ALPHA, ONE, ONE_MINUS_SRC_ALPHA)
        cb.blendEnable = VK_TRUE;
        cb.srcColorBlendFactor = VK_BLEND_FACTOR_SRC_ALPHA;
        cb.dstColorBlendFactor = VK_BLEND_FACTOR_ONE_MINUS_SRC_ALPHA;
        cb.colorBlendOp = VK_BLEND_OP_ADD;
        cb.srcAlphaBlendFactor = VK_BLEND_FACTOR_ONE;
        cb.dstAlphaBlendFactor = VK_BLEND_FACTOR_ONE_MINUS_SRC_ALPHA;
        cb.alphaBlendOp = VK_BLEND_OP_ADD;
    }
    VkPipelineColorBlendStateCreateInfo cbs{VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
    cbs.attachmentCount = 1;
    cbs.pAttachments = &cb;
    VkDynamicState dyn[2] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
    VkPipelineDynamicStateCreateInfo dy{VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO};
    dy.dynamicStateCount = 2;
    dy.pDynamicStates = dyn;
    VkRenderPass pass = mSinglePass.get();
    if (m == Method::Multiview) {
        auto p = multiviewPass(views);
        if (!p) return p.status();
        pass = *p;
    }
    VkGraphicsPipelineCreateInfo ci{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO};
    ci.stageCount = 2;
    ci.pStages = stages;
    ci.pVertexInputState = &vi;
    ci.pInputAssemblyState = &ia;
    ci.pViewportState = &vp;
    ci.pRasterizationState = &rs;
    ci.pMultisampleState = &ms;
    ci.pDepthStencilState = &ds;
    ci.pColorBlendState = &cbs;
    ci.pDynamicState = &dy;
    ci.layout = mPipelineLayout.get();
    ci.renderPass = pass;
    VkPipeline p = VK_NULL_HANDLE;
    if (Status s = check(vkCreateGraphicsPipelines(d, VK_NULL_HANDLE, 1, &ci, nullptr, &p),
                         "vkCreateGraphicsPipelines");
        !s)
        return s;
    return mPipelines.emplace(key, Pipeline(d, p)).first->second.get();
}

Status Renderer::prepareScene(const Scene& scene, std::vector<GpuMesh*>& meshes) {
    ++mUseCounter;
    meshes.clear();
    std::size_t noTangents = 1;  // vertices mNoTangents must cover
    for (const Mesh& mesh : scene.meshes) {
        const std::uint64_t key = contentHash(mesh);
        auto it = mMeshes.find(key);
        if (it == mMeshes.end()) {
            while (mMeshes.size() >= kMeshesKept) {  // least recently used, not this frame's
                auto lru = mMeshes.end();
                for (auto i = mMeshes.begin(); i != mMeshes.end(); ++i)
                    if (i->second.lastUse < mUseCounter &&
                        (lru == mMeshes.end() || i->second.lastUse < lru->second.lastUse))
                        lru = i;
                if (lru == mMeshes.end()) break;
                mMeshes.erase(lru);
            }
            GpuMesh g;
            const std::size_t nv = mesh.positions.size(), nt = mesh.triangleCount();
            // A mesh without colours is white (the shaders use the colour only where the
            // instance says the mesh has them).
            const bool colored = mesh.colors.size() == nv;
            const glm::vec4 white(1.0f);
            auto colorOf = [&](std::size_t i) -> const glm::vec4& {
                return colored ? mesh.colors[i] : white;
            };
            const bool hasUv = mesh.texcoords.size() == nv;
            const glm::vec2 noUv(0.0f);
            auto uvOf = [&](std::size_t i) -> const glm::vec2& {
                return hasUv ? mesh.texcoords[i] : noUv;
            };
            auto v = mContext->makeBuffer(nv * kVertexBytes, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT,
                                          true);
            if (!v) return v.status();
            auto* pv = static_cast<float*>(v->mapped);
            for (std::size_t i = 0; i < nv; ++i) {
                float* o = pv + i * (kVertexBytes / 4);
                std::memcpy(o, &mesh.positions[i], 12);
                std::memcpy(o + 3, &mesh.normals[i], 12);
                std::memcpy(o + 6, &colorOf(i), 16);
                std::memcpy(o + 10, &uvOf(i), 8);
            }
            auto ix = mContext->makeBuffer(mesh.indices.size() * 4, VK_BUFFER_USAGE_INDEX_BUFFER_BIT,
                                           true);
            if (!ix) return ix.status();
            std::memcpy(ix->mapped, mesh.indices.data(), mesh.indices.size() * 4);
            // Flat: every triangle's corners carry its model-space edge cross product (the
            // cofactor matrix maps it to the world-space one) and its centroid.
            auto fl = mContext->makeBuffer(nt * 3 * kFlatVertexBytes,
                                           VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, true);
            if (!fl) return fl.status();
            auto* pf = static_cast<float*>(fl->mapped);
            for (std::size_t t = 0; t < nt; ++t) {
                const glm::vec3 p0 = mesh.positions[mesh.indices[3 * t]];
                const glm::vec3 p1 = mesh.positions[mesh.indices[3 * t + 1]];
                const glm::vec3 p2 = mesh.positions[mesh.indices[3 * t + 2]];
                const glm::vec3 n = glm::cross(p1 - p0, p2 - p0);
                const glm::vec3 c = (p0 + p1 + p2) / 3.0f;
                for (int k = 0; k < 3; ++k) {
                    float* o = pf + (t * 3 + k) * (kFlatVertexBytes / 4);
                    const glm::vec3 p = k == 0 ? p0 : k == 1 ? p1 : p2;
                    std::memcpy(o, &p, 12);
                    std::memcpy(o + 3, &n, 12);
                    std::memcpy(o + 6, &c, 12);
                    std::memcpy(o + 9, &colorOf(mesh.indices[3 * t + k]), 16);
                    std::memcpy(o + 13, &uvOf(mesh.indices[3 * t + k]), 8);
                }
            }
            // Tangents (pixel shading's binding 1) where the mesh has them; the others bind
            // mNoTangents.
            if (mesh.tangents.size() == nv && nv > 0) {
                auto tb = mContext->makeBuffer(nv * kTangentBytes,
                                               VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, true);
                if (!tb) return tb.status();
                std::memcpy(tb->mapped, mesh.tangents.data(), nv * kTangentBytes);
                g.tangents = std::move(*tb);
            }
            g.vertices = std::move(*v);
            g.indices = std::move(*ix);
            g.flat = std::move(*fl);
            g.indexCount = std::uint32_t(mesh.indices.size());
            g.flatVertexCount = std::uint32_t(nt * 3);
            it = mMeshes.emplace(key, std::move(g)).first;
        }
        it->second.lastUse = mUseCounter;
        meshes.push_back(&it->second);
        if (!it->second.tangents.buffer) noTangents = std::max(noTangents, mesh.positions.size());
    }
    // (0, 0, 0, 1) for the largest mesh without tangents: perturbedNormal's degenerate frame,
    // the mesh's own normal (nothing is in flight between renders: it may be replaced).
    if (mNoTangents.bytes < noTangents * kTangentBytes) {
        auto b = mContext->makeBuffer(noTangents * kTangentBytes, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT,
                                      true);
        if (!b) return b.status();
        auto* p = static_cast<glm::vec4*>(b->mapped);
        std::fill(p, p + noTangents, glm::vec4(0.0f, 0.0f, 0.0f, 1.0f));
        mNoTangents = std::move(*b);
    }
    return {};
}

Status Renderer::uploadFrame(const Scene& scene, const Rig& rig, const RenderSettings& s) {
    const std::size_t instanceBytes = std::max<std::size_t>(scene.instances.size(), 1) *
                                      sizeof(InstanceData);
    bool rebind = false;
    if (!mFrameBuffer.buffer) {
        auto b = mContext->makeBuffer(sizeof(FrameData), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, true);
        if (!b) return b.status();
        mFrameBuffer = std::move(*b);
        rebind = true;
    }
    if (mInstanceBuffer.bytes < instanceBytes) {
        auto b = mContext->makeBuffer(instanceBytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, true);
        if (!b) return b.status();
        mInstanceBuffer = std::move(*b);
        rebind = true;
    }
    if (rebind) {
        VkDescriptorBufferInfo infos[2] = {{mFrameBuffer.buffer.get(), 0, VK_WHOLE_SIZE},
                                           {mInstanceBuffer.buffer.get(), 0, VK_WHOLE_SIZE}};
        VkWriteDescriptorSet w[2]{};
        for (int i = 0; i < 2; ++i) {
            w[i].sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET;
            w[i].dstSet = mSet;
            w[i].dstBinding = std::uint32_t(i);
            w[i].descriptorCount = 1;
            w[i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
            w[i].pBufferInfo = &infos[i];
        }
        vkUpdateDescriptorSets(mContext->device(), 2, w, 0, nullptr);
    }
    auto* f = static_cast<FrameData*>(mFrameBuffer.mapped);
    for (std::size_t i = 0; i < scene.lights.size() && i < std::size_t(kMaxLights); ++i) {
        const Light& l = scene.lights[i];
        f->lightDir[i] = glm::vec4(l.towardLight, 0.0f);
        f->lightColor[i] = glm::vec4(l.color, 0.0f);
        const float type = l.type == LightType::Directional ? 0.0f
                           : l.type == LightType::Point     ? 1.0f
                                                            : 2.0f;
        f->lightPos[i] = glm::vec4(l.position, type);
        f->lightCone[i] = glm::vec4(l.range, l.innerConeCos, l.outerConeCos, 0.0f);
    }
    f->ambient = glm::vec4(scene.ambient, float(int(scene.tonemap)));  // w: finishColor
    f->centerEye = glm::vec4(rig.centerEye(), 1.0f);
    f->counts = glm::ivec4(int(scene.lights.size()), int(rig.views.size()),
                           shadesFromEachEye(s) ? 1 : 0, scene.environment ? 1 : 0);
    for (std::size_t k = 0; k < 9; ++k)
        f->envSh[k] = scene.environment ? glm::vec4(scene.environment->sh[k], 0.0f) : glm::vec4(0.0f);
    for (std::size_t v = 0; v < rig.views.size(); ++v) {
        f->clipFromWorld[v] = rig.views[v].clipFromWorld();
        f->viewEye[v] = glm::vec4(rig.views[v].eyeWorld, 1.0f);
    }
    // As gl's setShadowUniforms(): per light its map, or layer −1 (lit).
    for (int k = 0; k < kMaxLights; ++k) {
        f->shadowClip[k] = glm::mat4(1.0f);
        f->shadowInfo[k] = glm::vec4(-1.0f, 0.0f, 0.0f, 1.0f);
        f->shadowTexel[k] = glm::vec4(0.0f, 1.0f, 0.0f, 0.0f);
        const int m = mShadows ? mShadows->mapOfLight[std::size_t(k)] : -1;
        if (m < 0) continue;
        const ShadowMap& sm = mShadows->maps[std::size_t(m)];
        f->shadowClip[k] = sm.clipFromWorld;
        f->shadowInfo[k] = glm::vec4(float(m), sm.perspective ? 1.0f : 0.0f, sm.near, sm.far);
        f->shadowTexel[k] = glm::vec4(sm.texelWorld, float(sm.size), 0.0f, 0.0f);
    }
    auto* inst = static_cast<InstanceData*>(mInstanceBuffer.mapped);
    for (std::size_t i = 0; i < scene.instances.size(); ++i) {
        const Instance& in = scene.instances[i];
        const glm::mat3 m3(in.worldFromModel);
        InstanceData& o = inst[i];
        o.worldFromModel = in.worldFromModel;
        o.normalFromModel = glm::mat4(glm::inverseTranspose(m3));
        o.cofactor = glm::mat4(glm::determinant(m3) * glm::inverseTranspose(m3));
        const Material& mt = in.material;
        o.material = glm::vec4(mt.albedo, mt.specular);
        o.params = glm::vec4(mt.shininess, mt.alpha, mt.alphaCutoff, mt.occlusionStrength);
        const int mode = mt.alphaMode == AlphaMode::Opaque ? 0 : mt.alphaMode == AlphaMode::Mask ? 1 : 2;
        const Mesh& mesh = scene.meshes[std::size_t(in.mesh)];
        const bool colored = !mesh.colors.empty() && mesh.colors.size() == mesh.positions.size();
        // A slot counts when it names a texture (prepareTextures binds the white texel else).
        auto slot = [&](int texture, int bit) {
            return texture >= 0 && std::size_t(texture) < scene.textures.size() ? bit : 0;
        };
        const int slots = slot(mt.baseColorTexture, kSlotBaseColor) |
                          slot(mt.metallicRoughnessTexture, kSlotMetallicRoughness) |
                          slot(mt.occlusionTexture, kSlotOcclusion) |
                          slot(mt.emissiveTexture, kSlotEmissive) |
                          slot(mt.normalTexture, kSlotNormal);
        o.flags = glm::ivec4(slots, mode, mt.doubleSided ? 1 : 0, colored ? 1 : 0);
        o.pbr = glm::vec4(mt.metallic, mt.roughness, float(int(mt.model)), mt.normalScale);
        // pipeline.h worldTangent's mirror test, for the vertex shader's tangent.
        o.emissive = glm::vec4(mt.emissive, glm::determinant(m3) < 0.0f ? -1.0f : 1.0f);
    }
    return {};
}

Status Renderer::recordBatch(Slot& slot, Method m, const RenderSettings& s, int firstView,
                             int views, const Scene& scene, const std::vector<GpuMesh*>& meshes) {
    VkCommandBuffer cmd = slot.cmd;
    if (Status st = check(vkResetCommandBuffer(cmd, 0), "vkResetCommandBuffer"); !st) return st;
    VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    if (Status st = check(vkBeginCommandBuffer(cmd, &bi), "vkBeginCommandBuffer"); !st) return st;
    ArrayTarget* array = nullptr;
    if (m != Method::Multipass) {
        auto t = arrayTarget(slot, views, m);
        if (!t) return t.status();
        array = *t;
    }
    const std::vector<int> order = drawOrder(scene);
    VkClearValue clears[2];
    clears[0].color = {{s.clearColor.x, s.clearColor.y, s.clearColor.z, 1.0f}};
    clears[1].depthStencil = {1.0f, 0};
    const VkViewport viewport{0.0f, 0.0f, float(s.width), float(s.height), 0.0f, 1.0f};
    const VkRect2D scissor{{0, 0}, {std::uint32_t(s.width), std::uint32_t(s.height)}};
    const bool flat = s.shading == Shading::Flat;
    const bool pixel = s.shading == Shading::Pixel;

    auto drawScene = [&](int viewBase, std::uint32_t instances) -> Status {
        vkCmdSetViewport(cmd, 0, 1, &viewport);
        vkCmdSetScissor(cmd, 0, 1, &scissor);
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, mPipelineLayout.get(), 0, 1,
                                &mSet, 0, nullptr);
        VkPipeline bound = VK_NULL_HANDLE;
        for (int i : order) {
            const Instance& in = scene.instances[std::size_t(i)];
            const bool blend = in.material.alphaMode == AlphaMode::Blend;
            const bool cull = s.cullBackFaces && !in.material.doubleSided;
            auto p = pipeline(m, s.shading, views, cull, blend, s.wireframe);
            if (!p) return p.status();
            if (*p != bound) vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, bound = *p);
            vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, mPipelineLayout.get(), 1,
                                    1, &mInstanceSets[std::size_t(i)], 0, nullptr);
            const Push push{i, viewBase};
            vkCmdPushConstants(cmd, mPipelineLayout.get(),
                               VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0,
                               sizeof(push), &push);
            const GpuMesh& g = *meshes[std::size_t(in.mesh)];
            const VkDeviceSize offset = 0;
            if (flat) {
                VkBuffer b = g.flat.buffer.get();
                vkCmdBindVertexBuffers(cmd, 0, 1, &b, &offset);
                vkCmdDraw(cmd, g.flatVertexCount, instances, 0, 0);
            } else {
                VkBuffer b = g.vertices.buffer.get();
                vkCmdBindVertexBuffers(cmd, 0, 1, &b, &offset);
                if (pixel) {
                    VkBuffer t = g.tangents.buffer ? g.tangents.buffer.get()
                                                   : mNoTangents.buffer.get();
                    vkCmdBindVertexBuffers(cmd, 1, 1, &t, &offset);
                }
                vkCmdBindIndexBuffer(cmd, g.indices.buffer.get(), 0, VK_INDEX_TYPE_UINT32);
                vkCmdDrawIndexed(cmd, g.indexCount, instances, 0, 0, 0);
            }
        }
        return {};
    };
    auto pass = [&](VkRenderPass rp, VkFramebuffer fb, int viewBase,
                    std::uint32_t instances) -> Status {
        VkRenderPassBeginInfo rb{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
        rb.renderPass = rp;
        rb.framebuffer = fb;
        rb.renderArea = scissor;
        rb.clearValueCount = 2;
        rb.pClearValues = clears;
        vkCmdBeginRenderPass(cmd, &rb, VK_SUBPASS_CONTENTS_INLINE);
        const Status st = drawScene(viewBase, instances);
        vkCmdEndRenderPass(cmd);
        return st;
    };
    if (m == Method::Multipass) {
        for (int v = 0; v < views; ++v) {
            if (Status st = pass(mSinglePass.get(), slot.layerFb[std::size_t(v)].get(),
                                 firstView + v, 1);
                !st)
                return st;
        }
    } else if (m == Method::Multiview) {
        auto rp = multiviewPass(views);
        if (!rp) return rp.status();
        if (Status st = pass(*rp, array->multiview.get(), firstView, 1); !st) return st;
    } else {
        if (Status st = pass(mSinglePass.get(), array->layered.get(), firstView,
                             std::uint32_t(views));
            !st)
            return st;
    }
    // One copy of the batch's colour (and depth) into the staging buffer, layer after layer.
    const VkDeviceSize colorBytes = VkDeviceSize(s.width) * s.height * 4 * views;
    VkBufferImageCopy region{};
    region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, std::uint32_t(views)};
    region.imageExtent = {std::uint32_t(s.width), std::uint32_t(s.height), 1};
    vkCmdCopyImageToBuffer(cmd, slot.color.image.get(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                           slot.staging.buffer.get(), 1, &region);
    if (s.depth) {
        region.bufferOffset = colorBytes;
        region.imageSubresource.aspectMask = VK_IMAGE_ASPECT_DEPTH_BIT;
        vkCmdCopyImageToBuffer(cmd, slot.depth.image.get(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                               slot.staging.buffer.get(), 1, &region);
    }
    VkBufferMemoryBarrier toHost{VK_STRUCTURE_TYPE_BUFFER_MEMORY_BARRIER};
    toHost.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    toHost.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
    toHost.srcQueueFamilyIndex = toHost.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    toHost.buffer = slot.staging.buffer.get();
    toHost.size = VK_WHOLE_SIZE;
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 0,
                         nullptr, 1, &toHost, 0, nullptr);
    if (Status st = check(vkEndCommandBuffer(cmd), "vkEndCommandBuffer"); !st) return st;
    VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    si.commandBufferCount = 1;
    si.pCommandBuffers = &cmd;
    VkFence fence = slot.fence.get();
    if (Status st = check(vkResetFences(mContext->device(), 1, &fence), "vkResetFences"); !st)
        return st;
    if (Status st = check(vkQueueSubmit(mContext->queue(), 1, &si, fence), "vkQueueSubmit"); !st)
        return st;
    slot.pending = true;
    slot.firstView = firstView;
    slot.views = views;
    slot.readDepth = s.depth;
    return {};
}

Status Renderer::finishBatch(Slot& slot, RenderOutput& out, const RenderSettings& s,
                             int totalViews, double* copyMs) {
    if (!slot.pending) return {};
    slot.pending = false;
    VkFence fence = slot.fence.get();
    if (Status st = check(vkWaitForFences(mContext->device(), 1, &fence, VK_TRUE, UINT64_MAX),
                          "vkWaitForFences");
        !st)
        return st;
    const auto copyStart = Clock::now();
    const std::size_t px = std::size_t(s.width) * s.height;
    const auto* base = static_cast<const std::uint8_t*>(slot.staging.mapped);
    OutputBlock* block = blockFor(s, std::size_t(totalViews));
    for (int k = 0; k < slot.views; ++k) {
        const std::size_t v = std::size_t(slot.firstView + k);
        out.color[v].reuseOrReset(s.width, s.height, block ? block->colorMemory(int(v)) : nullptr);
        std::memcpy(out.color[v].rgba.data(), base + px * 4 * k, px * 4);
        if (slot.readDepth) {
            out.depth[v].reuseOrReset(s.width, s.height,
                                      block ? block->depthMemory(int(v)) : nullptr);
            std::memcpy(out.depth[v].depth.data(), base + px * 4 * slot.views + px * 4 * k, px * 4);
        }
    }
    *copyMs += msSince(copyStart);
    return {};
}

Status Renderer::renderMethod(const Scene& scene, const Rig& rig, const RenderSettings& s,
                              Method m, RenderOutput& out) {
    const auto t0 = Clock::now();
    const int total = int(rig.views.size());
    const int limit = batchLimit(m);
    const int batches = (total + limit - 1) / limit;
    // Batches of `limit` views and the rest (8 views at 6: 6 + 2; kalaiah2007 §3).
    const int perBatch = std::min(limit, total);
    if (Status st = ensureSlots(s.width, s.height, perBatch); !st) return st;
    std::vector<GpuMesh*> meshes;
    if (Status st = prepareScene(scene, meshes); !st) return st;
    if (Status st = uploadFrame(scene, rig, s); !st) return st;
    if (Status st = prepareTextures(scene); !st) return st;
    if (Status st = prepareShadows(); !st) return st;
    if (Status st = prepareEnvironment(scene); !st) return st;
    out.color.resize(std::size_t(total));
    if (s.depth) {
        out.depth.resize(std::size_t(total));
    } else {
        out.depth.clear();
    }
    out.depthRange.clear();
    out.method = methodName(m);
    out.note.clear();
    out.stages = {};
    double readMs = 0.0;  // copying out of the staging buffers (the fence waits are drawing)
    // Batch b draws in slot b % 2 while batch b − 1's pixels are copied out of the other.
    Status status;
    for (int b = 0; b < batches && status; ++b) {
        Slot& slot = mSlots[b % 2];
        const int first = b * limit;
        status = recordBatch(slot, m, s, first, std::min(limit, total - first), scene, meshes);
        if (status && b > 0) status = finishBatch(mSlots[(b - 1) % 2], out, s, total, &readMs);
    }
    for (Slot& slot : mSlots) {
        if (Status st = finishBatch(slot, out, s, total, &readMs); !st && status) status = st;
    }
    if (!status) {
        vkDeviceWaitIdle(mContext->device());
        for (Slot& slot : mSlots) slot.pending = false;
        return status;
    }
    RenderStats stats;
    stats.method = methodName(m);
    stats.totalWallMs = msSince(t0);
    stats.readbackWallMs = readMs;
    stats.drawWallMs = stats.totalWallMs - readMs;
    stats.passes = batches;
    mLastStats = stats;
    return {};
}

}  // namespace mvr::vk::detail
