// The vk backend's textures (renderer.h): sRGB images (colour: base colour, emissive) or UNORM
// ones (data, Texture::linear: metallic-roughness, occlusion, normal) with their mip chain made
// by linear blits on the device (as gl's glGenerateMipmap: the box filter of the decoded colour,
// or of the bytes / 255 for data, as texture_sampling.h's buildMipChain), samplers from the
// material's TextureSampler, and one descriptor set (set 1, a binding per texture slot) per
// instance.
#include <algorithm>
#include <array>
#include <cstring>

#include <fmt/format.h>

#include "mvr/core/content_hash.h"
#include "mvr/core/scene.h"
#include "renderer.h"

namespace mvr::vk::detail {

namespace {

/// Colour is decoded from sRGB when sampled; data (Texture::linear) is byte / 255.
constexpr VkFormat kColorTextureFormat = VK_FORMAT_R8G8B8A8_SRGB;
constexpr VkFormat kDataTextureFormat = VK_FORMAT_R8G8B8A8_UNORM;

/// The sampler cache's key of a TextureSampler.
int samplerKey(const TextureSampler& s) {
    return int(s.magFilter) | int(s.minFilter) << 1 | int(s.mipmaps) << 2 | int(s.wrapS) << 3 |
           int(s.wrapT) << 5;
}

int mipLevels(int w, int h) {
    int levels = 1;
    for (int s = std::max(w, h); s > 1; s >>= 1) ++levels;
    return levels;
}

VkSamplerAddressMode addressMode(TextureWrap w) {
    switch (w) {
        case TextureWrap::ClampToEdge: return VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
        case TextureWrap::MirroredRepeat: return VK_SAMPLER_ADDRESS_MODE_MIRRORED_REPEAT;
        case TextureWrap::Repeat: break;
    }
    return VK_SAMPLER_ADDRESS_MODE_REPEAT;
}

void barrier(VkCommandBuffer cmd, VkImage image, int level, int levels, VkImageLayout from,
             VkImageLayout to, VkAccessFlags srcAccess, VkAccessFlags dstAccess,
             VkPipelineStageFlags srcStage, VkPipelineStageFlags dstStage) {
    VkImageMemoryBarrier b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
    b.srcAccessMask = srcAccess;
    b.dstAccessMask = dstAccess;
    b.oldLayout = from;
    b.newLayout = to;
    b.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    b.image = image;
    b.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, std::uint32_t(level), std::uint32_t(levels),
                          0, 1};
    vkCmdPipelineBarrier(cmd, srcStage, dstStage, 0, 0, nullptr, 0, nullptr, 1, &b);
}

}  // namespace

