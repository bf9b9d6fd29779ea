#include "kerf/viewport/HeapAllocator.hpp"

#include <stdexcept>

namespace kerf::vk {

HeapAllocator::HeapAllocator(std::size_t capacity, std::size_t alignment)
    : capacity_(capacity / alignment * alignment), alignment_(alignment)
{
    if (alignment == 0) throw std::invalid_argument("HeapAllocator: alignment 0");
    if (capacity_ > 0) free_[0] = capacity_;
}

std::optional<std::size_t> HeapAllocator::allocate(std::size_t bytes)
{
    const std::size_t need = rounded(bytes == 0 ? 1 : bytes);
    for (auto it = free_.begin(); it != free_.end(); ++it) {
        if (it->second < need) continue;
        const std::size_t offset = it->first, size = it->second;
        free_.erase(it);
        if (size > need) free_[offset + need] = size - need;
        used_ += need;
        return offset;
    }
    return std::nullopt;
}

void HeapAllocator::release(std::size_t offset, std::size_t bytes)
{
    const std::size_t size = rounded(bytes == 0 ? 1 : bytes);
    if (offset % alignment_ || offset + size > capacity_) throw std::logic_error("HeapAllocator: bad release");
    // The range must not overlap a free one (a double or wrong release).
    auto after = free_.lower_bound(offset);
    if (after != free_.end() && after->first < offset + size) throw std::logic_error("HeapAllocator: double release");
    if (after != free_.begin() && std::prev(after)->first + std::prev(after)->second > offset)
        throw std::logic_error("HeapAllocator: double release");
    auto [it, inserted] = free_.emplace(offset, size);
    if (!inserted) throw std::logic_error("HeapAllocator: double release");
    used_ -= size;
    // Merge with the following range, then with the preceding one.
    auto next = std::next(it);
    if (next != free_.end() && it->first + it->second == next->first) {
        it->second += next->second;
        free_.erase(next);
    }
    if (it != free_.begin()) {
        auto prev = std::prev(it);
        if (prev->first + prev->second == it->first) {
            prev->second += it->second;
            free_.erase(it);
        }
    }
}

std::size_t HeapAllocator::largestFree() const
{
    std::size_t best = 0;
    for (const auto& [offset, size] : free_) best = std::max(best, size);
    return best;
}

} // namespace kerf::vk
