// The paper's fragment entries of one row span of a triangle (--interpolation gpu, coverage gpu): havs_paper_entry of
// havs_varyings_at at every pixel of the span, the same bits, eight pixels at a time on an AVX2 + FMA3 host.
// tests/test_havs_paper_span.cpp compares the two paths bit for bit.
#pragma once

#include "gpu/havs/havs_fragment.h"

namespace uvr::gpu {

// How a span is computed: the fastest path the host has, or pixel by pixel (the definition the fast path is tested
// against).
enum class SpanPath { fastest, per_pixel };

// out[i] is the entry of setup-space pixel (first + i, py), for first <= first + i <= last. A span is at most a tile
// wide in the drivers, but any length works.
void havs_paper_entries(const HavsFrameConstants& fc, const HavsVaryingPlanes& planes, int py, int first, int last,
                        ViewportArithmetic arith, KEntry* out, SpanPath path = SpanPath::fastest);

}  // namespace uvr::gpu