Result<GpuTexture> Renderer::uploadTexture(const Image& image, const std::string& name,
                                           bool linear) {
    VkDevice d = mContext->device();
    const int w = image.width, h = image.height;
    const DeviceCaps& caps = mContext->caps();
    if (w <= 0 || h <= 0 || std::uint32_t(std::max(w, h)) > caps.maxImageDimension2D)
        return unsupportedError(fmt::format("vk: texture '{}' is {}x{} (maxImageDimension2D = {})",
                                            name, w, h, caps.maxImageDimension2D));
    const VkFormat format = linear ? kDataTextureFormat : kColorTextureFormat;
    VkFormatProperties fp{};
    vkGetPhysicalDeviceFormatProperties(mContext->physical(), format, &fp);
    const VkFormatFeatureFlags need = VK_FORMAT_FEATURE_SAMPLED_IMAGE_BIT |
                                      VK_FORMAT_FEATURE_SAMPLED_IMAGE_FILTER_LINEAR_BIT |
                                      VK_FORMAT_FEATURE_BLIT_SRC_BIT |
                                      VK_FORMAT_FEATURE_BLIT_DST_BIT;
    if ((fp.optimalTilingFeatures & need) != need)
        return unsupportedError(fmt::format(
            "vk: the device cannot sample, filter and blit R8G8B8A8_{} images (textures)",
            linear ? "UNORM" : "SRGB"));
    const int levels = mipLevels(w, h);
    VkImageCreateInfo ci{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
    ci.imageType = VK_IMAGE_TYPE_2D;
    ci.format = format;
    ci.extent = {std::uint32_t(w), std::uint32_t(h), 1};
    ci.mipLevels = std::uint32_t(levels);
    ci.arrayLayers = 1;
    ci.samples = VK_SAMPLE_COUNT_1_BIT;
    ci.tiling = VK_IMAGE_TILING_OPTIMAL;
    ci.usage = VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT |
               VK_IMAGE_USAGE_SAMPLED_BIT;
    ci.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    ci.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    auto img = mContext->makeImage(ci);
    if (!img) return img.status();
    auto staging = mContext->makeBuffer(image.rgba.size(), VK_BUFFER_USAGE_TRANSFER_SRC_BIT, true);
    if (!staging) return staging.status();
    std::memcpy(staging->mapped, image.rgba.data(), image.rgba.size());

    VkImage im = img->image.get();
    const Status recorded = submitOnce([&](VkCommandBuffer cmd) {
    barrier(cmd, im, 0, levels, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 0,
            VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT,
            VK_PIPELINE_STAGE_TRANSFER_BIT);
    // Row 0 of the image = texture coordinate t = 0 (glTF's v = 0 is the top row), as in gl.
    VkBufferImageCopy copy{};
    copy.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    copy.imageExtent = {std::uint32_t(w), std::uint32_t(h), 1};
    vkCmdCopyBufferToImage(cmd, staging->buffer.get(), im, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1,
                           &copy);
    int lw = w, lh = h;
    for (int level = 1; level < levels; ++level) {
        barrier(cmd, im, level - 1, 1, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_ACCESS_TRANSFER_WRITE_BIT,
                VK_ACCESS_TRANSFER_READ_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                VK_PIPELINE_STAGE_TRANSFER_BIT);
        const int nw = std::max(1, lw / 2), nh = std::max(1, lh / 2);
        VkImageBlit blit{};
        blit.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, std::uint32_t(level - 1), 0, 1};
        blit.srcOffsets[1] = {lw, lh, 1};
        blit.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, std::uint32_t(level), 0, 1};
        blit.dstOffsets[1] = {nw, nh, 1};
        vkCmdBlitImage(cmd, im, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, im,
                       VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &blit, VK_FILTER_LINEAR);
        lw = nw, lh = nh;
    }
    if (levels > 1)
        barrier(cmd, im, 0, levels - 1, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, VK_ACCESS_TRANSFER_READ_BIT,
                VK_ACCESS_SHADER_READ_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT);
    barrier(cmd, im, levels - 1, 1, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
            VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, VK_ACCESS_TRANSFER_WRITE_BIT,
            VK_ACCESS_SHADER_READ_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
            VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT);
    });
    if (!recorded) return recorded;

    auto view = makeView(d, im, format, VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, false, levels);
    if (!view) return view.status();
    GpuTexture t;
    t.image = std::move(*img);
    t.view = std::move(*view);
    return t;
}

Status Renderer::submitOnce(const std::function<void(VkCommandBuffer)>& record) {
    VkDevice d = mContext->device();
    VkCommandBufferAllocateInfo cai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    cai.commandPool = mContext->commandPool();
    cai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    cai.commandBufferCount = 1;
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    if (Status s = check(vkAllocateCommandBuffers(d, &cai, &cmd), "vkAllocateCommandBuffers"); !s)
        return s;
    struct FreeCmd {
        VkDevice d;
        VkCommandPool pool;
        VkCommandBuffer cmd;
        ~FreeCmd() { vkFreeCommandBuffers(d, pool, 1, &cmd); }
    } freeCmd{d, mContext->commandPool(), cmd};
    VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    if (Status s = check(vkBeginCommandBuffer(cmd, &bi), "vkBeginCommandBuffer"); !s) return s;
    record(cmd);
    if (Status s = check(vkEndCommandBuffer(cmd), "vkEndCommandBuffer"); !s) return s;
    VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    si.commandBufferCount = 1;
    si.pCommandBuffers = &cmd;
    if (Status s = check(vkQueueSubmit(mContext->queue(), 1, &si, VK_NULL_HANDLE), "vkQueueSubmit");
        !s)
        return s;
    return check(vkQueueWaitIdle(mContext->queue()), "vkQueueWaitIdle");
}

