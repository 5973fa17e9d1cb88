#include "context.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include <fmt/format.h>

namespace mvr::vk::detail {

const char* resultName(VkResult r) {
    switch (r) {
        case VK_SUCCESS: return "VK_SUCCESS";
        case VK_NOT_READY: return "VK_NOT_READY";
        case VK_TIMEOUT: return "VK_TIMEOUT";
        case VK_ERROR_OUT_OF_HOST_MEMORY: return "VK_ERROR_OUT_OF_HOST_MEMORY";
        case VK_ERROR_OUT_OF_DEVICE_MEMORY: return "VK_ERROR_OUT_OF_DEVICE_MEMORY";
        case VK_ERROR_INITIALIZATION_FAILED: return "VK_ERROR_INITIALIZATION_FAILED";
        case VK_ERROR_DEVICE_LOST: return "VK_ERROR_DEVICE_LOST";
        case VK_ERROR_LAYER_NOT_PRESENT: return "VK_ERROR_LAYER_NOT_PRESENT";
        case VK_ERROR_EXTENSION_NOT_PRESENT: return "VK_ERROR_EXTENSION_NOT_PRESENT";
        case VK_ERROR_FEATURE_NOT_PRESENT: return "VK_ERROR_FEATURE_NOT_PRESENT";
        case VK_ERROR_INCOMPATIBLE_DRIVER: return "VK_ERROR_INCOMPATIBLE_DRIVER";
        case VK_ERROR_FORMAT_NOT_SUPPORTED: return "VK_ERROR_FORMAT_NOT_SUPPORTED";
        default: return "VK_ERROR_(other)";
    }
}

Status check(VkResult r, const char* what) {
    if (r == VK_SUCCESS) return {};
    return internalError(fmt::format("vk: {}: {}", what, resultName(r)));
}

namespace {

bool envIs(const char* name, const char* value) {
    const char* v = std::getenv(name);
    return v && std::strcmp(v, value) == 0;
}

const char* typeName(VkPhysicalDeviceType t) {
    switch (t) {
        case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return "discrete GPU";
        case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return "integrated GPU";
        case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return "virtual GPU";
        case VK_PHYSICAL_DEVICE_TYPE_CPU: return "CPU";
        default: return "other";
    }
}

int typeRank(VkPhysicalDeviceType t) {
    switch (t) {
        case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return 0;
        case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return 1;
        case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return 2;
        case VK_PHYSICAL_DEVICE_TYPE_CPU: return 3;
        default: return 4;
    }
}

struct Candidate {
    VkPhysicalDevice device = VK_NULL_HANDLE;
    std::uint32_t queueFamily = 0;
    DeviceCaps caps;
    VkPhysicalDeviceType type{};
    std::string why;  ///< empty: usable
};

Candidate inspect(VkPhysicalDevice d) {
    Candidate c;
    c.device = d;
    VkPhysicalDeviceMultiviewProperties mv{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MULTIVIEW_PROPERTIES};
    VkPhysicalDeviceDriverProperties drv{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
    mv.pNext = &drv;
    VkPhysicalDeviceProperties2 p{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
    p.pNext = &mv;
    vkGetPhysicalDeviceProperties2(d, &p);
    c.type = p.properties.deviceType;
    c.caps.name = p.properties.deviceName;
    c.caps.type = typeName(p.properties.deviceType);
    c.caps.apiVersion = p.properties.apiVersion;
    c.caps.maxFramebufferLayers = p.properties.limits.maxFramebufferLayers;
    c.caps.maxImageArrayLayers = p.properties.limits.maxImageArrayLayers;
    c.caps.maxImageDimension2D = p.properties.limits.maxImageDimension2D;
    if (p.properties.apiVersion < VK_API_VERSION_1_2) {
        c.why = fmt::format("{}: Vulkan {}.{} (1.2 needed)", c.caps.name,
                            VK_API_VERSION_MAJOR(p.properties.apiVersion),
                            VK_API_VERSION_MINOR(p.properties.apiVersion));
        return c;
    }
    c.caps.driver = fmt::format("{} {}", drv.driverName, drv.driverInfo);
    c.caps.maxMultiviewViewCount = mv.maxMultiviewViewCount;
    // Mesa's lavapipe (22.3.6, Debian 12): with two or more views in a pass, views past the
    // first lose large triangles the rasterizer clips (an 8x8 ground quad of two triangles:
    // 70 % of view 1's pixels wrong), while one view a pass is right (src/vk/README.md).
    c.caps.multiviewOneView = drv.driverID == VK_DRIVER_ID_MESA_LLVMPIPE &&
                              !envIs("MVR_VK_MULTIVIEW_WORKAROUND", "0");

    VkPhysicalDeviceVulkan12Features f12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
    VkPhysicalDeviceVulkan11Features f11{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_1_FEATURES};
    f11.pNext = &f12;
    VkPhysicalDeviceFeatures2 f{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
    f.pNext = &f11;
    vkGetPhysicalDeviceFeatures2(d, &f);
    c.caps.multiview = f11.multiview == VK_TRUE;
    c.caps.shaderOutputLayer = f12.shaderOutputLayer == VK_TRUE;
    c.caps.fillModeNonSolid = f.features.fillModeNonSolid == VK_TRUE;

    std::uint32_t n = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(d, &n, nullptr);
    std::vector<VkQueueFamilyProperties> families(n);
    vkGetPhysicalDeviceQueueFamilyProperties(d, &n, families.data());
    bool found = false;
    for (std::uint32_t i = 0; i < n && !found; ++i) {
        if (families[i].queueFlags & VK_QUEUE_GRAPHICS_BIT) c.queueFamily = i, found = true;
    }
    if (!found) c.why = c.caps.name + ": no graphics queue";
    return c;
}

/// `size` bytes of memory type `type`, owned.
Result<Memory> allocateMemory(VkDevice device, VkDeviceSize size, std::uint32_t type) {
    VkMemoryAllocateInfo mai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    mai.allocationSize = size;
    mai.memoryTypeIndex = type;
    VkDeviceMemory memory = VK_NULL_HANDLE;
    if (Status s = check(vkAllocateMemory(device, &mai, nullptr, &memory), "vkAllocateMemory"); !s)
        return s;
    return Memory(device, memory);
}

}  // namespace

VKAPI_ATTR VkBool32 VKAPI_CALL Context::onMessage(VkDebugUtilsMessageSeverityFlagBitsEXT,
                                                  VkDebugUtilsMessageTypeFlagsEXT,
                                                  const VkDebugUtilsMessengerCallbackDataEXT* data,
                                                  void* user) {
    auto* self = static_cast<Context*>(user);
    std::lock_guard lock(self->mMessageMutex);
    self->mMessages.emplace_back(data && data->pMessage ? data->pMessage : "(no text)");
    return VK_FALSE;
}

Result<std::unique_ptr<Context>> Context::create() {
    std::unique_ptr<Context> ctx(new Context());
    ctx->mValidation = envIs("MVR_VK_VALIDATION", "1");

    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.pApplicationName = "mvr";
    app.pEngineName = "mvr";
    app.apiVersion = VK_API_VERSION_1_2;
    std::vector<const char*> layers, extensions;
    // Any message of the validation layer, warnings and errors of every type (the layer's
    // info and verbose ones are its progress reports, not findings).
    VkDebugUtilsMessengerCreateInfoEXT dbg{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
    dbg.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                          VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
    dbg.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                      VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                      VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
    dbg.pfnUserCallback = &Context::onMessage;
    dbg.pUserData = ctx.get();
    VkInstanceCreateInfo ici{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    ici.pApplicationInfo = &app;
    if (ctx->mValidation) {
        layers.push_back("VK_LAYER_KHRONOS_validation");
        extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
        ici.pNext = &dbg;  // messages of vkCreateInstance / vkDestroyInstance too
    }
    ici.enabledLayerCount = std::uint32_t(layers.size());
    ici.ppEnabledLayerNames = layers.data();
    ici.enabledExtensionCount = std::uint32_t(extensions.size());
    ici.ppEnabledExtensionNames = extensions.data();
    if (VkResult r = vkCreateInstance(&ici, nullptr, &ctx->mInstance); r != VK_SUCCESS) {
        ctx->mInstance = VK_NULL_HANDLE;
        if (r == VK_ERROR_LAYER_NOT_PRESENT) {
            return unsupportedError(
                "vk: MVR_VK_VALIDATION=1 but VK_LAYER_KHRONOS_validation is not installed "
                "(Debian: vulkan-validationlayers)");
        }
        return unsupportedError(fmt::format("vk: no Vulkan instance: {}", resultName(r)));
    }
    if (ctx->mValidation) {
        auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
            vkGetInstanceProcAddr(ctx->mInstance, "vkCreateDebugUtilsMessengerEXT"));
        if (!create) return internalError("vk: vkCreateDebugUtilsMessengerEXT not found");
        if (Status s = check(create(ctx->mInstance, &dbg, nullptr, &ctx->mMessenger),
                             "vkCreateDebugUtilsMessengerEXT");
            !s)
            return s;
    }

    std::uint32_t n = 0;
    vkEnumeratePhysicalDevices(ctx->mInstance, &n, nullptr);
    std::vector<VkPhysicalDevice> devices(n);
    vkEnumeratePhysicalDevices(ctx->mInstance, &n, devices.data());
    if (n == 0) return unsupportedError("vk: no Vulkan device");
    std::vector<Candidate> candidates;
    for (VkPhysicalDevice d : devices) {
        candidates.push_back(inspect(d));
        if (candidates.back().why.empty() && !candidates.back().caps.multiview)
            candidates.back().why = candidates.back().caps.name + ": no multiview";
    }
    const Candidate* chosen = nullptr;
    if (const char* want = std::getenv("MVR_VK_DEVICE"); want && *want) {
        char* end = nullptr;
        const long i = std::strtol(want, &end, 10);
        if (*end != '\0' || i < 0 || i >= long(n)) {
            return usageError(fmt::format("vk: MVR_VK_DEVICE={} is not a device (0..{})", want,
                                          n - 1));
        }
        chosen = &candidates[std::size_t(i)];
        if (!chosen->why.empty()) return unsupportedError("vk: MVR_VK_DEVICE: " + chosen->why);
    } else {
        std::vector<std::string> why;
        for (const Candidate& c : candidates) {
            if (!c.why.empty()) {
                why.push_back(c.why);
                continue;
            }
            if (!chosen || typeRank(c.type) < typeRank(chosen->type)) chosen = &c;
        }
        if (!chosen) {
            return unsupportedError(
                fmt::format("vk: no usable device ({})", fmt::join(why, "; ")));
        }
    }
    ctx->mPhysical = chosen->device;
    ctx->mCaps = chosen->caps;
    vkGetPhysicalDeviceMemoryProperties(ctx->mPhysical, &ctx->mMemory);

    float priority = 1.0f;
    VkDeviceQueueCreateInfo q{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    q.queueFamilyIndex = chosen->queueFamily;
    q.queueCount = 1;
    q.pQueuePriorities = &priority;
    VkPhysicalDeviceVulkan12Features f12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
    f12.shaderOutputLayer = ctx->mCaps.shaderOutputLayer ? VK_TRUE : VK_FALSE;
    VkPhysicalDeviceVulkan11Features f11{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_1_FEATURES};
    f11.multiview = VK_TRUE;
    f11.pNext = &f12;
    VkPhysicalDeviceFeatures2 f{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
    f.features.fillModeNonSolid = ctx->mCaps.fillModeNonSolid ? VK_TRUE : VK_FALSE;
    f.pNext = &f11;
    VkDeviceCreateInfo dci{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    dci.pNext = &f;
    dci.queueCreateInfoCount = 1;
    dci.pQueueCreateInfos = &q;
    if (Status s = check(vkCreateDevice(ctx->mPhysical, &dci, nullptr, &ctx->mDevice),
                         "vkCreateDevice");
        !s) {
        ctx->mDevice = VK_NULL_HANDLE;
        return s;
    }
    vkGetDeviceQueue(ctx->mDevice, chosen->queueFamily, 0, &ctx->mQueue);
    VkCommandPoolCreateInfo pci{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pci.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pci.queueFamilyIndex = chosen->queueFamily;
    VkCommandPool pool = VK_NULL_HANDLE;
    if (Status s = check(vkCreateCommandPool(ctx->mDevice, &pci, nullptr, &pool),
                         "vkCreateCommandPool");
        !s)
        return s;
    ctx->mPool = CommandPool(ctx->mDevice, pool);

    // Staging memory the CPU reads: cached where the device has it.
    for (std::uint32_t i = 0; i < ctx->mMemory.memoryTypeCount; ++i) {
        const auto f2 = ctx->mMemory.memoryTypes[i].propertyFlags;
        if ((f2 & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT) && (f2 & VK_MEMORY_PROPERTY_HOST_CACHED_BIT))
            ctx->mCaps.hostCachedStaging = true;
    }
    if (Status s = ctx->checkMessages("creating the device"); !s) return s;
    return ctx;
}

Context::~Context() {
    if (mDevice) {
        vkDeviceWaitIdle(mDevice);
        mPool.reset();
        vkDestroyDevice(mDevice, nullptr);
    }
    if (mMessenger) {
        auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
            vkGetInstanceProcAddr(mInstance, "vkDestroyDebugUtilsMessengerEXT"));
        if (destroy) destroy(mInstance, mMessenger, nullptr);
    }
    if (mInstance) vkDestroyInstance(mInstance, nullptr);
    if (mValidation && !mMessages.empty()) {
        // A leak or a misuse found at teardown: the tests must fail, and there is no caller
        // left to return it to.
        for (const std::string& m : mMessages) std::fprintf(stderr, "vk validation: %s\n", m.c_str());
        std::abort();
    }
}

std::vector<std::string> Context::takeMessages() {
    std::lock_guard lock(mMessageMutex);
    return std::exchange(mMessages, {});
}

Status Context::checkMessages(const std::string& what) {
    const auto messages = takeMessages();
    if (messages.empty()) return {};
    return internalError(fmt::format("vk: validation while {}: {}", what,
                                     fmt::join(messages, " | ")));
}

Result<std::uint32_t> Context::memoryType(std::uint32_t bits, VkMemoryPropertyFlags want,
                                          VkMemoryPropertyFlags prefer) const {
    for (int pass = 0; pass < 2; ++pass) {
        const VkMemoryPropertyFlags flags = pass == 0 ? want | prefer : want;
        for (std::uint32_t i = 0; i < mMemory.memoryTypeCount; ++i) {
            if ((bits & (1u << i)) && (mMemory.memoryTypes[i].propertyFlags & flags) == flags)
                return i;
        }
    }
    return internalError("vk: no suitable memory type");
}

Result<BufferMemory> Context::makeBuffer(VkDeviceSize bytes, VkBufferUsageFlags usage,
                                         bool host) {
    BufferMemory b;
    VkBufferCreateInfo bci{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    bci.size = std::max<VkDeviceSize>(bytes, 16);
    bci.usage = usage;
    bci.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    VkBuffer buffer = VK_NULL_HANDLE;
    if (Status s = check(vkCreateBuffer(mDevice, &bci, nullptr, &buffer), "vkCreateBuffer"); !s)
        return s;
    b.buffer = Buffer(mDevice, buffer);
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(mDevice, buffer, &req);
    auto type = host ? memoryType(req.memoryTypeBits,
                                  VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT |
                                      VK_MEMORY_PROPERTY_HOST_COHERENT_BIT,
                                  VK_MEMORY_PROPERTY_HOST_CACHED_BIT)
                     : memoryType(req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    if (!type) return type.status();
    auto allocated = allocateMemory(mDevice, req.size, *type);
    if (!allocated) return allocated.status();
    const VkDeviceMemory memory = allocated->get();
    b.memory = std::move(*allocated);
    if (Status s = check(vkBindBufferMemory(mDevice, buffer, memory, 0), "vkBindBufferMemory"); !s)
        return s;
    if (host) {
        if (Status s = check(vkMapMemory(mDevice, memory, 0, VK_WHOLE_SIZE, 0, &b.mapped),
                             "vkMapMemory");
            !s)
            return s;
    }
    b.bytes = bytes;
    return b;
}

Result<ImageMemory> Context::makeImage(const VkImageCreateInfo& info) {
    ImageMemory im;
    VkImage image = VK_NULL_HANDLE;
    if (Status s = check(vkCreateImage(mDevice, &info, nullptr, &image), "vkCreateImage"); !s)
        return s;
    im.image = ImageHandle(mDevice, image);
    VkMemoryRequirements req;
    vkGetImageMemoryRequirements(mDevice, image, &req);
    auto type = memoryType(req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    if (!type) type = memoryType(req.memoryTypeBits, 0);
    if (!type) return type.status();
    auto allocated = allocateMemory(mDevice, req.size, *type);
    if (!allocated) return allocated.status();
    const VkDeviceMemory memory = allocated->get();
    im.memory = std::move(*allocated);
    if (Status s = check(vkBindImageMemory(mDevice, image, memory, 0), "vkBindImageMemory"); !s)
        return s;
    return im;
}

}  // namespace mvr::vk::detail
