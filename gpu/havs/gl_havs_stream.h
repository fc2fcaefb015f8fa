// The geometry pass as both GL drivers of HAVS send the seed's vertices (gpu/havs/gl_havs.cpp with --interpolation
// gpu, gpu/havs/gl_havs_arb.cpp): fs.draw in draws of `chunk` triangles; of each draw, the triangles
// havs_sent_triangles keeps, each as three unshared vertices, uploaded with glBufferData to the bound GL_ARRAY_BUFFER and
// drawn with glDrawArrays in order, at most `in_flight` draws unfinished (GlDrawThrottle). GL keeps primitive order
// across draws, so every pixel sees its fragments in the sorted order. Twins: none (GL side only; the emulated driver
// rasterizes fs.draw itself).
#pragma once

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <vector>

#include "gpu/gl/gl_draw_throttle.h"
#include "gpu/havs/havs.h"

namespace uvr::gpu {

// `make(id, v, out)` writes draw id `id`'s three vertices (frame vertices v[0..2]) to out[0..2], in parallel;
// `after_draw()` runs after each draw call. Adds to st: setup_ms (building and uploading), raster_fragment_ms (the
// draws and the throttle's waits), draws and uncovered.
template <class Vertex, class Make, class AfterDraw>
void draw_havs_stream(const GlContext& ctx, const HavsMesh& hm, const HavsFrameSetup& fs, std::size_t chunk,
                      TriangleSubmission submission, std::size_t in_flight, HavsStats& st, Make&& make,
                      AfterDraw&& after_draw)
{
    using Clock = std::chrono::steady_clock;
    const auto ms_since = [](Clock::time_point t0) {
        return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    };
    const GlFunctions& gl = ctx.gl();
    const std::size_t ntris = fs.draw.size();
    std::vector<Vertex> stream(3 * std::min(chunk, ntris));
    std::vector<uint32_t> sent;  // a draw's triangles as sent
    GlDrawThrottle throttle(ctx, in_flight);
    for (std::size_t c0 = 0; c0 < ntris; c0 += chunk) {
        auto t0 = Clock::now();
        const std::size_t count = std::min(chunk, ntris - c0);
        havs_sent_triangles(hm, fs, c0, count, submission, sent);
        const std::size_t n = sent.size();
        st.uncovered += count - n;
        for_each_triangle(hm, fs, sent.data(), n,
                          [&](std::size_t i, const uint32_t* v) { make(sent[i], v, &stream[3 * i]); });
        gl.BufferData(GL_ARRAY_BUFFER, GLsizeiptr(3 * n * sizeof(Vertex)), stream.data(), GL_STREAM_DRAW);
        st.setup_ms += ms_since(t0);
        t0 = Clock::now();
        gl.DrawArrays(GL_TRIANGLES, 0, GLsizei(3 * n));
        after_draw();
        throttle.drawn();
        st.raster_fragment_ms += ms_since(t0);
        ++st.draws;
    }
}

}  // namespace uvr::gpu
