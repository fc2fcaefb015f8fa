// The published fragment program and its compositing with the pre-integrated table, for up to eight fragments of one
// front face at once in AVX2 lanes: vicp_published_varyings_at, vicp_published_exit and vicp_composite with a
// TableSegmentShader, each lane the same IEEE operations in the same order as those scalar stages, so the same bits
// (tests/test_vicp.cpp compares the two paths). llvmpipe runs the fragment program eight pixels at a time too.
// Derivation: docs/vicp.md, "The emulation's speed".
#pragma once

#include <cstdint>

#include <glm/vec4.hpp>

#include "gpu/pipeline/segment.h"
#include "gpu/vicp/vicp_fragment.h"
#include "gpu/vicp/vicp_published_fragment.h"

namespace uvr::gpu {

// Whether this host runs the lanes: AVX2 and FMA3, and the fused viewport arithmetic (the scalar stages' FMA3 path).
bool vicp_published_lanes_available(ViewportArithmetic arith);

// Up to kLanes fragments of one triangle (distinct pixels), in the order the rasterizer gave them.
struct FragmentBatch {
    static constexpr int kLanes = 8;
    alignas(32) int32_t px[kLanes] = {}, py[kLanes] = {};
    int n = 0;
};

// Composites the batch's fragments into fb (width pixels a row), as vicp_composite(fc, segment, fb[p], shade, nullptr)
// does each, the segment from vicp_published_exit(vicp_published_varyings_at(planes, px, py, arith)) under fused
// arithmetic and `shade` the table's TableSegmentShader. Only where vicp_published_lanes_available().
void composite_published_lanes(const VicpPublishedPlanes& planes, const VicpFrameConstants& fc,
                               const TableSegmentShader& shade, const FragmentBatch& batch, int width, glm::vec4* fb);

}  // namespace uvr::gpu
