// src/vk/renderer.h — the vk backend's internals: the context, GPU copies of meshes, the
// batch targets (two, so that one is read back while the next is drawn), render passes,
// pipelines and the per-method draws.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "context.h"
#include "mvr/core/render.h"
#include "mvr/core/shadows.h"
#include "spirv.h"

namespace mvr::vk::detail {

enum class Method { Multipass, Multiview, InstancedLayer };
const char* methodName(Method m);
/// Colour + depth, cleared, stored and left in TRANSFER_SRC for the copy; `viewMask` 0: no
/// multiview.
Result<RenderPass> makeRenderPassFor(VkDevice device, std::uint32_t viewMask);

/// A view of `layers` layers from `firstLayer` and `levels` mip levels of `image` (2D, or a 2D
/// array when `array`).
Result<ImageView> makeView(VkDevice device, VkImage image, VkFormat format,
                           VkImageAspectFlags aspect, int firstLayer, int layers, bool array,
                           int levels = 1);

/// The most views one batch target holds (layers of one image array): larger batches repeat
/// less vertex work, smaller ones keep the targets and the staging buffers small.
inline constexpr int kLayersPerBatch = 16;

struct GpuMesh {
    BufferMemory vertices;  ///< position, normal, colour, uv (48 bytes a vertex)
    BufferMemory indices;
    BufferMemory flat;  ///< unrolled triangles: position, face edge cross, centroid, colour, uv
    BufferMemory tangents;  ///< Mesh::tangents (16 bytes a vertex), none without them
    std::uint32_t indexCount = 0, flatVertexCount = 0;
    std::uint64_t lastUse = 0;
};

/// A scene texture on the device: sRGB (colour) or UNORM (data: Texture::linear), its mip chain
/// made by blits (gl: glGenerateMipmap).
struct GpuTexture {
    ImageMemory image;
    ImageView view;
    std::uint64_t lastUse = 0;
};
/// Textures kept between renders (least recently used evicted past it), as gl keeps.
inline constexpr std::size_t kTexturesKept = 64;
/// Descriptor sets of (textures, sampler) the pool holds; past it the pool is reset.
inline constexpr std::uint32_t kTextureSets = 256;
/// Set 1's bindings, one a texture slot: base colour, metallic-roughness, occlusion, emissive,
/// normal (scene.frag; a white texel where the material has none, which the shader then ignores
/// by InstanceData's slot bits).
inline constexpr std::uint32_t kTextureSlots = 5;
/// A texture's cache key: its content hash and whether it is data (Texture::linear, sampled as
/// UNORM) rather than colour (sRGB), so one image used both ways is two device images;
/// {0, false} is the white texel.
using TextureKey = std::pair<std::uint64_t, bool>;

/// Shadow maps on the device: linear distances (R32_SFLOAT), one layer per map.
struct ShadowImage {
    ImageMemory image;
    ImageView view;
    int size = 0, layers = 0;
};

/// Image lighting on the device (environment.cpp): a float image sampled by set 0's bindings 3
/// (an Environment's prefiltered levels as its mip levels) and 4 (the split-sum table).
struct GpuFloatImage {
    ImageMemory image;
    ImageView view;
    VkFormat format = VK_FORMAT_UNDEFINED;
};

/// The format image lighting's images of `channels` (2 or 4) floats take on `physical`: 32-bit
/// floats where it filters them linearly (VK_FORMAT_FEATURE_SAMPLED_IMAGE_FILTER_LINEAR_BIT),
/// else 16-bit; VK_FORMAT_UNDEFINED when neither filters.
VkFormat environmentFormat(VkPhysicalDevice physical, int channels);

/// A view of `layers` layers of a batch target and its framebuffers.
struct ArrayTarget {
    ImageView color, depth;
    Framebuffer layered;    ///< single-view render pass, `layers` framebuffer layers
    Framebuffer multiview;  ///< the multiview render pass of `layers` views
};

/// One batch in flight: its images, staging buffer, command buffer and fence.
struct Slot {
    int w = 0, h = 0, layers = 0;
    ImageMemory color, depth;
    std::vector<ImageView> colorLayer, depthLayer;  ///< one 2D view a layer
    std::vector<Framebuffer> layerFb;               ///< one a layer (multipass)
    std::map<int, ArrayTarget> arrays;              ///< by layer count
    BufferMemory staging;
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    Fence fence;
    bool pending = false;
    int firstView = 0, views = 0;
    bool readDepth = false;
};

class Renderer {
public:
    Renderer() = default;
    ~Renderer();
    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;

    Status ensureContext();
    /// Destroys every Vulkan object and the device now (later calls: Unsupported). Run for
    /// every live renderer by an exit handler registered after the driver's own, so that it
    /// runs before the driver (Mesa) tears its threads down: a backend held in a static is
    /// then destroyed safely after main() returns.
    void releaseDevice();
    std::vector<std::string> info();
    /// Usage for an unknown name, Unsupported when this device cannot run it.
    Status supports(const std::string& method);
    Status renderInto(const Scene& scene, const Rig& rig, const RenderSettings& s,
                      const std::string& method, RenderOutput& out);
    const std::optional<RenderStats>& lastStats() const { return mLastStats; }
    /// The shadow maps the next renders sample (shadows.h; null: none). The set must outlive
    /// those renders.
    void setShadows(const ShadowSet* set) { mShadows = set && !set->empty() ? set : nullptr; }

private:
    Status supportsMethod(Method m);
    Status checkRequest(const Scene& scene, const RenderSettings& s) const;
    Status renderMethod(const Scene& scene, const Rig& rig, const RenderSettings& s, Method m,
                        RenderOutput& out);
    Status renderAuto(const Scene& scene, const Rig& rig, const RenderSettings& s,
                      RenderOutput& out);
    int batchLimit(Method m) const;

