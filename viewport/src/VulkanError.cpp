#include "kerf/viewport/VulkanError.hpp"

namespace kerf::vk {

const char* resultName(VkResult r)
{
    switch (r) {
#define KERF_CASE(x)                                                                                                   \
    case x: return #x;
        KERF_CASE(VK_SUCCESS)
        KERF_CASE(VK_NOT_READY)
        KERF_CASE(VK_TIMEOUT)
        KERF_CASE(VK_INCOMPLETE)
        KERF_CASE(VK_ERROR_OUT_OF_HOST_MEMORY)
        KERF_CASE(VK_ERROR_OUT_OF_DEVICE_MEMORY)
        KERF_CASE(VK_ERROR_INITIALIZATION_FAILED)
        KERF_CASE(VK_ERROR_DEVICE_LOST)
        KERF_CASE(VK_ERROR_MEMORY_MAP_FAILED)
        KERF_CASE(VK_ERROR_LAYER_NOT_PRESENT)
        KERF_CASE(VK_ERROR_EXTENSION_NOT_PRESENT)
        KERF_CASE(VK_ERROR_FEATURE_NOT_PRESENT)
        KERF_CASE(VK_ERROR_INCOMPATIBLE_DRIVER)
        KERF_CASE(VK_ERROR_TOO_MANY_OBJECTS)
        KERF_CASE(VK_ERROR_FORMAT_NOT_SUPPORTED)
        KERF_CASE(VK_ERROR_FRAGMENTED_POOL)
        KERF_CASE(VK_ERROR_OUT_OF_POOL_MEMORY)
        KERF_CASE(VK_ERROR_INVALID_EXTERNAL_HANDLE)
        KERF_CASE(VK_ERROR_SURFACE_LOST_KHR)
        KERF_CASE(VK_ERROR_OUT_OF_DATE_KHR)
        KERF_CASE(VK_SUBOPTIMAL_KHR)
#undef KERF_CASE
    default: return "VkResult (unknown)";
    }
}

} // namespace kerf::vk
