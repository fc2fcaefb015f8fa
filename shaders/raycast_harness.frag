// Runs the ray caster's fragment program (raycast_fragment.frag, compiled in front of this file behind
// classification_table.frag and preintegration_table.frag) alone: one case per pixel of a full-screen pass, inputs
// and outputs in storage buffers laid out as gpu/raycast/gl_raycast_harness.cpp's Gl* structs. Exactly one of
//   HARNESS_RAY    raycast_ray_exact at pixel harness_pixels[case], every double before its rounding
//   HARNESS_MARCH  raycast_march of ray harness_rays[case] over the bound textures
//   HARNESS_LIGHT  raycast_light_factors of harness_lights[case]
//   HARNESS_RAY_PUBLISHED  raycast_ray_published of the entry and exit texels harness_texels[2 case], [2 case + 1]
// is defined. The frame constants are the renderer's uniforms (rc_*).

uniform int harness_width;  // pixels per row: case = y * harness_width + x
uniform int harness_count;  // cases in this pass; the pixels past the last do nothing

int harness_case() { return int(gl_FragCoord.y) * harness_width + int(gl_FragCoord.x); }

// As raycast.frag: a pre-integrated segment is the table's lookup.
vec4 raycast_segment(float x_front, float x_back, float t_z, float seg_length)
{
    return preintegration_lookup(x_front, x_back, t_z);
}

#if defined(HARNESS_RAY)

struct HarnessRayExact {
    double tex0[3], dtex[3], tex_exit[3];
    double last_length, span;
    double entry[3], dir[3];
    int samples, pad;
};
layout(std430, binding = 0) readonly buffer HarnessPixels { ivec2 harness_pixels[]; };
layout(std430, binding = 1) writeonly buffer HarnessRays { HarnessRayExact harness_rays[]; };

void main()
{
    int i = harness_case();
    if (i >= harness_count) return;
    RaycastRayExact e = raycast_ray_exact(harness_pixels[i]);
    HarnessRayExact r;
    for (int k = 0; k < 3; ++k) {
        r.tex0[k] = e.tex0[k];
        r.dtex[k] = e.dtex[k];
        r.tex_exit[k] = e.tex_exit[k];
        r.entry[k] = e.entry[k];
        r.dir[k] = e.dir[k];
    }
    r.last_length = e.last_length;
    r.span = e.span;
    r.samples = e.samples;
    r.pad = 0;
    harness_rays[i] = r;
}

#elif defined(HARNESS_MARCH)

struct HarnessRay {
    double span, entry[3], dir[3];
    float tex0[3], dtex[3], tex_exit[3], last_length;
    int samples;
    float pad;
};
struct HarnessMarchResult {
    vec4 colour;
    float samples, pad[3];
};
layout(std430, binding = 0) readonly buffer HarnessRays { HarnessRay harness_rays[]; };
layout(std430, binding = 1) writeonly buffer HarnessResults { HarnessMarchResult harness_results[]; };

void main()
{
    int i = harness_case();
    if (i >= harness_count) return;
    HarnessRay h = harness_rays[i];
    RaycastRay ray;
    ray.samples = h.samples;
    ray.tex0 = vec3(h.tex0[0], h.tex0[1], h.tex0[2]);
    ray.dtex = vec3(h.dtex[0], h.dtex[1], h.dtex[2]);
    ray.tex_exit = vec3(h.tex_exit[0], h.tex_exit[1], h.tex_exit[2]);
    ray.last_length = h.last_length;
    ray.span = h.span;
    ray.entry = dvec3(h.entry[0], h.entry[1], h.entry[2]);
    ray.dir = dvec3(h.dir[0], h.dir[1], h.dir[2]);
    HarnessMarchResult r;
    r.colour = raycast_march(ray, r.samples);
    r.pad = float[3](0.0, 0.0, 0.0);
    harness_results[i] = r;
}

#elif defined(HARNESS_RAY_PUBLISHED)

struct HarnessRay {
    double span, entry[3], dir[3];
    float tex0[3], dtex[3], tex_exit[3], last_length;
    int samples;
    float pad;
};
layout(std430, binding = 0) readonly buffer HarnessTexels { vec4 harness_texels[]; };
layout(std430, binding = 1) writeonly buffer HarnessRays { HarnessRay harness_rays[]; };

void main()
{
    int i = harness_case();
    if (i >= harness_count) return;
    RaycastRay ray = raycast_ray_published(harness_texels[2 * i], harness_texels[2 * i + 1]);
    HarnessRay h;
    h.span = ray.span;
    for (int k = 0; k < 3; ++k) {
        h.entry[k] = ray.entry[k];
        h.dir[k] = ray.dir[k];
        h.tex0[k] = ray.tex0[k];
        h.dtex[k] = ray.dtex[k];
        h.tex_exit[k] = ray.tex_exit[k];
    }
    h.last_length = ray.last_length;
    h.samples = ray.samples;
    h.pad = 0.0;
    harness_rays[i] = h;
}

#elif defined(HARNESS_LIGHT)

struct HarnessLightCase {
    double entry[3], dir[3], t;
    float g[3], pad;
};
layout(std430, binding = 0) readonly buffer HarnessLights { HarnessLightCase harness_lights[]; };
layout(std430, binding = 1) writeonly buffer HarnessFactors { double harness_factors[]; };  // 2 a case

void main()
{
    int i = harness_case();
    if (i >= harness_count) return;
    HarnessLightCase c = harness_lights[i];
    RaycastRay ray;
    ray.samples = 1;
    ray.tex0 = vec3(0.0);
    ray.dtex = vec3(0.0);
    ray.tex_exit = vec3(0.0);
    ray.last_length = 0.0;
    ray.span = 0.0lf;
    ray.entry = dvec3(c.entry[0], c.entry[1], c.entry[2]);
    ray.dir = dvec3(c.dir[0], c.dir[1], c.dir[2]);
    dvec2 f = raycast_light_factors(ray, c.t, vec3(c.g[0], c.g[1], c.g[2]));
    harness_factors[2 * i] = f.x;
    harness_factors[2 * i + 1] = f.y;
}

#endif
