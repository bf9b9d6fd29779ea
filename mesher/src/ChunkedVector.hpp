#pragma once
// A growable array stored in chunks: growing never copies, never holds two
// copies at once (a std::vector's doubling briefly needs three times its
// size), and the merge can free it chunk by chunk while it copies out.
// Chunks start small (a tile with a handful of triangles wastes little) and
// double up to 64 Ki elements; large ones come from the system
// (SystemAllocator.hpp), so that releasing them returns the memory at once.
// Not thread-safe; one owner.

#include "SystemAllocator.hpp"

#include <bit>
#include <cstddef>
#include <vector>

namespace kerf::mesher {

template <class T> class ChunkedVector {
public:
    static constexpr int kFirstBits = 8; // first chunk: 256 elements
    static constexpr int kLastBits = 16; // chunks stop growing at 65,536

    std::size_t size() const { return size_; }
    bool empty() const { return size_ == 0; }

    T& operator[](std::size_t i)
    {
        const auto [c, o] = locate(i);
        return chunks_[c][o];
    }
    const T& operator[](std::size_t i) const
    {
        const auto [c, o] = locate(i);
        return chunks_[c][o];
    }

    void push_back(const T& v)
    {
        const auto [c, o] = locate(size_);
        if (c == chunks_.size()) {
            chunks_.emplace_back();
            chunks_.back().reserve(chunkCapacity(c)); // written once, by push_back
        }
        chunks_[c].push_back(v);
        ++size_;
    }

    /// Chunk access for copying out: chunk c holds chunkLength(c) elements.
    std::size_t chunkCount() const { return chunks_.size(); }
    const T* chunk(std::size_t c) const { return chunks_[c].data(); }
    std::size_t chunkLength(std::size_t c) const
    {
        const std::size_t first = chunkStart(c);
        return size_ - first < chunkCapacity(c) ? size_ - first : chunkCapacity(c);
    }
    /// Frees one chunk's memory (its elements become unusable).
    void releaseChunk(std::size_t c) { Chunk().swap(chunks_[c]); }
    void clear()
    {
        chunks_.clear();
        chunks_.shrink_to_fit();
        size_ = 0;
    }
    std::size_t bytes() const
    {
        std::size_t b = chunks_.capacity() * sizeof(chunks_[0]);
        for (std::size_t c = 0; c < chunks_.size(); ++c)
            b += chunkCapacity(c) * sizeof(T);
        return b;
    }

private:
    static constexpr std::size_t kGrowing = kLastBits - kFirstBits; // chunks 0 .. kGrowing - 1 double
    static std::size_t chunkCapacity(std::size_t c)
    {
        return std::size_t(1) << (c < kGrowing ? kFirstBits + c : kLastBits);
    }
    static std::size_t chunkStart(std::size_t c)
    {
        // Chunks before c: 256 (2^c - 1) while growing, then 65,536 each.
        if (c <= kGrowing) return (std::size_t(1) << kFirstBits) * ((std::size_t(1) << c) - 1);
        return chunkStart(kGrowing) + (c - kGrowing) * (std::size_t(1) << kLastBits);
    }
    static std::pair<std::size_t, std::size_t> locate(std::size_t i)
    {
        const std::size_t growingEnd = chunkStart(kGrowing);
        if (i < growingEnd) {
            const std::size_t c = std::size_t(std::bit_width((i >> kFirstBits) + 1)) - 1;
            return {c, i - chunkStart(c)};
        }
        const std::size_t j = i - growingEnd;
        return {kGrowing + (j >> kLastBits), j & ((std::size_t(1) << kLastBits) - 1)};
    }

    using Chunk = std::vector<T, SystemAllocator<T>>;
    std::vector<Chunk> chunks_;
    std::size_t size_ = 0;
};

} // namespace kerf::mesher
