#include "gpu/raycast/raycast.h"

#include <algorithm>
#include <chrono>
#include <cstring>

#include <tbb/parallel_for.h>

#include "gpu/pipeline/denormals.h"
#include "gpu/pipeline/rasterize.h"
#include "gpu/raycast/raycast_packet.h"
#include "reference/timing.h"

namespace uvr::gpu {

void store_raycast_frame(const std::vector<glm::vec4>& colour, const std::vector<uint32_t>& samples, int width,
                         int height, RaycastFrame& out)
{
    out.image = Image(width, height);
    out.samples.resize(std::size_t(width) * std::size_t(height));
    RaycastStats& st = out.stats;
    for_each_gl_pixel(width, height, [&](std::size_t p, std::size_t q) {
        std::memcpy(&out.image.rgba[4 * q], &colour[p][0], 4 * sizeof(float));
        out.samples[q] = samples[p];
        st.samples += samples[p];
        st.rays += samples[p] ? 1 : 0;
        st.max_samples = std::max(st.max_samples, samples[p]);
    });
}

RaycastRenderer::RaycastRenderer(const Volume& volume, const TransferFunction& tf, const RaycastOptions& options)
    : volume_(volume, tf, options)
{
}

void count_raycast_box(const RaycastBoxFrame& bf, RaycastStats& st)
{
    st.box_triangles = bf.triangles();
    st.near_sections = bf.near_sections;
    st.clipped_faces = bf.clipped_faces;
    st.gpu_clipped = bf.gpu_clipped;
}

RaycastFrame RaycastRenderer::render(const Camera& cam, int width, int height) const
{
    RaycastFrame out;
    auto t0 = Clock::now();
    const RaycastFrameConstants fc = raycast_frame_constants(volume_, cam, width, height);
    const RaycastTextures tex = raycast_textures(volume_);
    const bool published = volume_.options().interpolation == InterpolationMode::gpu;
    // The published first two passes: each pixel's entry and exit as the box's faces interpolate them.
    RaycastBoxPass front, back;
    if (published) {
        const RaycastBoxFrame bf = raycast_box_frame(fc, cam, volume_.origin(), width, height);
        front = raycast_box_pass(bf, Facing::front);
        back = raycast_box_pass(bf, Facing::back);
        count_raycast_box(bf, out.stats);
    }
    const double setup_ms = ms_since(t0);

    // The march: on the pixels the box's front covers (the published third pass draws the box again), or on every pixel
    // of one full-screen pass (--interpolation exact). GL rows, from the bottom.
    const std::size_t npix = std::size_t(width) * std::size_t(height);
    std::vector<glm::vec4> colour(npix, glm::vec4(0.0f));
    std::vector<uint32_t> samples(npix, 0);
    t0 = Clock::now();
    const bool packets = packet_march_applies(fc, tex);
    tbb::parallel_for(0, height, [&](int py) {
        const FlushDenormals llvmpipe_mxcsr;  // as llvmpipe's shader threads (gpu/pipeline/denormals.h)
        // The row's rays, marched one at a time or kPacketRays together (the same bits).
        RaycastRay rays[kPacketRays];
        std::size_t pixel[kPacketRays];
        int count = 0;
        const auto flush = [&] {
            RaycastResult r[kPacketRays];
            if (packets) {
                raycast_march_packet(fc, rays, count, tex, r);
            } else {
                for (int i = 0; i < count; ++i) r[i] = raycast_march(fc, rays[i], tex);
            }
            for (int i = 0; i < count; ++i) {
                colour[pixel[i]] = r[i].colour;
                samples[pixel[i]] = r[i].samples;
            }
            count = 0;
        };
        for (int px = 0; px < width; ++px) {
            const std::size_t p = std::size_t(py) * std::size_t(width) + std::size_t(px);
            if (published && front.position[p].w == 0.0f) continue;
            rays[count] =
                published ? raycast_ray_published(fc, front.position[p], back.position[p]) : raycast_ray(fc, px, py);
            pixel[count] = p;
            if (++count == kPacketRays) flush();
        }
        flush();
    });
    const double march_ms = ms_since(t0);
    store_raycast_frame(colour, samples, width, height, out);
    if (published) {
        out.stats.entries = front.covered;
        out.stats.overlaps = front.overlaps + back.overlaps;
        for (std::size_t p = 0; p < npix; ++p)
            if (front.position[p].w != 0.0f && back.position[p].w == 0.0f) ++out.stats.unpaired;
    }
    out.stats.table_ms = volume_.table_ms();
    out.stats.setup_ms = setup_ms;
    out.stats.march_ms = march_ms;
    return out;
}

}  // namespace uvr::gpu
