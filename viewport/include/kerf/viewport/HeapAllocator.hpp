#pragma once
// First-fit allocation of byte ranges inside one large GPU buffer (the tile
// heap). Free ranges are kept sorted and merged with their neighbours.
// Pure bookkeeping: no Vulkan, testable alone. Not thread-safe.

#include <cstddef>
#include <map>
#include <optional>

namespace kerf::vk {

class HeapAllocator {
public:
    explicit HeapAllocator(std::size_t capacity = 0, std::size_t alignment = 24);

    /// Offset of a new range of `bytes` (rounded up to the alignment), or
    /// nothing when no free range is large enough.
    std::optional<std::size_t> allocate(std::size_t bytes);
    /// Returns a range obtained from allocate() with the same size.
    void release(std::size_t offset, std::size_t bytes);

    std::size_t capacity() const { return capacity_; }
    std::size_t used() const { return used_; }
    std::size_t alignment() const { return alignment_; }
    std::size_t largestFree() const;

private:
    std::size_t rounded(std::size_t bytes) const { return (bytes + alignment_ - 1) / alignment_ * alignment_; }

    std::size_t capacity_, alignment_, used_ = 0;
    std::map<std::size_t, std::size_t> free_; // offset -> size
};

} // namespace kerf::vk
