#pragma once
// A Vulkan buffer with its own memory, reachable from shaders by device
// address (so no storage-buffer range limit applies: lavapipe caps bindings
// at 128 MiB). Host-visible buffers are mapped for their whole life.

#include "kerf/viewport/VulkanContext.hpp"

#include <cstddef>
#include <cstdint>
#include <utility>

namespace kerf::vk {

class GpuBuffer {
public:
    enum class Kind { DeviceLocal, HostVisible, Readback };

    GpuBuffer() = default;
    /// `bytes` may be 0 (a 16-byte buffer is made so that it has an address).
    GpuBuffer(const Context& ctx, std::size_t bytes, VkBufferUsageFlags usage, Kind kind, const char* name);
    /// A moved-from buffer is empty (size 0, no address), like a default one.
    GpuBuffer(GpuBuffer&& o) noexcept { *this = std::move(o); }
    GpuBuffer& operator=(GpuBuffer&& o) noexcept
    {
        if (this == &o) return *this;
        buffer_ = std::move(o.buffer_);
        memory_ = std::move(o.memory_);
        address_ = std::exchange(o.address_, 0);
        size_ = std::exchange(o.size_, 0);
        mapped_ = std::exchange(o.mapped_, nullptr);
        return *this;
    }

    VkBuffer buffer() const { return buffer_; }
    VkDeviceAddress address() const { return address_; }
    std::size_t size() const { return size_; }
    void* mapped() const { return mapped_; }

private:
    Buffer buffer_;
    Memory memory_;
    VkDeviceAddress address_ = 0;
    std::size_t size_ = 0;
    void* mapped_ = nullptr;
};

/// Uploads `bytes` into a new device-local buffer through a staging buffer.
GpuBuffer uploadBuffer(const Context& ctx, const void* data, std::size_t bytes, VkBufferUsageFlags usage,
                       const char* name);

} // namespace kerf::vk
