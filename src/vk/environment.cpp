// The vk backend's image lighting (issue 39 item 2; environment.h, lighting.h environmentTerms):
// an Environment's prefiltered levels as the mip levels 0..5 of one equirectangular float image
// (set 0, binding 3: linear, linear mipmaps, REPEAT in u, CLAMP_TO_EDGE in v) and the split
// sum's table as a 32x32 two-channel float image (binding 4: linear, clamped), as
// environment.h says a GPU mirrors its lookups; the SH coefficients go in FrameData
// (batches.cpp). RGBA32F / RG32F where the device filters them linearly, else 16-bit floats.
// Each Environment is uploaded once (the last one is kept, by address and content), the
// table once per device; without an environment a 1x1 image is bound to both (never read:
// FrameData's counts.w is 0).
#include <algorithm>
#include <cstring>

#include <fmt/format.h>
#include <glm/gtc/packing.hpp>

#include "mvr/core/environment.h"
#include "mvr/core/scene.h"
#include "renderer.h"

namespace mvr::vk::detail {

namespace {

/// FNV-style, 8 bytes a step (as content_hash.h): the Environment's SH, level sizes and
/// texels. Never 0.
std::uint64_t environmentHash(const Environment& env) {
    std::uint64_t h = 0xcbf29ce484222325ull;
    auto mix = [&](const void* data, std::size_t bytes) {
        const auto* p = static_cast<const unsigned char*>(data);
        std::size_t i = 0;
        for (; i + 8 <= bytes; i += 8) {
            std::uint64_t w;
            std::memcpy(&w, p + i, 8);
            h = (h ^ w) * 0x100000001b3ull;
        }
        for (; i < bytes; ++i) h = (h ^ p[i]) * 0x100000001b3ull;
    };
    mix(env.sh.data(), sizeof(env.sh));
    for (const Environment::Level& l : env.levels) {
        const int size[2] = {l.width, l.height};
        mix(size, sizeof(size));
        mix(l.texels.data(), l.texels.size() * sizeof(glm::vec4));
    }
    return h ? h : 1;
}

}  // namespace

VkFormat environmentFormat(VkPhysicalDevice physical, int channels) {
    const VkFormat wide = channels == 4 ? VK_FORMAT_R32G32B32A32_SFLOAT : VK_FORMAT_R32G32_SFLOAT;
    const VkFormat half = channels == 4 ? VK_FORMAT_R16G16B16A16_SFLOAT : VK_FORMAT_R16G16_SFLOAT;
    const VkFormatFeatureFlags need =
        VK_FORMAT_FEATURE_SAMPLED_IMAGE_BIT | VK_FORMAT_FEATURE_SAMPLED_IMAGE_FILTER_LINEAR_BIT;
    for (VkFormat f : {wide, half}) {
        VkFormatProperties fp{};
        vkGetPhysicalDeviceFormatProperties(physical, f, &fp);
        if ((fp.optimalTilingFeatures & need) == need) return f;
    }
    return VK_FORMAT_UNDEFINED;
}

Result<GpuFloatImage> Renderer::uploadFloatImage(
    const std::vector<std::pair<glm::ivec2, const float*>>& levels, int channels,
    const char* what) {
    VkDevice d = mContext->device();
    const VkFormat format = environmentFormat(mContext->physical(), channels);
    if (format == VK_FORMAT_UNDEFINED)
        return unsupportedError(fmt::format(
            "vk: the device cannot filter {}-channel float images linearly ({})", channels, what));
    const bool wide =
        format == VK_FORMAT_R32G32B32A32_SFLOAT || format == VK_FORMAT_R32G32_SFLOAT;
    const std::size_t texelBytes = std::size_t(channels) * (wide ? 4 : 2);
    const glm::ivec2 size0 = levels.front().first;
    const DeviceCaps& caps = mContext->caps();
    if (std::uint32_t(std::max(size0.x, size0.y)) > caps.maxImageDimension2D)
        return unsupportedError(fmt::format("vk: {} is {}x{} (maxImageDimension2D = {})", what,
                                            size0.x, size0.y, caps.maxImageDimension2D));
    VkImageCreateInfo ci{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
    ci.imageType = VK_IMAGE_TYPE_2D;
    ci.format = format;
    ci.extent = {std::uint32_t(size0.x), std::uint32_t(size0.y), 1};
    ci.mipLevels = std::uint32_t(levels.size());
    ci.arrayLayers = 1;
    ci.samples = VK_SAMPLE_COUNT_1_BIT;
    ci.tiling = VK_IMAGE_TILING_OPTIMAL;
    ci.usage = VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_SAMPLED_BIT;
    ci.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    ci.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    auto img = mContext->makeImage(ci);
    if (!img) return img.status();
    // Every level into one staging buffer, each at an offset a multiple of 16 bytes.
    std::vector<VkBufferImageCopy> copies;
    VkDeviceSize total = 0;
    for (std::size_t k = 0; k < levels.size(); ++k) {
        const glm::ivec2 s = levels[k].first;
        // Vulkan's mip k is max(1, size0 >> k) in each dimension: so is an Environment level's.
        if (s.x != std::max(1, size0.x >> k) || s.y != std::max(1, size0.y >> k))
            return internalError(fmt::format("vk: {} level {} is {}x{}, not a mip of {}x{}", what,
                                             k, s.x, s.y, size0.x, size0.y));
        VkBufferImageCopy c{};
        c.bufferOffset = total;
        c.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, std::uint32_t(k), 0, 1};
        c.imageExtent = {std::uint32_t(s.x), std::uint32_t(s.y), 1};
        copies.push_back(c);
        total += (VkDeviceSize(s.x) * VkDeviceSize(s.y) * texelBytes + 15) / 16 * 16;
    }
    auto staging = mContext->makeBuffer(total, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, true);
    if (!staging) return staging.status();
    auto* dst = static_cast<unsigned char*>(staging->mapped);
    for (std::size_t k = 0; k < levels.size(); ++k) {
        const std::size_t n = std::size_t(levels[k].first.x) * std::size_t(levels[k].first.y) *
                              std::size_t(channels);
        unsigned char* o = dst + copies[k].bufferOffset;
        if (wide) {
            std::memcpy(o, levels[k].second, n * sizeof(float));
        } else {
            for (std::size_t i = 0; i < n; ++i) {
                // 16-bit floats end at 65504 (a bright sun can be more): clamped, not inf.
                const std::uint16_t h =
                    glm::packHalf1x16(std::min(levels[k].second[i], 65504.0f));
                std::memcpy(o + 2 * i, &h, 2);
            }
        }
    }
    VkImage im = img->image.get();
    const Status recorded = submitOnce([&](VkCommandBuffer cmd) {
        VkImageMemoryBarrier b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
        b.srcAccessMask = 0;
        b.dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
        b.oldLayout = VK_IMAGE_LAYOUT_UNDEFINED;
        b.newLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
        b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
        b.image = im;
        b.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, std::uint32_t(levels.size()), 0, 1};
        vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                             0, 0, nullptr, 0, nullptr, 1, &b);
        vkCmdCopyBufferToImage(cmd, staging->buffer.get(), im, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                               std::uint32_t(copies.size()), copies.data());
        b.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
        b.dstAccessMask = VK_ACCESS_SHADER_READ_BIT;
        b.oldLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
        b.newLayout = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
        vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT,
                             VK_PIPELINE_STAGE_VERTEX_SHADER_BIT |
                                 VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT,
                             0, 0, nullptr, 0, nullptr, 1, &b);
    });
    if (!recorded) return recorded;
    auto view = makeView(d, im, format, VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, false, int(levels.size()));
    if (!view) return view.status();
    GpuFloatImage out;
    out.image = std::move(*img);
    out.view = std::move(*view);
    out.format = format;
    return out;
}

