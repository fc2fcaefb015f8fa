// Bounds how far the submitting thread runs ahead of the GPU: a fence after each draw, and before a new draw a wait for
// the fence `depth` draws back. llvmpipe rasterizes a draw's triangles later, on its own threads, from scenes that hold
// each triangle's setup (its planes, per input) until they are rasterized, and the submitting thread may queue many
// scenes: without a bound, what a 10 M-tetrahedron HAVS frame keeps in flight doubled its memory peak
// (docs/results.md, "Memory with the published interpolation"). Changes no bit: GL keeps the draws' order.
// Twins: none (GL side only). Used by gpu/havs/gl_havs.cpp and gpu/havs/gl_havs_arb.cpp.
#pragma once

#include <deque>

#include "gpu/gl/gl_context.h"

namespace uvr::gpu {

class GlDrawThrottle {
public:
    GlDrawThrottle(const GlContext& ctx, std::size_t depth) : gl_(ctx.gl()), depth_(depth) {}
    ~GlDrawThrottle()
    {
        for (GLsync s : fences_) gl_.DeleteSync(s);
    }
    GlDrawThrottle(const GlDrawThrottle&) = delete;
    GlDrawThrottle& operator=(const GlDrawThrottle&) = delete;

    // Call after each draw: fences it, and waits until at most `depth` fenced draws are unfinished.
    void drawn()
    {
        fences_.push_back(gl_.FenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0));
        while (fences_.size() > depth_) {
            // Flushes the queued commands, then waits without a time limit (a draw always finishes).
            while (gl_.ClientWaitSync(fences_.front(), GL_SYNC_FLUSH_COMMANDS_BIT, 1000000000ull) == GL_TIMEOUT_EXPIRED) {
            }
            gl_.DeleteSync(fences_.front());
            fences_.pop_front();
        }
    }

private:
    const GlFunctions& gl_;
    std::size_t depth_;
    std::deque<GLsync> fences_;
};

}  // namespace uvr::gpu
