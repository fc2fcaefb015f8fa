// The ray caster's march pass (raycast_fragment.frag's march; gpu/raycast/gl_raycast.cpp reads both outputs back):
//   - RAYCAST_PUBLISHED_PASSES (--interpolation gpu): the published third pass, the box drawn again (raycast_box.vert), its
//     front faces only; the ray from the entry and exit the first two passes wrote, read at the fragment's pixel;
//   - otherwise (exact): one full-screen triangle (fullscreen.vert), the ray from gl_FragCoord in double.
layout(location = 0) out vec4 rc_colour;
layout(location = 1) out vec4 rc_diagnostics;

vec4 raycast_segment(float x_front, float x_back, float t_z, float seg_length)
{
    return preintegration_lookup(x_front, x_back, t_z);
}

#ifdef RAYCAST_PUBLISHED_PASSES
layout(binding = 5) uniform sampler2D rc_front_positions;  // the first pass's target
layout(binding = 6) uniform sampler2D rc_back_positions;   // the second's
#endif

void main()
{
#ifdef RAYCAST_PUBLISHED_PASSES
    ivec2 pix = ivec2(gl_FragCoord.xy);
    RaycastRay ray = raycast_ray_published(texelFetch(rc_front_positions, pix, 0), texelFetch(rc_back_positions, pix, 0));
#else
    RaycastRay ray = raycast_ray(ivec2(gl_FragCoord.xy));
#endif
    float samples;
    rc_colour = raycast_march(ray, samples);
    rc_diagnostics = vec4(samples, 0.0, 0.0, 0.0);
}