    Status ensureStatic();
    Status ensureSlots(int w, int h, int layers);
    Result<ArrayTarget*> arrayTarget(Slot& slot, int layers, Method m);
    Result<VkRenderPass> multiviewPass(int views);
    Result<VkPipeline> pipeline(Method m, Shading shading, int views, bool cull, bool blend,
                                bool wire);
    Status prepareScene(const Scene& scene, std::vector<GpuMesh*>& meshes);
    Status uploadFrame(const Scene& scene, const Rig& rig, const RenderSettings& s);
    /// The scene's textures on the device and, per instance, the descriptor set (set 1) of its
    /// texture slots (kTextureSlots; a white texel for each slot it lacks) and sampler:
    /// mInstanceSets.
    Status prepareTextures(const Scene& scene);
    /// `linear`: data (Texture::linear), R8G8B8A8_UNORM; else colour, R8G8B8A8_SRGB.
    Result<GpuTexture> uploadTexture(const Image& image, const std::string& name, bool linear);
    Result<VkSampler> sampler(const TextureSampler& s);
    /// Records `record` into a one-time command buffer, submits it and waits (uploads; nothing
    /// else is in flight between renders).
    Status submitOnce(const std::function<void(VkCommandBuffer)>& record);
    /// mShadows' maps (or one unused 1x1 layer) into set 0's binding 2 (textures.cpp).
    Status prepareShadows();
    /// Scene::environment's levels and the split-sum table (or a 1x1 image for both when there
    /// is none) into set 0's bindings 3 and 4 (environment.cpp); uploads an Environment once.
    Status prepareEnvironment(const Scene& scene);
    /// A float image of `channels` (2 or 4) floats a texel with the given mip levels (each
    /// `channels` · w · h floats), 32-bit where the device filters it, else 16-bit.
    Result<GpuFloatImage> uploadFloatImage(const std::vector<std::pair<glm::ivec2, const float*>>& levels,
                                           int channels, const char* what);
    Status recordBatch(Slot& slot, Method m, const RenderSettings& s, int firstView, int views,
                       const Scene& scene, const std::vector<GpuMesh*>& meshes);
    /// Waits for the slot's fence and copies its views out (adding the copy's time to copyMs).
    Status finishBatch(Slot& slot, RenderOutput& out, const RenderSettings& s, int totalViews,
                       double* copyMs);

    // Declared first: destroyed last, after every object made from its device.
    std::unique_ptr<Context> mContext;
    std::optional<Status> mContextStatus;
    RenderPass mSinglePass;
    std::map<int, RenderPass> mMultiviewPasses;
    DescriptorSetLayout mSetLayout;
    DescriptorPool mDescriptorPool;
    VkDescriptorSet mSet = VK_NULL_HANDLE;
    PipelineLayout mPipelineLayout;
    std::map<std::uint32_t, Pipeline> mPipelines;
    std::map<int, ShaderModule> mModules;
    BufferMemory mFrameBuffer, mInstanceBuffer;
    // Textures (set 1: a combined image sampler per texture slot): by TextureKey; the white
    // texel absent slots bind; samplers by TextureSampler; sets by (slots' textures, sampler).
    DescriptorSetLayout mTextureLayout;
    DescriptorPool mTexturePool;
    std::map<TextureKey, GpuTexture> mTextures;
    std::optional<GpuTexture> mWhite;
    std::map<int, SamplerHandle> mSamplers;
    std::map<std::pair<std::array<TextureKey, kTextureSlots>, int>, VkDescriptorSet> mTextureSets;
    std::vector<VkDescriptorSet> mInstanceSets;
    const ShadowSet* mShadows = nullptr;
    ShadowImage mShadowImage;  ///< the last maps' image (reused while size and count hold)
    ShadowImage mNoShadow;     ///< one layer, bound when no light casts
    VkImageView mShadowBound = VK_NULL_HANDLE;
    // Image lighting (set 0, bindings 3 and 4): the last Environment uploaded, keyed by its
    // address and content hash; the split-sum table (once per device); the 1x1 image bound to
    // both when the scene has none; the view bound to binding 3.
    GpuFloatImage mEnvironment;
    std::pair<const void*, std::uint64_t> mEnvironmentKey{nullptr, 0};
    GpuFloatImage mSplitSum;
    GpuFloatImage mNoEnvironment;
    VkImageView mEnvironmentBound = VK_NULL_HANDLE;
    std::map<std::uint64_t, GpuMesh> mMeshes;
    /// (0, 0, 0, 1) per vertex, the tangents of meshes without them (pixel shading's binding 1).
    BufferMemory mNoTangents;
    std::uint64_t mUseCounter = 0;
    Slot mSlots[2];
    std::map<std::string, std::pair<Method, std::string>> mAutoChoices;
    std::optional<RenderStats> mLastStats;
};

}  // namespace mvr::vk::detail
