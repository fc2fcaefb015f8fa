// The ray caster's fragment program (Krüger and Westermann): the GLSL twin of gpu/raycast/raycast_fragment.cpp,
// operation for operation. Read that file's header first; the comments here only say where GLSL needs care.
// classification_table.frag and preintegration_table.frag are compiled in front of this file; a pass appends its own
// main (raycast.frag in the renderer), which also defines raycast_segment(), a pre-integrated segment's colour.
//
// Every arithmetic result is `precise` (no fused multiply-add the emulation does not do). The ray is computed in
// double (IEEE operations on llvmpipe), the march in float, as the emulation does; llvmpipe runs shaders with
// denormals flushed and the emulation runs under FlushDenormals (gpu/pipeline/denormals.h).

// ---- Per-frame constants (RaycastFrameConstants) ----
uniform double rc_two_over_width, rc_two_over_height;
uniform dvec3 rc_eye;
uniform dvec3 rc_ray_ox, rc_ray_oy;
uniform dvec3 rc_ray_d0;
uniform dvec3 rc_ray_dx, rc_ray_dy;
uniform dvec3 rc_box_lo, rc_box_hi;
uniform dvec3 rc_tex_scale, rc_tex_half;
uniform vec3 rc_tex_extent;
uniform double rc_step;
uniform int rc_max_samples;
uniform int rc_preintegrate;
uniform float rc_threshold;
uniform float rc_scalar_scale, rc_scalar_bias;
uniform float rc_step_f;
uniform float rc_length_scale, rc_length_bias;
uniform int rc_shade;
uniform dvec3 rc_light;
uniform double rc_ambient, rc_diffuse, rc_specular;
uniform int rc_shininess;
uniform vec3 rc_texel;
uniform vec3 rc_gradient_scale;

// The volume texture: one channel, R8 / R16 / R32F, GL_LINEAR, CLAMP_TO_EDGE (gpu/raycast/gl_raycast.cpp).
layout(binding = 0) uniform sampler3D raycast_volume;

// RaycastRay of gpu/raycast/raycast_fragment.h.
struct RaycastRay {
    int samples;
    vec3 tex0, dtex, tex_exit;
    float last_length;
    double span;  // its length (not `length`, which some compilers take for the method)
    dvec3 entry, dir;
};

// RaycastRayExact: the double part's results before their rounding (the stage harness reads these).
struct RaycastRayExact {
    int samples;
    dvec3 tex0, dtex, tex_exit;
    double last_length;
    double span;  // its length (not `length`, which some compilers take for the method)
    dvec3 entry, dir;
};

RaycastRayExact raycast_ray_exact(ivec2 pix)
{
    RaycastRayExact ray;
    ray.samples = 0;
    ray.tex0 = dvec3(0.0lf);
    ray.dtex = dvec3(0.0lf);
    ray.tex_exit = dvec3(0.0lf);
    ray.last_length = 0.0lf;
    ray.span = 0.0lf;
    ray.entry = dvec3(0.0lf);
    ray.dir = dvec3(0.0lf);
    precise double ndc_x = (double(pix.x) + 0.5lf) * rc_two_over_width - 1.0lf;
    precise double ndc_y = (double(pix.y) + 0.5lf) * rc_two_over_height - 1.0lf;
    precise dvec3 o = dvec3((rc_eye.x + ndc_x * rc_ray_ox.x) + ndc_y * rc_ray_oy.x,
                            (rc_eye.y + ndc_x * rc_ray_ox.y) + ndc_y * rc_ray_oy.y,
                            (rc_eye.z + ndc_x * rc_ray_ox.z) + ndc_y * rc_ray_oy.z);
    precise dvec3 d = dvec3((rc_ray_d0.x + ndc_x * rc_ray_dx.x) + ndc_y * rc_ray_dy.x,
                            (rc_ray_d0.y + ndc_x * rc_ray_dx.y) + ndc_y * rc_ray_dy.y,
                            (rc_ray_d0.z + ndc_x * rc_ray_dx.z) + ndc_y * rc_ray_dy.z);
    // The slab test; vector components are indexed only by loop counters the compiler unrolls.
    double t_in = 0.0lf, t_out = 1e300lf;
    for (int i = 0; i < 3; ++i) {
        if (d[i] == 0.0lf) {
            if (o[i] < rc_box_lo[i] || o[i] > rc_box_hi[i]) t_out = -1.0lf;
            continue;
        }
        precise double ta = (rc_box_lo[i] - o[i]) / d[i];
        precise double tb = (rc_box_hi[i] - o[i]) / d[i];
        double near = ta < tb ? ta : tb;
        double far = ta < tb ? tb : ta;
        if (near > t_in) t_in = near;
        if (far < t_out) t_out = far;
    }
    if (!(t_out > t_in)) return ray;
    precise double scale = sqrt((d.x * d.x + d.y * d.y) + d.z * d.z);
    precise double chord = (t_out - t_in) * scale;
    // n = ceil(L / step), at most rc_max_samples.
    precise double q = chord / rc_step;
    int n = q < double(rc_max_samples) ? int(q) : rc_max_samples;
    if (double(n) < q && n < rc_max_samples) n += 1;
    if (n == 0) return ray;
    ray.samples = n;
    ray.span = chord;
    for (int i = 0; i < 3; ++i) {
        precise double entry = o[i] + t_in * d[i];
        precise double exit_ = o[i] + t_out * d[i];
        precise double dir = d[i] / scale;
        precise double tex0 = (entry - rc_box_lo[i]) * rc_tex_scale[i] + rc_tex_half[i];
        precise double tex_exit = (exit_ - rc_box_lo[i]) * rc_tex_scale[i] + rc_tex_half[i];
        precise double dtex = (dir * rc_step) * rc_tex_scale[i];
        ray.tex0[i] = tex0;
        ray.tex_exit[i] = tex_exit;
        ray.dtex[i] = dtex;
        ray.entry[i] = entry;
        ray.dir[i] = dir;
    }
    precise double last = chord - double(n - 1) * rc_step;
    ray.last_length = last;
    return ray;
}

