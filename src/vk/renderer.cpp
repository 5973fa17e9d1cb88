#include "renderer.h"

#include <algorithm>
#include <chrono>
#include <cstring>
#include <cstdlib>
#include <limits>
#include <mutex>
#include <set>

#include <fmt/format.h>
#include <glm/gtc/matrix_inverse.hpp>

#include "mvr/core/rig.h"
#include "mvr/core/scene.h"

namespace mvr::vk::detail {

namespace {

struct Push {
    std::int32_t instance = 0, viewBase = 0;
};
constexpr VkFormat kColorFormat = VK_FORMAT_R8G8B8A8_UNORM;
constexpr VkFormat kDepthFormat = VK_FORMAT_D32_SFLOAT;

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

}  // namespace

/// Colour + depth, cleared, stored, left ready to be copied; `viewMask` 0: no multiview.
Result<RenderPass> makeRenderPassFor(VkDevice device, std::uint32_t viewMask) {
    VkAttachmentDescription a[2]{};
    a[0].format = kColorFormat;
    a[1].format = kDepthFormat;
    for (auto& d : a) {
        d.samples = VK_SAMPLE_COUNT_1_BIT;
        d.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
        d.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
        d.stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
        d.stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
        d.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
        d.finalLayout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
    }
    VkAttachmentReference colorRef{0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
    VkAttachmentReference depthRef{1, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
    VkSubpassDescription sub{};
    sub.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
    sub.colorAttachmentCount = 1;
    sub.pColorAttachments = &colorRef;
    sub.pDepthStencilAttachment = &depthRef;
    const VkPipelineStageFlags attachments = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT |
                                             VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT |
                                             VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT;
    const VkAccessFlags writes =
        VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
    VkSubpassDependency deps[2]{};
    // The previous batch's copy out of these images before this pass writes them.
    deps[0].srcSubpass = VK_SUBPASS_EXTERNAL;
    deps[0].dstSubpass = 0;
    deps[0].srcStageMask = VK_PIPELINE_STAGE_TRANSFER_BIT;
    deps[0].dstStageMask = attachments;
    deps[0].srcAccessMask = 0;
    deps[0].dstAccessMask = writes | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT;
    // The pass's writes before the copy into the staging buffer.
    deps[1].srcSubpass = 0;
    deps[1].dstSubpass = VK_SUBPASS_EXTERNAL;
    deps[1].srcStageMask = attachments;
    deps[1].dstStageMask = VK_PIPELINE_STAGE_TRANSFER_BIT;
    deps[1].srcAccessMask = writes;
    deps[1].dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
    VkRenderPassMultiviewCreateInfo mv{VK_STRUCTURE_TYPE_RENDER_PASS_MULTIVIEW_CREATE_INFO};
    mv.subpassCount = 1;
    mv.pViewMasks = &viewMask;
    VkRenderPassCreateInfo ci{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
    if (viewMask) ci.pNext = &mv;
    ci.attachmentCount = 2;
    ci.pAttachments = a;
    ci.subpassCount = 1;
    ci.pSubpasses = &sub;
    ci.dependencyCount = 2;
    ci.pDependencies = deps;
    VkRenderPass pass = VK_NULL_HANDLE;
    if (Status s = check(vkCreateRenderPass(device, &ci, nullptr, &pass), "vkCreateRenderPass"); !s)
        return s;
    return RenderPass(device, pass);
}

Result<ImageView> makeView(VkDevice device, VkImage image, VkFormat format,
                           VkImageAspectFlags aspect, int firstLayer, int layers, bool array,
                           int levels) {
    VkImageViewCreateInfo ci{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    ci.image = image;
    ci.viewType = array ? VK_IMAGE_VIEW_TYPE_2D_ARRAY : VK_IMAGE_VIEW_TYPE_2D;
    ci.format = format;
    ci.subresourceRange = {aspect, 0, std::uint32_t(levels), std::uint32_t(firstLayer),
                           std::uint32_t(layers)};
    VkImageView v = VK_NULL_HANDLE;
    if (Status s = check(vkCreateImageView(device, &ci, nullptr, &v), "vkCreateImageView"); !s)
        return s;
    return ImageView(device, v);
}

const char* methodName(Method m) {
    switch (m) {
        case Method::Multipass: return "multipass";
        case Method::Multiview: return "multiview";
        case Method::InstancedLayer: return "instanced-layer";
    }
    return "?";
}

namespace {
// The live renderers with a device, released by the exit handler (releaseAtExit).
std::mutex gLiveMutex;
std::set<Renderer*> gLive;
void releaseAtExit() {
    std::set<Renderer*> live;
    {
        std::lock_guard lock(gLiveMutex);
        live = gLive;
    }
    for (Renderer* r : live) r->releaseDevice();  // (takes the lock itself)
}
}  // namespace

Renderer::~Renderer() { releaseDevice(); }

void Renderer::releaseDevice() {
    {
        std::lock_guard lock(gLiveMutex);
        gLive.erase(this);
    }
    if (!mContext) return;
    vkDeviceWaitIdle(mContext->device());
    for (Slot& s : mSlots) {
        if (s.cmd) vkFreeCommandBuffers(mContext->device(), mContext->commandPool(), 1, &s.cmd);
        s = Slot{};
    }
    mMeshes.clear();
    mNoTangents = {};
    mTextureSets.clear();
    mInstanceSets.clear();
    mTexturePool = {};
    mShadowImage = {};
    mNoShadow = {};
    mShadowBound = VK_NULL_HANDLE;
    mEnvironment = {};
    mEnvironmentKey = {nullptr, 0};
    mSplitSum = {};
    mNoEnvironment = {};
    mEnvironmentBound = VK_NULL_HANDLE;
    mTextures.clear();
    mWhite.reset();
    mSamplers.clear();
    mTextureLayout = {};
    mPipelines.clear();
    mModules.clear();
    mMultiviewPasses.clear();
    mSinglePass = {};
    mFrameBuffer = {};
    mInstanceBuffer = {};
    mPipelineLayout = {};
    mSet = VK_NULL_HANDLE;
    mDescriptorPool = {};
    mSetLayout = {};
    mContext.reset();
    mContextStatus = unsupportedError("vk: the device was released (the process is exiting)");
}

Status Renderer::ensureContext() {
    if (mContextStatus) return *mContextStatus;
    auto ctx = Context::create();
    if (!ctx) {
        mContextStatus = ctx.status();
        return *mContextStatus;
    }
    mContext = std::move(*ctx);
    {
        // After the driver's exit handlers (registered while the instance was made): ours
        // runs first.
        static std::once_flag once;
        std::call_once(once, [] { std::atexit(releaseAtExit); });
        std::lock_guard lock(gLiveMutex);
        gLive.insert(this);
    }
    Status s = ensureStatic();
    if (s) s = mContext->checkMessages("setting up");
    mContextStatus = s;
    return s;
}

Status Renderer::ensureStatic() {
    VkDevice d = mContext->device();
    auto single = makeRenderPassFor(d, 0);
    if (!single) return single.status();
    mSinglePass = std::move(*single);

    // Set 0: the frame's and the instances' storage buffers, the shadow maps, the environment's
    // prefiltered levels and the split-sum table (vertex shading looks them up in the vertex
    // stage).
    VkDescriptorSetLayoutBinding b[5]{};
    for (std::uint32_t i = 0; i < 5; ++i) {
        b[i].binding = i;
        b[i].descriptorType = i < 2 ? VK_DESCRIPTOR_TYPE_STORAGE_BUFFER
                                    : VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
        b[i].descriptorCount = 1;
        b[i].stageFlags = VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT;
    }
    VkDescriptorSetLayoutCreateInfo lci{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    lci.bindingCount = 5;
    lci.pBindings = b;
    VkDescriptorSetLayout layout = VK_NULL_HANDLE;
    if (Status s = check(vkCreateDescriptorSetLayout(d, &lci, nullptr, &layout),
                         "vkCreateDescriptorSetLayout");
        !s)
        return s;
    mSetLayout = DescriptorSetLayout(d, layout);
    const VkDescriptorPoolSize sizes[2] = {{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 2},
                                           {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 3}};
    VkDescriptorPoolCreateInfo pci{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    pci.maxSets = 1;
    pci.poolSizeCount = 2;
    pci.pPoolSizes = sizes;
    VkDescriptorPool pool = VK_NULL_HANDLE;
    if (Status s = check(vkCreateDescriptorPool(d, &pci, nullptr, &pool), "vkCreateDescriptorPool");
        !s)
        return s;
    mDescriptorPool = DescriptorPool(d, pool);
    VkDescriptorSetAllocateInfo ai{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    ai.descriptorPool = pool;
    ai.descriptorSetCount = 1;
    ai.pSetLayouts = &layout;
    if (Status s = check(vkAllocateDescriptorSets(d, &ai, &mSet), "vkAllocateDescriptorSets"); !s)
        return s;
    // Set 1: the texture slots (base colour, metallic-roughness, occlusion, emissive, normal:
    // bindings 0 to 4), each with the material's sampler (fragment stage).
    VkDescriptorSetLayoutBinding tb[kTextureSlots]{};
    for (std::uint32_t i = 0; i < kTextureSlots; ++i) {
        tb[i].binding = i;
        tb[i].descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
        tb[i].descriptorCount = 1;
        tb[i].stageFlags = VK_SHADER_STAGE_FRAGMENT_BIT;
    }
    VkDescriptorSetLayoutCreateInfo tci{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    tci.bindingCount = kTextureSlots;
    tci.pBindings = tb;
    VkDescriptorSetLayout textureLayout = VK_NULL_HANDLE;
    if (Status s = check(vkCreateDescriptorSetLayout(d, &tci, nullptr, &textureLayout),
                         "vkCreateDescriptorSetLayout");
        !s)
        return s;
    mTextureLayout = DescriptorSetLayout(d, textureLayout);
    VkDescriptorPoolSize tsize{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER,
                               kTextureSets * kTextureSlots};
    VkDescriptorPoolCreateInfo tpci{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    tpci.maxSets = kTextureSets;
    tpci.poolSizeCount = 1;
    tpci.pPoolSizes = &tsize;
    VkDescriptorPool texturePool = VK_NULL_HANDLE;
    if (Status s = check(vkCreateDescriptorPool(d, &tpci, nullptr, &texturePool),
                         "vkCreateDescriptorPool");
        !s)
        return s;
    mTexturePool = DescriptorPool(d, texturePool);
    VkPushConstantRange push{VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0,
                             sizeof(Push)};
    const VkDescriptorSetLayout layouts[2] = {layout, textureLayout};
    VkPipelineLayoutCreateInfo plci{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    plci.setLayoutCount = 2;
    plci.pSetLayouts = layouts;
    plci.pushConstantRangeCount = 1;
    plci.pPushConstantRanges = &push;
    VkPipelineLayout pl = VK_NULL_HANDLE;
    if (Status s = check(vkCreatePipelineLayout(d, &plci, nullptr, &pl), "vkCreatePipelineLayout");
        !s)
        return s;
    mPipelineLayout = PipelineLayout(d, pl);

    for (Slot& slot : mSlots) {
        VkCommandBufferAllocateInfo cai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
        cai.commandPool = mContext->commandPool();
        cai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
        cai.commandBufferCount = 1;
        if (Status s = check(vkAllocateCommandBuffers(d, &cai, &slot.cmd),
                             "vkAllocateCommandBuffers");
            !s)
            return s;
        VkFenceCreateInfo fci{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
        VkFence fence = VK_NULL_HANDLE;
        if (Status s = check(vkCreateFence(d, &fci, nullptr, &fence), "vkCreateFence"); !s)
            return s;
        slot.fence = Fence(d, fence);
    }
    return {};
}

std::vector<std::string> Renderer::info() {
    std::vector<std::string> lines;
    if (Status s = ensureContext(); !s) {
        lines.push_back("vk: unavailable: " + s.message());
        return lines;
    }
    const DeviceCaps& c = mContext->caps();
    lines.push_back(fmt::format("vk device: {} ({})", c.name, c.type));
    lines.push_back(fmt::format("vk driver: {}, Vulkan {}.{}.{}", c.driver,
                                VK_API_VERSION_MAJOR(c.apiVersion),
                                VK_API_VERSION_MINOR(c.apiVersion),
                                VK_API_VERSION_PATCH(c.apiVersion)));
    lines.push_back(fmt::format(
        "vk limits: maxMultiviewViewCount {}, maxFramebufferLayers {}, shaderOutputLayer {}, "
        "fillModeNonSolid {}",
        c.maxMultiviewViewCount, c.maxFramebufferLayers, c.shaderOutputLayer ? "yes" : "no",
        c.fillModeNonSolid ? "yes" : "no"));
    for (Method m : {Method::Multipass, Method::Multiview, Method::InstancedLayer}) {
        const Status s = supportsMethod(m);
        const bool oneView = m == Method::Multiview && c.multiviewOneView;
        lines.push_back(s ? fmt::format("vk method {}: supported, {} view{} a batch{}",
                                        methodName(m), batchLimit(m),
                                        batchLimit(m) == 1 ? "" : "s",
                                        oneView ? " (lavapipe: a pass of several views loses "
                                                  "clipped triangles past its first view; "
                                                  "MVR_VK_MULTIVIEW_WORKAROUND=0 batches them)"
                                                : "")
                          : fmt::format("vk method {}: unsupported: {}", methodName(m),
                                        s.message()));
    }
    auto formatName = [](VkFormat f) {
        switch (f) {
            case VK_FORMAT_R32G32B32A32_SFLOAT: return "R32G32B32A32_SFLOAT";
            case VK_FORMAT_R16G16B16A16_SFLOAT: return "R16G16B16A16_SFLOAT";
            case VK_FORMAT_R32G32_SFLOAT: return "R32G32_SFLOAT";
            case VK_FORMAT_R16G16_SFLOAT: return "R16G16_SFLOAT";
            default: return "none (unsupported)";
        }
    };
    lines.push_back(fmt::format("vk image lighting: map {}, split-sum table {}",
                                formatName(environmentFormat(mContext->physical(), 4)),
                                formatName(environmentFormat(mContext->physical(), 2))));
    lines.push_back(fmt::format("vk validation: {}", mContext->validation() ? "on" : "off"));
    return lines;
}

int Renderer::batchLimit(Method m) const {
    const DeviceCaps& c = mContext->caps();
    int limit = std::min<int>(kLayersPerBatch, int(c.maxImageArrayLayers));
    if (m == Method::Multiview)
        limit = c.multiviewOneView ? 1 : std::min<int>(limit, int(c.maxMultiviewViewCount));
    if (m == Method::InstancedLayer) limit = std::min<int>(limit, int(c.maxFramebufferLayers));
    return std::max(limit, 1);
}

Status Renderer::supportsMethod(Method m) {
    if (Status s = ensureContext(); !s) return s;
    const DeviceCaps& c = mContext->caps();
    if (m == Method::Multiview && (!c.multiview || c.maxMultiviewViewCount < 1))
        return unsupportedError("vk: multiview: the device has no VK_KHR_multiview");
    if (m == Method::InstancedLayer && !c.shaderOutputLayer)
        return unsupportedError(
            "vk: instanced-layer: the device lacks shaderOutputLayer (Vulkan 1.2)");
    return {};
}

Status Renderer::supports(const std::string& method) {
    if (method == "auto") return ensureContext();
    for (Method m : {Method::Multipass, Method::Multiview, Method::InstancedLayer}) {
        if (method == methodName(m)) return supportsMethod(m);
    }
    return usageError(fmt::format(
        "unknown vk method '{}' (expected multipass, multiview, instanced-layer or auto)", method));
}

Status Renderer::checkRequest(const Scene& /*scene*/, const RenderSettings& s) const {
    const DeviceCaps& c = mContext->caps();
    if (s.wireframe && !c.fillModeNonSolid)
        return unsupportedError("vk: wireframe needs fillModeNonSolid, which the device lacks");
    if (std::uint32_t(std::max(s.width, s.height)) > c.maxImageDimension2D) {
        return unsupportedError(fmt::format("vk: {}x{} exceeds maxImageDimension2D = {}", s.width,
                                            s.height, c.maxImageDimension2D));
    }
    return {};
}

Status Renderer::renderInto(const Scene& scene, const Rig& rig, const RenderSettings& s,
                            const std::string& method, RenderOutput& out) {
    if (Status st = validateRequest(scene, rig, s); !st) return st;
    if (Status st = supports(method); !st) return st;
    if (Status st = checkRequest(scene, s); !st) return st;
    Status st;
    if (method == "auto") {
        st = renderAuto(scene, rig, s, out);
    } else {
        Method m = Method::Multipass;
        for (Method c : {Method::Multipass, Method::Multiview, Method::InstancedLayer})
            if (method == methodName(c)) m = c;
        st = renderMethod(scene, rig, s, m, out);
    }
    if (Status v = mContext->checkMessages("rendering with vk:" + method); !v) return v;
    return st;
}

Status Renderer::renderAuto(const Scene& scene, const Rig& rig, const RenderSettings& s,
                            RenderOutput& out) {
    const std::string key =
        fmt::format("{}:{}x{}:{}:{}:{}", rig.views.size(), s.width, s.height,
                    shadingName(s.shading), s.depth ? 1 : 0, s.wireframe ? 1 : 0);
    auto it = mAutoChoices.find(key);
    if (it == mAutoChoices.end()) {
        // Each supported method once to build its pipelines, once timed.
        std::vector<std::string> times;
        Method best = Method::Multipass;
        double bestMs = std::numeric_limits<double>::infinity();
        for (Method m : {Method::Multipass, Method::Multiview, Method::InstancedLayer}) {
            if (!supportsMethod(m)) continue;
            if (Status st = renderMethod(scene, rig, s, m, out); !st) return st;
            const auto t = Clock::now();
            if (Status st = renderMethod(scene, rig, s, m, out); !st) return st;
            const double ms = msSince(t);
            times.push_back(fmt::format("{} {:.2f} ms", methodName(m), ms));
            if (ms < bestMs) bestMs = ms, best = m;
        }
        it = mAutoChoices
                 .emplace(key, std::pair{best, fmt::format("auto: {} measured fastest ({})",
                                                           methodName(best),
                                                           fmt::join(times, ", "))})
                 .first;
    }
    if (Status st = renderMethod(scene, rig, s, it->second.first, out); !st) return st;
    out.note = it->second.second;
    return {};
}

}  // namespace mvr::vk::detail
