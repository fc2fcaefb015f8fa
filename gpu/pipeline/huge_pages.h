// Memory for the emulated GPU's large per-frame arrays (the pre-integration table, the k-buffer, the framebuffer):
// blocks of 2 MiB or more are aligned to 2 MiB and offered to Linux's transparent huge pages (madvise), so that the
// table's scattered trilinear reads do not miss the TLB on every sample (docs/gl-backend.md, "Speed"). Placement
// only: the values, and so every bit the emulation computes, are the same as with std::allocator.
#pragma once

#include <cstddef>
#include <new>
#include <vector>

namespace uvr::gpu {

// Allocates `bytes` (2 MiB-aligned and advised for huge pages from kHugePageBytes up); free with release_huge().
void* allocate_huge(std::size_t bytes);
void release_huge(void* p) noexcept;

// A huge page on x86-64 Linux: the granule MADV_HUGEPAGE works in.
inline constexpr std::size_t kHugePageBytes = std::size_t(2) << 20;

template <class T>
struct HugePageAllocator {
    using value_type = T;
    HugePageAllocator() = default;
    template <class U>
    HugePageAllocator(const HugePageAllocator<U>&) noexcept
    {
    }
    T* allocate(std::size_t n)
    {
        if (n > std::size_t(-1) / sizeof(T)) throw std::bad_array_new_length();
        return static_cast<T*>(allocate_huge(n * sizeof(T)));
    }
    void deallocate(T* p, std::size_t) noexcept { release_huge(p); }
    template <class U>
    bool operator==(const HugePageAllocator<U>&) const noexcept
    {
        return true;
    }
};

template <class T>
using HugeVector = std::vector<T, HugePageAllocator<T>>;

}  // namespace uvr::gpu