// rounded_ray: each float member rounded from its double once.
RaycastRay raycast_ray(ivec2 pix)
{
    RaycastRayExact e = raycast_ray_exact(pix);
    RaycastRay ray;
    ray.samples = e.samples;
    ray.tex0 = vec3(e.tex0);
    ray.dtex = vec3(e.dtex);
    ray.tex_exit = vec3(e.tex_exit);
    ray.last_length = float(e.last_length);
    ray.span = e.span;
    ray.entry = e.entry;
    ray.dir = e.dir;
    return ray;
}

// raycast_ray_published (--interpolation gpu): the ray from the box passes' entry and exit texels. Float, every result
// precise; the dot product in the order llvmpipe's lowering gives it, inversesqrt as 1 / sqrt (as havs_paper_entry).
RaycastRay raycast_ray_published(vec4 front, vec4 back)
{
    RaycastRay ray;
    ray.samples = 0;
    ray.tex0 = vec3(0.0);
    ray.dtex = vec3(0.0);
    ray.tex_exit = vec3(0.0);
    ray.last_length = 0.0;
    ray.span = 0.0lf;
    ray.entry = dvec3(0.0lf);
    ray.dir = dvec3(0.0lf);
    if (front.w == 0.0 || back.w == 0.0) return ray;
    precise vec3 d = vec3(back.x - front.x, back.y - front.y, back.z - front.z);
    precise vec3 w = vec3(d.x * rc_tex_extent.x, d.y * rc_tex_extent.y, d.z * rc_tex_extent.z);
    precise float zz = w.z * w.z;
    precise float yy = w.y * w.y;
    precise float xx = w.x * w.x;
    precise float t = (zz + yy) + xx;
    if (!(t > 0.0)) return ray;
    precise float rsq = inversesqrt(t);
    precise float len = t * rsq;
    // The sample count in double, as raycast_ray_exact's.
    precise double q = double(len) / rc_step;
    int n = q < double(rc_max_samples) ? int(q) : rc_max_samples;
    if (double(n) < q && n < rc_max_samples) n += 1;
    if (n == 0) return ray;
    ray.samples = n;
    ray.span = double(len);
    precise float scale = rsq * rc_step_f;
    precise vec3 dtex = vec3(d.x * scale, d.y * scale, d.z * scale);
    ray.dtex = dtex;
    ray.tex0 = front.xyz;
    ray.tex_exit = back.xyz;
    precise double last = double(len) - double(n - 1) * rc_step;
    ray.last_length = float(last);
    precise double inv_length = 1.0lf / double(len);
    for (int i = 0; i < 3; ++i) {
        precise double entry = (double(front[i]) - rc_tex_half[i]) / rc_tex_scale[i] + rc_box_lo[i];
        precise double dir = double(w[i]) * inv_length;
        ray.entry[i] = entry;
        ray.dir[i] = dir;
    }
    return ray;
}

float raycast_at(vec3 p) { return texture(raycast_volume, p).r; }

vec3 raycast_gradient(vec3 p)
{
    precise float xp = p.x + rc_texel.x, xm = p.x - rc_texel.x;
    precise float yp = p.y + rc_texel.y, ym = p.y - rc_texel.y;
    precise float zp = p.z + rc_texel.z, zm = p.z - rc_texel.z;
    precise float gx = (raycast_at(vec3(xp, p.y, p.z)) - raycast_at(vec3(xm, p.y, p.z))) * rc_gradient_scale.x;
    precise float gy = (raycast_at(vec3(p.x, yp, p.z)) - raycast_at(vec3(p.x, ym, p.z))) * rc_gradient_scale.y;
    precise float gz = (raycast_at(vec3(p.x, p.y, zp)) - raycast_at(vec3(p.x, p.y, zm))) * rc_gradient_scale.z;
    return vec3(gx, gy, gz);
}

