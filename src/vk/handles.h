// src/vk/handles.h — RAII owners of Vulkan objects: one owner per object, destroyed in reverse
// order of declaration by the members that hold them (Context outlives everything it made).
#pragma once

#include <utility>

#include <vulkan/vulkan.h>

namespace mvr::vk::detail {

/// Owns one object made from `device` and destroys it with Destroy(device, handle, nullptr).
template <class T, void (*Destroy)(VkDevice, T, const VkAllocationCallbacks*)>
class Owned {
public:
    Owned() = default;
    Owned(VkDevice device, T handle) : mDevice(device), mHandle(handle) {}
    ~Owned() { reset(); }
    Owned(const Owned&) = delete;
    Owned& operator=(const Owned&) = delete;
    Owned(Owned&& o) noexcept
        : mDevice(std::exchange(o.mDevice, VK_NULL_HANDLE)),
          mHandle(std::exchange(o.mHandle, VK_NULL_HANDLE)) {}
    Owned& operator=(Owned&& o) noexcept {
        if (this != &o) {
            reset();
            mDevice = std::exchange(o.mDevice, VK_NULL_HANDLE);
            mHandle = std::exchange(o.mHandle, VK_NULL_HANDLE);
        }
        return *this;
    }
    void reset() {
        if (mHandle != VK_NULL_HANDLE) Destroy(mDevice, mHandle, nullptr);
        mHandle = VK_NULL_HANDLE;
    }
    T get() const { return mHandle; }
    explicit operator bool() const { return mHandle != VK_NULL_HANDLE; }

private:
    VkDevice mDevice = VK_NULL_HANDLE;
    T mHandle = VK_NULL_HANDLE;
};

using Buffer = Owned<VkBuffer, vkDestroyBuffer>;
using ImageHandle = Owned<VkImage, vkDestroyImage>;
using ImageView = Owned<VkImageView, vkDestroyImageView>;
using Memory = Owned<VkDeviceMemory, vkFreeMemory>;
using Framebuffer = Owned<VkFramebuffer, vkDestroyFramebuffer>;
using RenderPass = Owned<VkRenderPass, vkDestroyRenderPass>;
using Pipeline = Owned<VkPipeline, vkDestroyPipeline>;
using PipelineLayout = Owned<VkPipelineLayout, vkDestroyPipelineLayout>;
using ShaderModule = Owned<VkShaderModule, vkDestroyShaderModule>;
using DescriptorSetLayout = Owned<VkDescriptorSetLayout, vkDestroyDescriptorSetLayout>;
using DescriptorPool = Owned<VkDescriptorPool, vkDestroyDescriptorPool>;
using Fence = Owned<VkFence, vkDestroyFence>;
using CommandPool = Owned<VkCommandPool, vkDestroyCommandPool>;
using SamplerHandle = Owned<VkSampler, vkDestroySampler>;

/// A buffer with its memory, mapped for its lifetime when host visible.
struct BufferMemory {
    Buffer buffer;
    Memory memory;
    VkDeviceSize bytes = 0;
    void* mapped = nullptr;  ///< unmapped by freeing the memory
};

/// An image with its memory.
struct ImageMemory {
    ImageHandle image;
    Memory memory;
};

}  // namespace mvr::vk::detail
