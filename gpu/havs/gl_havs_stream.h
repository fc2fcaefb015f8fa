// The geometry pass as the GL drivers of HAVS submit it (gpu/havs/gl_havs.cpp, gpu/havs/gl_havs_arb.cpp): fs.draw in
// draws of `chunk` triangles; of each draw, the triangles havs_sent_triangles keeps, built and uploaded just before
// the draw, at most kDrawsInFlight draws unfinished (GlDrawThrottle). GL keeps primitive order across draws, so every
// pixel sees its fragments in the sorted order. Twins: none (GL side only; the emulated driver rasterizes fs.draw
// itself).
#pragma once

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <vector>

#include "gpu/gl/gl_draw_throttle.h"
#include "gpu/havs/havs.h"
#include "reference/timing.h"

namespace uvr::gpu {

// Geometry draws llvmpipe may hold unfinished: two keep its rasterizer threads fed while the next draw's data is
// built.
inline constexpr std::size_t kDrawsInFlight = 2;

// The loop: per draw, `upload(sent)` builds and uploads the data of the draw ids `sent`, `draw(sent.size())` issues
// the draw call. Adds to st: setup_ms (choosing and uploading), raster_fragment_ms (the draws and the throttle's
// waits), draws and uncovered.
template <class Upload, class Draw>
void draw_havs_chunks(const GlContext& ctx, const HavsMesh& hm, const HavsFrameSetup& fs, std::size_t chunk,
                      TriangleSubmission submission, HavsStats& st, Upload&& upload, Draw&& draw)
{
    const std::size_t ntris = fs.draw.size();
    std::vector<uint32_t> sent;  // a draw's triangles as sent
    GlDrawThrottle throttle(ctx, kDrawsInFlight);
    for (std::size_t c0 = 0; c0 < ntris; c0 += chunk) {
        auto t0 = Clock::now();
        const std::size_t count = std::min(chunk, ntris - c0);
        havs_sent_triangles(hm, fs, c0, count, submission, sent);
        st.uncovered += count - sent.size();
        upload(sent);
        st.setup_ms += ms_since(t0);
        t0 = Clock::now();
        draw(sent.size());
        throttle.drawn();
        st.raster_fragment_ms += ms_since(t0);
        ++st.draws;
    }
}

// The paper's vertices: each sent triangle as three unshared vertices, `make(id, v, out)` writing draw id `id`'s
// (frame vertices v[0..2]) to out[0..2] in parallel, uploaded with glBufferData to the bound GL_ARRAY_BUFFER and drawn
// with glDrawArrays; `after_draw()` runs after each draw call.
template <class Vertex, class Make, class AfterDraw>
void draw_havs_stream(const GlContext& ctx, const HavsMesh& hm, const HavsFrameSetup& fs, std::size_t chunk,
                      TriangleSubmission submission, HavsStats& st, Make&& make, AfterDraw&& after_draw)
{
    const GlFunctions& gl = ctx.gl();
    std::vector<Vertex> stream(3 * std::min(chunk, fs.draw.size()));
    draw_havs_chunks(
        ctx, hm, fs, chunk, submission, st,
        [&](const std::vector<uint32_t>& sent) {
            for_each_triangle(hm, fs, sent.data(), sent.size(),
                              [&](std::size_t i, const uint32_t* v) { make(sent[i], v, &stream[3 * i]); });
            gl.BufferData(GL_ARRAY_BUFFER, GLsizeiptr(3 * sent.size() * sizeof(Vertex)), stream.data(),
                          GL_STREAM_DRAW);
        },
        [&](std::size_t n) {
            gl.DrawArrays(GL_TRIANGLES, 0, GLsizei(3 * n));
            after_draw();
        });
}

}  // namespace uvr::gpu