// raycast_light_factors: the double part; raycast_light rounds it to float.
dvec2 raycast_light_factors(RaycastRay ray, double t, vec3 g)
{
    double gx = double(g.x), gy = double(g.y), gz = double(g.z);
    precise double gg = (gx * gx + gy * gy) + gz * gz;
    if (gg == 0.0lf) return dvec2(1.0lf, 0.0lf);
    precise double lx = rc_light.x - (ray.entry.x + t * ray.dir.x);
    precise double ly = rc_light.y - (ray.entry.y + t * ray.dir.y);
    precise double lz = rc_light.z - (ray.entry.z + t * ray.dir.z);
    precise double ll = sqrt((lx * lx + ly * ly) + lz * lz);
    precise double glen = sqrt(gg);
    double diffuse = 0.0lf, specular = 0.0lf;
    if (ll > 0.0lf) {
        precise double ndl = ((gx * lx + gy * ly) + gz * lz) / (glen * ll);
        diffuse = ndl < 0.0lf ? -ndl : ndl;
        precise double hx = lx / ll - ray.dir.x;
        precise double hy = ly / ll - ray.dir.y;
        precise double hz = lz / ll - ray.dir.z;
        precise double hh = sqrt((hx * hx + hy * hy) + hz * hz);
        if (hh > 0.0lf) {
            precise double ndh = ((gx * hx + gy * hy) + gz * hz) / (glen * hh);
            double a = ndh < 0.0lf ? -ndh : ndh;
            precise double power = 1.0lf;
            for (int i = 0; i < rc_shininess; ++i) power = power * a;
            specular = power;
        }
    }
    precise double m = rc_ambient + rc_diffuse * diffuse;
    precise double s = rc_specular * specular;
    return dvec2(m, s);
}

vec2 raycast_light(RaycastRay ray, double t, vec3 g)
{
    dvec2 f = raycast_light_factors(ray, t, g);
    return vec2(float(f.x), float(f.y));
}

// c.rgb * m + c.a * p, alpha unchanged (unfused).
vec4 raycast_lit(vec4 c, vec2 f)
{
    precise float r = c.r * f.x + c.a * f.y;
    precise float g = c.g * f.x + c.a * f.y;
    precise float b = c.b * f.x + c.a * f.y;
    return vec4(r, g, b, c.a);
}

vec4 raycast_shaded(vec4 c, RaycastRay ray, vec3 p, double t)
{
    // Compiled only into a program that shades (RAYCAST_SHADE; the stage harness always): llvmpipe runs both sides of
    // a branch under an execution mask, even a branch on a uniform, so the gradient's six fetches would cost every
    // unshaded sample their time (docs/raycast.md, "Speed").
#ifdef RAYCAST_SHADE
    if (rc_shade != 0) c = raycast_lit(c, raycast_light(ray, t, raycast_gradient(p)));
#endif
    return c;
}

vec3 raycast_position(RaycastRay ray, int k)
{
    float kf = float(k);
    precise vec3 p = ray.tex0 + kf * ray.dtex;
    return p;
}

float raycast_scalar(vec3 p)
{
    precise float x = raycast_at(p) * rc_scalar_scale + rc_scalar_bias;
    return x;
}

// Front to back: acc = c * (1 - acc.a) + acc (MAD, unfused).
void raycast_composite(inout vec4 acc, vec4 c)
{
    precise float one_minus_a = 1.0 - acc.a;
    precise vec4 composited = c * one_minus_a + acc;
    acc = composited;
}

// What a pre-integrated segment contributes (the pass defines it: preintegration_lookup in the renderer).
vec4 raycast_segment(float x_front, float x_back, float t_z, float seg_length);

// raycast_march of gpu/raycast/raycast_fragment.cpp: the colour, and the samples taken (as a float: exact below 2^24).
vec4 raycast_march(RaycastRay ray, out float samples)
{
    vec4 acc = vec4(0.0);
    samples = 0.0;
    int n = ray.samples;
    if (rc_preintegrate == 0) {
        for (int k = 0; k < n; ++k) {
            vec3 p = raycast_position(ray, k);
            precise double t = double(k) * rc_step;
            vec4 c = raycast_shaded(classification_lookup(raycast_scalar(p)), ray, p, t);
            raycast_composite(acc, c);
            samples += 1.0;
            if (acc.a > rc_threshold) break;
        }
        return acc;
    }
    if (n == 0) return acc;
    float previous = raycast_scalar(raycast_position(ray, 0));
    samples = 1.0;
    for (int k = 1; k <= n; ++k) {
        bool last = k == n;
        vec3 p = last ? ray.tex_exit : raycast_position(ray, k);
        float seg_length = last ? ray.last_length : rc_step_f;
        float x = raycast_scalar(p);
        samples += 1.0;
        if (seg_length > 0.0) {
            precise float t_z = seg_length * rc_length_scale + rc_length_bias;
            precise double t = last ? ray.span : double(k) * rc_step;
            vec4 c = raycast_shaded(raycast_segment(previous, x, t_z, seg_length), ray, p, t);
            raycast_composite(acc, c);
        }
        previous = x;
        if (acc.a > rc_threshold) break;
    }
    return acc;
}
