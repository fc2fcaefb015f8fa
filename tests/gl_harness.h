// One GL context and one stage harness per platform for the whole test program, shared by the stage tests
// (test_havs_gl_stage, test_vicp_gl_stage, test_raycast_gl_stage). Creating a context compiles nothing, but
// llvmpipe's first shaders are slow to build: the harness keeps its programs. A platform without a context fails the
// test that asks for it, with the reason.
#pragma once

#include <exception>
#include <memory>

#include <catch2/catch.hpp>

#include "gpu/gl/gl_context.h"

namespace uvr::test {

template <typename Harness>
struct GlHarness {
    std::unique_ptr<gpu::GlContext> ctx;
    std::unique_ptr<Harness> harness;
};

template <typename Harness>
GlHarness<Harness>& gl_harness(gpu::GlPlatform p)
{
    // Never destroyed: Mesa registers exit handlers of its own (its work queues' teardown) when the first context is
    // made, after these statics came to be, so at exit they run first, and a harness destroyed after them made its
    // context current on a torn-down library (a crash after the last test, in OSMesaMakeCurrent). The process's exit
    // frees both.
    static GlHarness<Harness>* const osmesa = new GlHarness<Harness>();
    static GlHarness<Harness>* const egl = new GlHarness<Harness>();
    GlHarness<Harness>& g = p == gpu::GlPlatform::osmesa ? *osmesa : *egl;
    if (!g.ctx) {
        try {
            g.ctx = std::make_unique<gpu::GlContext>(p);
            g.harness = std::make_unique<Harness>(*g.ctx);
        } catch (const std::exception& e) {
            FAIL("no GL context (" << gpu::gl_platform_name(p) << "): " << e.what());
        }
        WARN("GL " << gpu::gl_platform_name(p) << ": " << g.ctx->info().summary());
    }
    g.ctx->make_current();
    return g;
}

}  // namespace uvr::test
