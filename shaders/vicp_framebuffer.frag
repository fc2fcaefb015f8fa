// VICP's compositing reads and writes its pixel's colour and diagnostics (gpu/vicp/gl_vicp.cpp, gpu/gl/
// gl_fragment_access.h): through framebuffer fetch (the attachments as inout outputs, coherent: each fragment sees
// what the previous one on its pixel wrote, in primitive order), or, with VICP_IMAGES, as images read and written by
// imageLoad / imageStore between a fragment-shader interlock's begin and end (VICP_INTERLOCK_ARB or _NV; compiled out
// on llvmpipe, which shades one pixel's fragments in primitive order), as HAVS's k-buffer does (shaders/havs.frag).
// Compiled in front of vicp.frag and vicp_published.frag, which call vicp_begin_interlock() and vicp_end_interlock()
// in main (an interlock may be entered nowhere else).

#ifdef VICP_IMAGES
layout(binding = 0, rgba32f) coherent uniform image2D vicp_color_image;
layout(binding = 1, rgba32f) coherent uniform image2D vicp_diagnostics_image;
#if defined(VICP_INTERLOCK_ARB)
layout(pixel_interlock_ordered) in;
#define vicp_begin_interlock() beginInvocationInterlockARB()
#define vicp_end_interlock() endInvocationInterlockARB()
#elif defined(VICP_INTERLOCK_NV)
layout(pixel_interlock_ordered) in;
#define vicp_begin_interlock() beginInvocationInterlockNV()
#define vicp_end_interlock() endInvocationInterlockNV()
#else
#define vicp_begin_interlock()
#define vicp_end_interlock()
#endif
#define vicp_load_color() imageLoad(vicp_color_image, ivec2(gl_FragCoord.xy))
#define vicp_load_diagnostics() imageLoad(vicp_diagnostics_image, ivec2(gl_FragCoord.xy))
#define vicp_store(fb, diag)                                          \
    imageStore(vicp_color_image, ivec2(gl_FragCoord.xy), fb);         \
    imageStore(vicp_diagnostics_image, ivec2(gl_FragCoord.xy), diag)
#else
layout(location = 0) inout vec4 vicp_color;
layout(location = 1) inout vec4 vicp_diagnostics;  // VicpDiagnostics as floats (vicp_composite)
#define vicp_begin_interlock()
#define vicp_end_interlock()
#define vicp_load_color() vicp_color
#define vicp_load_diagnostics() vicp_diagnostics
#define vicp_store(fb, diag) \
    vicp_color = fb;          \
    vicp_diagnostics = diag
#endif
