// VICP's published program draw (--interpolation gpu, gpu/vicp/gl_vicp.cpp): the fragment program's main.
// preintegration_table.frag, vicp_tet.glsl, vicp_fragment.frag (the compositing), vicp_published.glsl,
// vicp_published_fragment.frag (the exit) and vicp_framebuffer.frag are compiled in front of this file;
// vicp_published.vert is its vertex side.
// The twin of VicpRenderer::composite_published (gpu/vicp/vicp.cpp). Back faces leave the attachments as read, as in
// vicp.frag (on gl_FrontFacing, llvmpipe's fixed-point facing).

smooth in vec3 vicp_published_distance;
smooth in vec3 vicp_published_scalar;
smooth in float vicp_published_s;
smooth in vec3 vicp_published_entry;


vec4 vicp_shade(float u_front, float u_back, float t_z, float seg_length)
{
    return preintegration_lookup(u_front, u_back, t_z);
}

void main()
{
    VicpPublishedExit e = vicp_published_exit(vicp_published_distance, vicp_published_scalar, vicp_published_s);
    VicpSegment seg;
    seg.s_front = double(e.s_front);
    seg.s_back = double(e.s_back);
    precise double t_in = double(vicp_published_entry_distance(vicp_published_entry));
    precise double t_out = t_in + double(e.chord);
    seg.t_in = t_in;
    seg.t_out = t_out;
    seg.chord = double(e.chord);
    vicp_begin_interlock();
    vec4 fb = vicp_load_color(), diag = vicp_load_diagnostics();
    if (gl_FrontFacing) vicp_composite(seg, fb, diag);  // killed: fb and diag are as read
    vicp_store(fb, diag);
    vicp_end_interlock();
}
