// HAVS's two passes on the GPU: the GLSL side of gpu/havs/havs.cpp (the emulated driver) and gpu/havs/gl_havs.cpp (the
// GL driver). havs_fragment.frag is compiled in front of this file; the prelude defines
//   HAVS_K             the number of stored entries
//   HAVS_TARGETS       the k-buffer's colour attachments, (HAVS_K + 1) / 2: two entries (x, y) a texel, as in the paper
//   HAVS_PASS_FLUSH    for the flush pass (a full-screen triangle, k runs a pixel); absent for the geometry pass
//   HAVS_DIAGNOSTICS   when the per-pixel diagnostics go to one more attachment
//   HAVS_PAPER_VARYINGS --interpolation gpu: the fragment values from the interpolated varyings (havs_paper_entry)
//   HAVS_PAPER_ENTRIES  --entries paper: the entry is the interpolated scalar, nullified only when negative
//   HAVS_KBUFFER_IMAGES the read-modify-write through image load/store (no framebuffer fetch), with HAVS_INTERLOCK_ARB,
//                      HAVS_INTERLOCK_NV or neither (llvmpipe)
//
// Read-modify-write of the k-buffer. The paper reads its k-buffer as textures bound to the very targets it renders
// into, which GL leaves undefined once two fragments of one draw hit the same pixel. Here every attachment is an
// `inout` output of GL_EXT_shader_framebuffer_fetch (coherent, not the _non_coherent variant): a fragment reads what
// the previous fragment on its pixel wrote, in primitive order, which GL guarantees for framebuffer operations. So one
// draw call takes all faces in the CPU's sorted order and each pixel sees its fragments exactly in that order, as the
// emulation applies them.
//
// The opacity kill does not `discard`: a killed fragment writes back what it read, unchanged (havs_kbuffer leaves a[]
// and fb alone when it kills), which leaves every attachment with the bits a discard would. (llvmpipe's selects may
// flush a denormal they move, docs/gl-backend.md "denormals"; but no attachment holds one: every value written is a
// clear value or the result of arithmetic, which llvmpipe flushes to zero.) The reason is speed: a shader that can
// discard costs llvmpipe about 150 ms more on a Blunt Fin frame (512 x 512, k = 6: 0.65 s against 0.49 s, same run;
// docs/gl-backend.md, "Speed").

#if defined(HAVS_PAPER_VARYINGS) && !defined(HAVS_PASS_FLUSH)
smooth in vec3 havs_eye_position;  // the paper's texture coordinate 1
smooth in float havs_eye_scalar;   // the paper's texture coordinate 0
flat in float havs_face_side;
noperspective in vec3 havs_corner;
#endif

#ifdef HAVS_KBUFFER_IMAGES
// Without framebuffer fetch (desktop GPUs): the colour, the k-buffer and the diagnostics are the same RGBA32F textures
// bound as images, read and written by imageLoad / imageStore between the interlock's begin and end, which orders the
// fragments of one pixel by primitive as the framebuffer does (GL_ARB_ or GL_NV_fragment_shader_interlock). On
// llvmpipe the interlock is compiled out (HAVS_INTERLOCK none): its rasterizer threads each own a tile and shade a
// tile's fragments one primitive after another, so one pixel's fragments run in primitive order anyway.
layout(binding = 0, rgba32f) coherent uniform image2D havs_color_image;
layout(binding = 1, rgba32f) coherent uniform image2D havs_entry_images[HAVS_TARGETS];
#ifdef HAVS_DIAGNOSTICS
layout(binding = HAVS_TARGETS + 1, rgba32f) coherent uniform image2D havs_diagnostics_image;
#endif
#if defined(HAVS_INTERLOCK_ARB)
layout(pixel_interlock_ordered) in;
#define havs_begin_interlock() beginInvocationInterlockARB()
#define havs_end_interlock() endInvocationInterlockARB()
#elif defined(HAVS_INTERLOCK_NV)
layout(pixel_interlock_ordered) in;
#define havs_begin_interlock() beginInvocationInterlockNV()
#define havs_end_interlock() endInvocationInterlockNV()
#else
#define havs_begin_interlock()
#define havs_end_interlock()
#endif
#define havs_load_color(p) imageLoad(havs_color_image, p)
#define havs_store_color(p, v) imageStore(havs_color_image, p, v)
#define havs_load_entries(p, t) imageLoad(havs_entry_images[t], p)
#define havs_store_entries(p, t, v) imageStore(havs_entry_images[t], p, v)
#define havs_load_diagnostics(p) imageLoad(havs_diagnostics_image, p)
#define havs_store_diagnostics(p, v) imageStore(havs_diagnostics_image, p, v)
#else
layout(location = 0) inout vec4 havs_color;
layout(location = 1) inout vec4 havs_entries[HAVS_TARGETS];
#ifdef HAVS_DIAGNOSTICS
layout(location = HAVS_TARGETS + 1) inout vec4 havs_diagnostics;  // havs_diag of havs_fragment.frag
#endif
#define havs_begin_interlock()
#define havs_end_interlock()
#define havs_load_color(p) havs_color
#define havs_store_color(p, v) havs_color = v
#define havs_load_entries(p, t) havs_entries[t]
#define havs_store_entries(p, t, v) havs_entries[t] = v
#define havs_load_diagnostics(p) havs_diagnostics
#define havs_store_diagnostics(p, v) havs_diagnostics = v
#endif

