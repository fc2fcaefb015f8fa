// Eight rays of the march at once, one in each lane of AVX2 registers, as llvmpipe's JIT code runs eight fragments:
// raycast_march's operations lane by lane (the same IEEE and integer operations in the same order), so every ray gets
// raycast_march's bits. The volume's lookups (8-bit, 16-bit or float), the tables' lookups and the compositing run in
// the lanes; with the exact segment (--segment exact) each lane's segment is integrated on its own, with a light each
// lane's light factors are computed on their own (the gradient's lookups in the lanes). It takes every march on a host
// with AVX2 and FMA3; raycast_march does them elsewhere. docs/raycast.md, "The emulation's speed".
#pragma once

#include "gpu/raycast/raycast_fragment.h"

namespace uvr::gpu {

inline constexpr int kPacketRays = 8;

// Whether raycast_march_packet computes this frame's rays.
bool packet_march_applies(const RaycastFrameConstants& fc, const RaycastTextures& tex);

// rays[0 .. count) (count <= kPacketRays) marched together; out[i] is raycast_march(fc, rays[i], tex). The volume
// texture's storage holds kPacketGatherPadding bytes past its last texel (gpu/raycast/raycast_setup.h).
void raycast_march_packet(const RaycastFrameConstants& fc, const RaycastRay* rays, int count,
                          const RaycastTextures& tex, RaycastResult* out);

}  // namespace uvr::gpu
