// src/vk/context.h — the Vulkan instance, the device chosen for the backend, its queue and
// command pool, the validation messenger (MVR_VK_VALIDATION=1) and memory helpers.
#pragma once

#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "handles.h"
#include "mvr/core/status.h"

namespace mvr::vk::detail {

struct DeviceCaps {
    std::string name, driver, type;
    std::uint32_t apiVersion = 0;
    std::uint32_t maxMultiviewViewCount = 0;
    std::uint32_t maxFramebufferLayers = 0;
    std::uint32_t maxImageArrayLayers = 0;
    std::uint32_t maxImageDimension2D = 0;
    bool multiview = false;
    bool shaderOutputLayer = false;
    bool fillModeNonSolid = false;
    bool hostCachedStaging = false;
    /// Multiview passes hold one view (lavapipe: a pass of several views loses the large,
    /// clipped triangles of every view but its first; src/vk/README.md). Off with
    /// MVR_VK_MULTIVIEW_WORKAROUND=0.
    bool multiviewOneView = false;
};

class Context {
public:
    /// The instance and device (see vk_backend.h: device choice, validation).
    static Result<std::unique_ptr<Context>> create();
    ~Context();
    Context(const Context&) = delete;
    Context& operator=(const Context&) = delete;

    VkDevice device() const { return mDevice; }
    VkPhysicalDevice physical() const { return mPhysical; }
    VkQueue queue() const { return mQueue; }
    VkCommandPool commandPool() const { return mPool.get(); }
    const DeviceCaps& caps() const { return mCaps; }
    bool validation() const { return mValidation; }

    /// The validation messages since the last call (empty when none or validation is off).
    std::vector<std::string> takeMessages();
    /// ok, or an Internal error quoting the validation messages `what` caused.
    Status checkMessages(const std::string& what);

    Result<BufferMemory> makeBuffer(VkDeviceSize bytes, VkBufferUsageFlags usage, bool host);
    Result<ImageMemory> makeImage(const VkImageCreateInfo& info);

private:
    Context() = default;
    Result<std::uint32_t> memoryType(std::uint32_t bits, VkMemoryPropertyFlags want,
                                     VkMemoryPropertyFlags prefer = 0) const;

    VkInstance mInstance = VK_NULL_HANDLE;
    VkDebugUtilsMessengerEXT mMessenger = VK_NULL_HANDLE;
    VkPhysicalDevice mPhysical = VK_NULL_HANDLE;
    VkDevice mDevice = VK_NULL_HANDLE;
    VkQueue mQueue = VK_NULL_HANDLE;
    CommandPool mPool;
    DeviceCaps mCaps;
    VkPhysicalDeviceMemoryProperties mMemory{};
    bool mValidation = false;
    std::mutex mMessageMutex;
    std::vector<std::string> mMessages;
    static VKAPI_ATTR VkBool32 VKAPI_CALL onMessage(
        VkDebugUtilsMessageSeverityFlagBitsEXT, VkDebugUtilsMessageTypeFlagsEXT,
        const VkDebugUtilsMessengerCallbackDataEXT*, void*);
};

/// "VK_ERROR_OUT_OF_DEVICE_MEMORY" etc.
const char* resultName(VkResult r);
/// ok, or Internal "vk: WHAT: VK_ERROR_…".
Status check(VkResult r, const char* what);

}  // namespace mvr::vk::detail
