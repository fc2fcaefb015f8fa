// Frame-level comparison of a GL driver's frame with the emulated driver's (docs/spec.md §5), shared by the HAVS and
// VICP frame tests: the OSMesa context they render with, and the pixel-by-pixel bit comparison.
#pragma once

#include <cstdint>
#include <cstring>
#include <sstream>
#include <string>

#include "gpu/gl/gl_context.h"
#include "reference/image.h"

namespace uvr::test {

// One GL context for the whole program (creating one costs ~50 ms; they are independent of the scene).
inline gpu::GlContext& osmesa()
{
    // Never destroyed, as gl_harness.h's contexts: Mesa's exit handlers may run before a static's destructor.
    static gpu::GlContext* const ctx = new gpu::GlContext(gpu::GlPlatform::osmesa);
    ctx->make_current();
    return *ctx;
}

// GL's own count of the primitives the draws of `draw()` submitted (GL_PRIMITIVES_SUBMITTED, a pipeline-statistics
// query): what a driver sent, counted by the GL rather than by uvr. Needs GL_ARB_pipeline_statistics_query.
template <class Draw>
uint64_t primitives_submitted(gpu::GlContext& ctx, Draw&& draw)
{
    ctx.make_current();
    const gpu::GlFunctions& gl = ctx.gl();
    GLuint query = 0;
    gl.GenQueries(1, &query);
    gl.BeginQuery(GL_PRIMITIVES_SUBMITTED_ARB, query);
    draw();
    ctx.make_current();
    gl.EndQuery(GL_PRIMITIVES_SUBMITTED_ARB);
    GLuint64 n = 0;
    gl.GetQueryObjectui64v(query, GL_QUERY_RESULT, &n);
    gl.DeleteQueries(1, &query);
    ctx.check_error("the primitives-submitted query");
    return n;
}

struct FrameDiff {
    std::size_t pixels = 0, differing = 0, coverage_differs = 0, diagnostics_differ = 0;
    std::string first;  // the first differing pixel, for INFO
};

// `gl` against `emu` bit for bit. diagnostics_differ(p) says whether pixel p's diagnostics differ (the image's row
// order (row 0 on top)); describe(p) says what to add about pixel p to the first difference's description.
template <class Differ, class Describe>
FrameDiff diff_frames(const Image& gl, const Image& emu, Differ&& diagnostics_differ, Describe&& describe)
{
    FrameDiff d;
    d.pixels = std::size_t(gl.width) * std::size_t(gl.height);
    for (int y = 0; y < gl.height; ++y)
        for (int x = 0; x < gl.width; ++x) {
            const std::size_t p = std::size_t(y) * std::size_t(gl.width) + std::size_t(x);
            const float* pa = &gl.rgba[4 * p];
            const float* pb = &emu.rgba[4 * p];
            if (std::memcmp(pa, pb, 4 * sizeof(float)) != 0 && d.differing++ == 0) {
                std::ostringstream s;
                s.precision(9);
                s << "pixel (" << x << ", " << y << "): GL " << pa[0] << " " << pa[1] << " " << pa[2] << " " << pa[3]
                  << ", emulation " << pb[0] << " " << pb[1] << " " << pb[2] << " " << pb[3] << describe(p);
                d.first = s.str();
            }
            if ((pa[3] > 0.0f) != (pb[3] > 0.0f)) ++d.coverage_differs;
            if (diagnostics_differ(p)) ++d.diagnostics_differ;
        }
    return d;
}

}  // namespace uvr::test