Status Renderer::prepareEnvironment(const Scene& scene) {
    const Environment* env = scene.environment.get();
    if (env) {
        // The split sum's table: once per device.
        if (!mSplitSum.view) {
            const auto& table = splitSumTable();
            auto t = uploadFloatImage({{glm::ivec2(kBrdfSize), &table[0].x}}, 2, "the split-sum table");
            if (!t) return t.status();
            mSplitSum = std::move(*t);
        }
        // The environment: once per object and content (a sequence reuses one object).
        const std::pair<const void*, std::uint64_t> key{env, environmentHash(*env)};
        if (!mEnvironment.view || mEnvironmentKey != key) {
            std::vector<std::pair<glm::ivec2, const float*>> levels;
            for (const Environment::Level& l : env->levels) {
                if (l.texels.size() != std::size_t(l.width) * std::size_t(l.height) ||
                    l.texels.empty())
                    return internalError(
                        fmt::format("vk: environment '{}' has an empty or malformed level", env->name));
                levels.emplace_back(glm::ivec2(l.width, l.height), &l.texels[0].x);
            }
            // Nothing is in flight between renders: the old image may go.
            if (mEnvironmentBound == mEnvironment.view.get()) mEnvironmentBound = VK_NULL_HANDLE;
            mEnvironment = {};
            mEnvironmentKey = {nullptr, 0};
            const std::string what = fmt::format("environment '{}'", env->name);
            auto e = uploadFloatImage(levels, 4, what.c_str());
            if (!e) return e.status();
            mEnvironment = std::move(*e);
            mEnvironmentKey = key;
        }
    } else if (!mNoEnvironment.view) {
        const float zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
        auto n = uploadFloatImage({{glm::ivec2(1), zero}}, 4, "the unused environment");
        if (!n) return n.status();
        mNoEnvironment = std::move(*n);
    }
    const VkImageView map = env ? mEnvironment.view.get() : mNoEnvironment.view.get();
    if (mEnvironmentBound == map) return {};
    // environment.h: GL's LINEAR_MIPMAP_LINEAR, REPEAT in u, CLAMP_TO_EDGE in v for the map;
    // bilinear, clamped, its one level for the table.
    TextureSampler mapSampler;
    mapSampler.magFilter = mapSampler.minFilter = TextureFilter::Linear;
    mapSampler.mipmaps = true;
    mapSampler.wrapS = TextureWrap::Repeat;
    mapSampler.wrapT = TextureWrap::ClampToEdge;
    TextureSampler tableSampler = mapSampler;
    tableSampler.mipmaps = false;
    tableSampler.wrapS = TextureWrap::ClampToEdge;
    auto ms = sampler(mapSampler);
    if (!ms) return ms.status();
    auto ts = sampler(tableSampler);
    if (!ts) return ts.status();
    const VkImageView table = env ? mSplitSum.view.get() : mNoEnvironment.view.get();
    const VkDescriptorImageInfo ii[2] = {{*ms, map, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL},
                                         {*ts, table, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL}};
    VkWriteDescriptorSet w[2]{};
    for (int k = 0; k < 2; ++k) {
        w[k].sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET;
        w[k].dstSet = mSet;
        w[k].dstBinding = std::uint32_t(3 + k);
        w[k].descriptorCount = 1;
        w[k].descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
        w[k].pImageInfo = &ii[k];
    }
    vkUpdateDescriptorSets(mContext->device(), 2, w, 0, nullptr);
    mEnvironmentBound = map;
    return {};
}

}  // namespace mvr::vk::detail
