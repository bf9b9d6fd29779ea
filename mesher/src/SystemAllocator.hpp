#pragma once
// An allocator that takes large blocks straight from the system (mmap) and
// gives them straight back (munmap). The mesher frees a tile's tables and
// chunks while it assembles the mesh; through malloc, freed blocks stay in the
// process (glibc raises its mmap threshold after the first large free, then
// serves large blocks from its heap), so the tiles' share and the mesh would
// both count against the peak; and malloc_trim, which would return them,
// costs about a second per 400 MB on a virtual machine (measured). Small
// blocks still come from operator new. Thread-safe (as mmap and new are).

#include <cstddef>
#include <new>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace kerf::mesher {

inline constexpr std::size_t kSystemBlock = std::size_t(256) << 10;

inline void* systemAllocate(std::size_t bytes)
{
#if defined(__linux__)
    if (bytes >= kSystemBlock) {
        void* p = ::mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
        if (p == MAP_FAILED) throw std::bad_alloc();
        return p;
    }
#endif
    return ::operator new(bytes);
}

inline void systemFree(void* p, std::size_t bytes)
{
#if defined(__linux__)
    if (bytes >= kSystemBlock) {
        ::munmap(p, bytes);
        return;
    }
#endif
    ::operator delete(p, bytes);
}

template <class T> struct SystemAllocator {
    using value_type = T;
    SystemAllocator() = default;
    template <class U> SystemAllocator(const SystemAllocator<U>&) {}
    T* allocate(std::size_t n) { return static_cast<T*>(systemAllocate(n * sizeof(T))); }
    void deallocate(T* p, std::size_t n) { systemFree(p, n * sizeof(T)); }
    template <class U> bool operator==(const SystemAllocator<U>&) const { return true; }
};

} // namespace kerf::mesher
