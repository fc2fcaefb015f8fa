// The ray caster's full-screen pass (drawn with fullscreen.vert): one fragment per pixel runs the march
// (raycast_fragment.frag) and writes the colour and the number of samples (gpu/raycast/gl_raycast.cpp reads both back).
layout(location = 0) out vec4 rc_colour;
layout(location = 1) out vec4 rc_diagnostics;

vec4 raycast_segment(float x_front, float x_back, float t_z, float seg_length)
{
    return preintegration_lookup(x_front, x_back, t_z);
}

void main()
{
    RaycastRay ray = raycast_ray(ivec2(gl_FragCoord.xy));
    float samples;
    rc_colour = raycast_march(ray, samples);
    rc_diagnostics = vec4(samples, 0.0, 0.0, 0.0);
}
