// VICP's draw (gpu/vicp/gl_vicp.cpp): the fragment program's main. preintegration_table.frag, vicp_tet.glsl,
// vicp_fragment.frag and vicp_framebuffer.frag are compiled in front of this file; vicp.vert is its vertex side.
//
// Front-to-back compositing reads the framebuffer colour in the shader (framebuffer fetch, or the image route:
// vicp_framebuffer.frag), each fragment seeing what the previous one on its pixel wrote, in primitive order, the
// cells' order, as HAVS's k-buffer does (shaders/havs.frag); the paper blends back to front in fixed function, which a front-to-back order
// and the opacity kill cannot use (docs/vicp.md, "Compositing"). Back faces are dropped here, on gl_FrontFacing
// (llvmpipe's fixed-point facing, which the emulation mirrors), not culled by glCullFace, whose draw-module stage
// decides slivers on a float determinant (docs/rasterizer.md, "Not emulated" 2): each pixel sees a cell once,
// through the face its ray enters by.

flat in VicpTet vicp_tet;


vec4 vicp_shade(float u_front, float u_back, float t_z, float seg_length)
{
    return preintegration_lookup(u_front, u_back, t_z);
}

// Neither a back face nor a killed fragment (the opacity kill) discards: both write back what they read, which leaves
// the attachments' bits as a discard would (no attachment holds a denormal a select could flush: shaders/havs.frag).
// A shader that can discard runs markedly slower on llvmpipe (shaders/havs.frag).
void main()
{
    VicpSegment seg = vicp_fragment_values(vicp_tet, ivec2(gl_FragCoord.xy));
    vicp_begin_interlock();
    vec4 fb = vicp_load_color(), diag = vicp_load_diagnostics();
    if (gl_FrontFacing) vicp_composite(seg, fb, diag);  // killed: fb and diag are as read
    vicp_store(fb, diag);
    vicp_end_interlock();
}
