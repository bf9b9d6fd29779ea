#pragma once
// Open-addressing hash tables keyed by 64-bit integers: linear probing,
// power-of-two capacity, at most 70% full, no erase. The mesher keeps one
// per surface tile for its cells and edges, so compactness matters: 8 bytes
// of key plus the value per slot, against about 40 for std::unordered_map.
// Keys must not be ~0 (the empty slot). Large tables come from the system
// (SystemAllocator.hpp) so that freeing them returns the memory. Not
// thread-safe; one owner.

#include "SystemAllocator.hpp"

#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

namespace kerf::mesher {

inline constexpr std::uint64_t kEmptyKey = ~std::uint64_t(0);

inline std::uint64_t mixKey(std::uint64_t x)
{
    // splitmix64's finalizer: lattice keys are structured bit fields.
    x ^= x >> 30;
    x *= 0xbf58476d1ce4e5b9ull;
    x ^= x >> 27;
    x *= 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}

/// The default hash: keys spread uniformly over the table.
struct MixHash {
    std::uint64_t operator()(std::uint64_t key) const { return mixKey(key); }
};

template <class Value, class Hash = MixHash> class FlatMap {
public:
    /// The value for `key`, inserting `value` if absent; second: inserted.
    /// The pointer is valid until the next insertion.
    std::pair<Value*, bool> insert(std::uint64_t key, const Value& value)
    {
        if ((size_ + 1) * 10 > keys_.size() * 7) grow();
        std::size_t i = Hash{}(key)&mask_;
        while (keys_[i] != kEmptyKey) {
            if (keys_[i] == key) return {&values_[i], false};
            i = (i + 1) & mask_;
        }
        keys_[i] = key;
        values_[i] = value;
        ++size_;
        return {&values_[i], true};
    }

    const Value* find(std::uint64_t key) const
    {
        if (keys_.empty()) return nullptr;
        std::size_t i = Hash{}(key)&mask_;
        while (keys_[i] != kEmptyKey) {
            if (keys_[i] == key) return &values_[i];
            i = (i + 1) & mask_;
        }
        return nullptr;
    }
    Value* find(std::uint64_t key) { return const_cast<Value*>(std::as_const(*this).find(key)); }

    /// Makes room for `n` keys without growing again.
    void reserve(std::size_t n)
    {
        while (n * 10 > keys_.size() * 7)
            grow();
    }

    std::size_t size() const { return size_; }
    std::size_t bytes() const { return keys_.capacity() * sizeof(std::uint64_t) + values_.capacity() * sizeof(Value); }
    /// Empties the table, keeping its memory for reuse unless it is much
    /// larger than what it held (clearing costs its capacity).
    void clear()
    {
        if (size_ == 0) return;
        if (keys_.size() > 4096 && size_ * 8 < keys_.size()) return release();
        std::fill(keys_.begin(), keys_.end(), kEmptyKey);
        size_ = 0;
    }
    /// Empties the table and frees its memory.
    void release()
    {
        decltype(keys_)().swap(keys_);
        decltype(values_)().swap(values_);
        size_ = 0;
        mask_ = 0;
    }

    template <class F> void forEach(F&& f) const
    {
        for (std::size_t i = 0; i < keys_.size(); ++i)
            if (keys_[i] != kEmptyKey) f(keys_[i], values_[i]);
    }

private:
    void grow()
    {
        const std::size_t capacity = keys_.empty() ? 64 : keys_.size() * 2;
        std::vector<std::uint64_t, SystemAllocator<std::uint64_t>> keys(capacity, kEmptyKey);
        std::vector<Value, SystemAllocator<Value>> values(capacity);
        const std::size_t mask = capacity - 1;
        for (std::size_t j = 0; j < keys_.size(); ++j) {
            if (keys_[j] == kEmptyKey) continue;
            std::size_t i = Hash{}(keys_[j]) & mask;
            while (keys[i] != kEmptyKey)
                i = (i + 1) & mask;
            keys[i] = keys_[j];
            values[i] = values_[j];
        }
        keys_.swap(keys);
        values_.swap(values);
        mask_ = mask;
    }

    std::vector<std::uint64_t, SystemAllocator<std::uint64_t>> keys_;
    std::vector<Value, SystemAllocator<Value>> values_;
    std::size_t size_ = 0;
    std::size_t mask_ = 0;
};

} // namespace kerf::mesher
