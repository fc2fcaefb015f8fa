#include "gpu/pipeline/huge_pages.h"

#include <cstdlib>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace uvr::gpu {

void* allocate_huge(std::size_t bytes)
{
    if (bytes == 0) bytes = 1;
    void* p = nullptr;
    if (bytes < kHugePageBytes) {
        p = std::malloc(bytes);
        if (!p) throw std::bad_alloc();
        return p;
    }
    // Rounded up to whole huge pages, so that the last one is not shared with other data.
    const std::size_t rounded = (bytes + kHugePageBytes - 1) / kHugePageBytes * kHugePageBytes;
    if (posix_memalign(&p, kHugePageBytes, rounded) != 0) throw std::bad_alloc();
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    // Advice only: where transparent huge pages are off ("never") the call fails or is ignored, and the memory stays
    // in small pages with the same contents.
    (void)madvise(p, rounded, MADV_HUGEPAGE);
#endif
    return p;
}

void release_huge(void* p) noexcept { std::free(p); }

}  // namespace uvr::gpu