Status Renderer::prepareShadows() {
    VkDevice d = mContext->device();
    const bool any = mShadows != nullptr;
    const int size = any ? mShadows->maps.front().size : 1;
    const int layers = any ? int(mShadows->maps.size()) : 1;
    ShadowImage& target = any ? mShadowImage : mNoShadow;
    const bool fresh = target.size != size || target.layers != layers;
    if (fresh) {
        VkImageCreateInfo ci{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
        ci.imageType = VK_IMAGE_TYPE_2D;
        ci.format = VK_FORMAT_R32_SFLOAT;
        ci.extent = {std::uint32_t(size), std::uint32_t(size), 1};
        ci.mipLevels = 1;
        ci.arrayLayers = std::uint32_t(layers);
        ci.samples = VK_SAMPLE_COUNT_1_BIT;
        ci.tiling = VK_IMAGE_TILING_OPTIMAL;
        ci.usage = VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_SAMPLED_BIT;
        ci.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
        ci.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
        auto img = mContext->makeImage(ci);
        if (!img) return img.status();
        auto view = makeView(d, img->image.get(), VK_FORMAT_R32_SFLOAT, VK_IMAGE_ASPECT_COLOR_BIT,
                             0, layers, true);
        if (!view) return view.status();
        if (mShadowBound == target.view.get()) mShadowBound = VK_NULL_HANDLE;
        target = {};
        target.image = std::move(*img);
        target.view = std::move(*view);
        target.size = size, target.layers = layers;
    }
    // The maps' distances (rows bottom first: texel (x, y) is depth[y · size + x], as gl's
    // upload); the unused layer only once.
    if (any || fresh) {
        const VkDeviceSize layerBytes = VkDeviceSize(size) * size * sizeof(float);
        auto staging = mContext->makeBuffer(layerBytes * VkDeviceSize(layers),
                                            VK_BUFFER_USAGE_TRANSFER_SRC_BIT, true);
        if (!staging) return staging.status();
        auto* dst = static_cast<unsigned char*>(staging->mapped);
        for (int k = 0; k < layers; ++k) {
            if (any)
                std::memcpy(dst + layerBytes * VkDeviceSize(k),
                            mShadows->maps[std::size_t(k)].depth.data(), layerBytes);
            else
                std::memset(dst, 0, layerBytes);
        }
        VkImage im = target.image.image.get();
        const Status recorded = submitOnce([&](VkCommandBuffer cmd) {
            VkImageMemoryBarrier b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
            b.srcAccessMask = fresh ? 0 : VK_ACCESS_SHADER_READ_BIT;
            b.dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
            b.oldLayout = fresh ? VK_IMAGE_LAYOUT_UNDEFINED : VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
            b.newLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
            b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
            b.image = im;
            b.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, std::uint32_t(layers)};
            const VkPipelineStageFlags shaders =
                VK_PIPELINE_STAGE_VERTEX_SHADER_BIT | VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT;
            vkCmdPipelineBarrier(cmd, fresh ? VkPipelineStageFlags(VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT) : shaders,
                                 VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0, nullptr, 0, nullptr, 1, &b);
            VkBufferImageCopy copy{};
            copy.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, std::uint32_t(layers)};
            copy.imageExtent = {std::uint32_t(size), std::uint32_t(size), 1};
            vkCmdCopyBufferToImage(cmd, staging->buffer.get(), im,
                                   VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &copy);
            b.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
            b.dstAccessMask = VK_ACCESS_SHADER_READ_BIT;
            b.oldLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
            b.newLayout = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
            vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, shaders, 0, 0, nullptr, 0,
                                 nullptr, 1, &b);
        });
        if (!recorded) return recorded;
    }
    if (mShadowBound != target.view.get()) {
        // texelFetch reads the maps: the sampler's filtering is never used.
        TextureSampler nearest;
        nearest.magFilter = nearest.minFilter = TextureFilter::Nearest;
        nearest.mipmaps = false;
        nearest.wrapS = nearest.wrapT = TextureWrap::ClampToEdge;
        auto smp = sampler(nearest);
        if (!smp) return smp.status();
        VkDescriptorImageInfo ii{*smp, target.view.get(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
        VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
        w.dstSet = mSet;
        w.dstBinding = 2;
        w.descriptorCount = 1;
        w.descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
        w.pImageInfo = &ii;
        vkUpdateDescriptorSets(d, 1, &w, 0, nullptr);
        mShadowBound = target.view.get();
    }
    return {};
}

Result<VkSampler> Renderer::sampler(const TextureSampler& s) {
    const int key = samplerKey(s);
    if (auto it = mSamplers.find(key); it != mSamplers.end()) return it->second.get();
    VkSamplerCreateInfo ci{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
    ci.magFilter = s.magFilter == TextureFilter::Linear ? VK_FILTER_LINEAR : VK_FILTER_NEAREST;
    ci.minFilter = s.minFilter == TextureFilter::Linear ? VK_FILTER_LINEAR : VK_FILTER_NEAREST;
    // gl: GL_LINEAR_MIPMAP_LINEAR / GL_NEAREST_MIPMAP_LINEAR with mipmaps, else the base level.
    ci.mipmapMode = s.mipmaps ? VK_SAMPLER_MIPMAP_MODE_LINEAR : VK_SAMPLER_MIPMAP_MODE_NEAREST;
    ci.addressModeU = addressMode(s.wrapS);
    ci.addressModeV = addressMode(s.wrapT);
    ci.addressModeW = VK_SAMPLER_ADDRESS_MODE_REPEAT;
    ci.minLod = 0.0f;
    ci.maxLod = s.mipmaps ? VK_LOD_CLAMP_NONE : 0.0f;
    VkSampler smp = VK_NULL_HANDLE;
    if (Status st = check(vkCreateSampler(mContext->device(), &ci, nullptr, &smp),
                          "vkCreateSampler");
        !st)
        return st;
    return mSamplers.emplace(key, SamplerHandle(mContext->device(), smp)).first->second.get();
}

Status Renderer::prepareTextures(const Scene& scene) {
    VkDevice d = mContext->device();
    if (!mWhite) {
        auto white = uploadTexture(Image(1, 1, {255, 255, 255, 255}), "white", false);
        if (!white) return white.status();
        mWhite = std::move(*white);
    }
    // The scene's textures: kept by content and kind (colour / data); past kTexturesKept the
    // least recently used go, with every descriptor set (they may name them): nothing is in
    // flight here.
    ++mUseCounter;
    std::vector<TextureKey> keys(scene.textures.size());
    for (std::size_t i = 0; i < scene.textures.size(); ++i) {
        const Texture& tex = scene.textures[i];
        const TextureKey key{contentHash(tex.image), tex.linear};  // hash never 0
        keys[i] = key;
        auto it = mTextures.find(key);
        if (it == mTextures.end()) {
            while (mTextures.size() >= kTexturesKept) {
                auto lru = mTextures.end();
                for (auto t = mTextures.begin(); t != mTextures.end(); ++t)
                    if (t->second.lastUse < mUseCounter &&
                        (lru == mTextures.end() || t->second.lastUse < lru->second.lastUse))
                        lru = t;
                if (lru == mTextures.end()) break;
                vkResetDescriptorPool(d, mTexturePool.get(), 0);
                mTextureSets.clear();
                mTextures.erase(lru);
            }
            auto t = uploadTexture(tex.image, tex.name, tex.linear);
            if (!t) return t.status();
            it = mTextures.emplace(key, std::move(*t)).first;
        }
        it->second.lastUse = mUseCounter;
    }
    // The key of texture index `t` in a slot: the white texel ({0, false}) for none.
    const TextureKey white{0, false};
    auto slotKey = [&](int t) {
        return t >= 0 && std::size_t(t) < keys.size() ? keys[std::size_t(t)] : white;
    };
    // One set per (slots' textures, sampler) an instance uses.
    mInstanceSets.assign(scene.instances.size(), VK_NULL_HANDLE);
    bool restarted = false;
    for (std::size_t i = 0; i < scene.instances.size(); ++i) {
        const Material& m = scene.instances[i].material;
        // Binding order (scene.frag): base colour, metallic-roughness, occlusion, emissive,
        // normal.
        const std::array<TextureKey, kTextureSlots> slots = {
            slotKey(m.baseColorTexture), slotKey(m.metallicRoughnessTexture),
            slotKey(m.occlusionTexture), slotKey(m.emissiveTexture), slotKey(m.normalTexture)};
        // Every slot samples with the material's one sampler; an instance with no texture
        // (validateScene checked the indices) samples only white texels, with the default
        // sampler (fewer distinct sets).
        const TextureSampler samplerInfo = hasTexture(m) ? m.sampler : TextureSampler{};
        auto smp = sampler(samplerInfo);
        if (!smp) return smp.status();
        const int sampled = samplerKey(samplerInfo);
        auto it = mTextureSets.find({slots, sampled});
        if (it == mTextureSets.end()) {
            if (mTextureSets.size() >= kTextureSets) {  // every set of this frame is made anew
                if (restarted)
                    return unsupportedError(fmt::format(
                        "vk: the scene's materials use more than {} combinations of textures "
                        "and sampler",
                        kTextureSets));
                restarted = true;
                vkResetDescriptorPool(d, mTexturePool.get(), 0);
                mTextureSets.clear();
                std::fill(mInstanceSets.begin(), mInstanceSets.begin() + std::ptrdiff_t(i),
                          VK_NULL_HANDLE);
                i = std::size_t(-1);  // restart the loop (++i: 0)
                continue;
            }
            VkDescriptorSetLayout layout = mTextureLayout.get();
            VkDescriptorSetAllocateInfo ai{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
            ai.descriptorPool = mTexturePool.get();
            ai.descriptorSetCount = 1;
            ai.pSetLayouts = &layout;
            VkDescriptorSet set = VK_NULL_HANDLE;
            if (Status s = check(vkAllocateDescriptorSets(d, &ai, &set), "vkAllocateDescriptorSets");
                !s)
                return s;
            VkDescriptorImageInfo ii[kTextureSlots];
            VkWriteDescriptorSet w[kTextureSlots];
            for (std::uint32_t k = 0; k < kTextureSlots; ++k) {
                const GpuTexture& tex = slots[k] == white ? *mWhite : mTextures.at(slots[k]);
                ii[k] = {*smp, tex.view.get(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
                w[k] = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
                w[k].dstSet = set;
                w[k].dstBinding = k;
                w[k].descriptorCount = 1;
                w[k].descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
                w[k].pImageInfo = &ii[k];
            }
            vkUpdateDescriptorSets(d, kTextureSlots, w, 0, nullptr);
            it = mTextureSets.emplace(std::make_pair(slots, sampled), set).first;
        }
        mInstanceSets[i] = it->second;
    }
    return {};
}

}  // namespace mvr::vk::detail