vec4 havs_shade(float u_front, float u_back, float t_z, float seg_length)
{
    return preintegration_lookup(u_front, u_back, t_z);
}

void main()
{
    ivec2 pix = ivec2(gl_FragCoord.xy);
    havs_begin_interlock();
    vec4 stored[HAVS_TARGETS];
    for (int t = 0; t < HAVS_TARGETS; ++t) stored[t] = havs_load_entries(pix, t);
    vec2 a[HAVS_K];
    for (int i = 0; i < HAVS_K; ++i) a[i] = (i % 2 == 0) ? stored[i / 2].xy : stored[i / 2].zw;
    vec4 fb = havs_load_color(pix);
#ifdef HAVS_DIAGNOSTICS
    havs_diag = havs_load_diagnostics(pix);
#endif
#ifdef HAVS_PASS_FLUSH
    // The flush: k runs of the program on kFlushFragment (-1, +inf; kPaperFlushFragment with --entries paper), one
    // after the other, in one full-screen pass. Each pixel sees the same k runs in the same order as from k passes of
    // one run each (the emulation's loop in gpu/havs/havs.cpp), with one fetch and one store of the attachments
    // instead of k.
    for (int run = 0; run < HAVS_K; ++run) havs_kbuffer(vec2(-1.0, havs_flush_distance), a, fb);
#elif defined(HAVS_PAPER_VARYINGS)
    // --interpolation gpu: the paper's fragment program on the rasterizer's varyings; the side as below.
    float side = havs_face_side;
    if (side < 0.0 && gl_FrontFacing) side = havs_side_entry;
    side = havs_paper_side(side, havs_corner);
    havs_kbuffer(havs_paper_entry(havs_eye_position, havs_eye_scalar, side), a, fb);
#else
    // The face's constants, in sorted order (gl_PrimitiveID counts the draw's triangles). A boundary face arrives with
    // side -1 (an exit) and stays one only when the rasterizer sees it back-facing; front-facing, it is an entry.
    HavsFace f = havs_face(gl_PrimitiveID);
    if (f.side < 0.0 && gl_FrontFacing) f.side = havs_side_entry;
    havs_kbuffer(havs_fragment_entry(f, ivec2(gl_FragCoord.xy)), a, fb);  // false (killed): a[] and fb are as read
#endif
    havs_store_color(pix, fb);
    for (int t = 0; t < HAVS_TARGETS; ++t) {
        vec4 texel = stored[t];
        texel.xy = a[2 * t];
        if (2 * t + 1 < HAVS_K) texel.zw = a[2 * t + 1];
        havs_store_entries(pix, t, texel);
    }
#ifdef HAVS_DIAGNOSTICS
    havs_store_diagnostics(pix, havs_diag);
#endif
    havs_end_interlock();
}
