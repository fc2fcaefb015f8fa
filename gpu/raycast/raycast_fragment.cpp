#include "gpu/raycast/raycast_fragment.h"

#include <cmath>

namespace uvr::gpu {

namespace {

// n = ceil(L / step), written with a truncation (exact) and a comparison; at most max_samples.
int sample_count(const RaycastFrameConstants& fc, double length)
{
    const double q = length / fc.step;
    int n = q < double(fc.max_samples) ? int(q) : fc.max_samples;
    if (double(n) < q && n < fc.max_samples) n += 1;
    return n;
}

}  // namespace

RaycastRayExact raycast_ray_exact(const RaycastFrameConstants& fc, int pix_x, int pix_y)
{
    RaycastRayExact ray;
    const double ndc_x = (double(pix_x) + 0.5) * fc.two_over_width - 1.0;
    const double ndc_y = (double(pix_y) + 0.5) * fc.two_over_height - 1.0;
    const double o[3] = {(fc.eye.x + ndc_x * fc.ray_ox.x) + ndc_y * fc.ray_oy.x,
                         (fc.eye.y + ndc_x * fc.ray_ox.y) + ndc_y * fc.ray_oy.y,
                         (fc.eye.z + ndc_x * fc.ray_ox.z) + ndc_y * fc.ray_oy.z};
    const double d[3] = {(fc.ray_d0.x + ndc_x * fc.ray_dx.x) + ndc_y * fc.ray_dy.x,
                         (fc.ray_d0.y + ndc_x * fc.ray_dx.y) + ndc_y * fc.ray_dy.y,
                         (fc.ray_d0.z + ndc_x * fc.ray_dx.z) + ndc_y * fc.ray_dy.z};
    const double lo[3] = {fc.box_lo.x, fc.box_lo.y, fc.box_lo.z}, hi[3] = {fc.box_hi.x, fc.box_hi.y, fc.box_hi.z};
    // The slab test. An axis the ray runs parallel to either holds the whole ray or none of it.
    double t_in = 0.0, t_out = 1e300;
    for (int i = 0; i < 3; ++i) {
        if (d[i] == 0.0) {
            if (o[i] < lo[i] || o[i] > hi[i]) t_out = -1.0;
            continue;
        }
        const double ta = (lo[i] - o[i]) / d[i], tb = (hi[i] - o[i]) / d[i];
        const double near = ta < tb ? ta : tb, far = ta < tb ? tb : ta;
        if (near > t_in) t_in = near;
        if (far < t_out) t_out = far;
    }
    if (!(t_out > t_in)) return ray;
    const double scale = std::sqrt((d[0] * d[0] + d[1] * d[1]) + d[2] * d[2]);
    const double length = (t_out - t_in) * scale;
    const int n = sample_count(fc, length);
    if (n == 0) return ray;
    ray.samples = n;
    ray.length = length;
    const double tex_scale[3] = {fc.tex_scale.x, fc.tex_scale.y, fc.tex_scale.z};
    const double tex_half[3] = {fc.tex_half.x, fc.tex_half.y, fc.tex_half.z};
    for (int i = 0; i < 3; ++i) {
        const double entry = o[i] + t_in * d[i], exit = o[i] + t_out * d[i];
        const double dir = d[i] / scale;
        ray.tex0[i] = (entry - lo[i]) * tex_scale[i] + tex_half[i];
        ray.tex_exit[i] = (exit - lo[i]) * tex_scale[i] + tex_half[i];
        ray.dtex[i] = (dir * fc.step) * tex_scale[i];
        ray.entry[i] = entry;
        ray.dir[i] = dir;
    }
    ray.last_length = length - double(n - 1) * fc.step;
    return ray;
}

RaycastRay rounded_ray(const RaycastRayExact& e)
{
    RaycastRay ray;
    ray.samples = e.samples;
    ray.tex0 = glm::vec3(e.tex0);
    ray.dtex = glm::vec3(e.dtex);
    ray.tex_exit = glm::vec3(e.tex_exit);
    ray.last_length = float(e.last_length);
    ray.length = e.length;
    ray.entry = e.entry;
    ray.dir = e.dir;
    return ray;
}

RaycastRay raycast_ray_published(const RaycastFrameConstants& fc, const glm::vec4& front, const glm::vec4& back)
{
    RaycastRay ray;
    if (front.w == 0.0f || back.w == 0.0f) return ray;
    // The published direction, back - front, in texture coordinates; in world units through the box's extent per
    // texture unit, so that the step is world units as --step says (docs/raycast.md, "The published passes").
    const glm::vec3 d(back.x - front.x, back.y - front.y, back.z - front.z);
    const glm::vec3 w(d.x * fc.tex_extent.x, d.y * fc.tex_extent.y, d.z * fc.tex_extent.z);
    // DP3, RSQ, MUL, as the HAVS paper's program measures a distance (gpu/havs/havs_fragment.cpp havs_paper_entry):
    // llvmpipe's dot sums from the last component, inversesqrt is 1 / sqrt, two roundings.
    const float zz = w.z * w.z, yy = w.y * w.y, xx = w.x * w.x;
    const float t = (zz + yy) + xx;
    if (!(t > 0.0f)) return ray;
    const float rsq = 1.0f / std::sqrt(t);
    const float length = t * rsq;
    const int n = sample_count(fc, double(length));
    if (n == 0) return ray;
    ray.samples = n;
    ray.length = double(length);
    // normalize(d) (in world units) * step, back in texture coordinates: d * (rsq * step).
    const float scale = rsq * fc.step_f;
    ray.dtex = glm::vec3(d.x * scale, d.y * scale, d.z * scale);
    ray.tex0 = glm::vec3(front);
    ray.tex_exit = glm::vec3(back);
    ray.last_length = float(double(length) - double(n - 1) * fc.step);
    // Shading's geometry, in double from the same floats: the entry in the box's centred frame and the unit direction.
    const double inv_length = 1.0 / double(length);
    for (int i = 0; i < 3; ++i) {
        ray.entry[i] = (double(front[i]) - fc.tex_half[i]) / fc.tex_scale[i] + fc.box_lo[i];
        ray.dir[i] = double(w[i]) * inv_length;
    }
    return ray;
}

glm::vec3 raycast_gradient(const RaycastFrameConstants& fc, const RaycastTextures& tex, const glm::vec3& p)
{
    auto at = [&](float x, float y, float z) { return sample_3d(tex.volume, x, y, z, TextureFilter::linear, tex.cpu).x; };
    const float gx = (at(p.x + fc.texel.x, p.y, p.z) - at(p.x - fc.texel.x, p.y, p.z)) * fc.gradient_scale.x;
    const float gy = (at(p.x, p.y + fc.texel.y, p.z) - at(p.x, p.y - fc.texel.y, p.z)) * fc.gradient_scale.y;
    const float gz = (at(p.x, p.y, p.z + fc.texel.z) - at(p.x, p.y, p.z - fc.texel.z)) * fc.gradient_scale.z;
    return {gx, gy, gz};
}

glm::dvec2 raycast_light_factors(const RaycastFrameConstants& fc, const RaycastRay& ray, double t, const glm::vec3& g)
{
    const double gx = g.x, gy = g.y, gz = g.z;
    const double gg = (gx * gx + gy * gy) + gz * gz;
    if (gg == 0.0) return {1.0, 0.0};
    const double lx = fc.light.x - (ray.entry.x + t * ray.dir.x);
    const double ly = fc.light.y - (ray.entry.y + t * ray.dir.y);
    const double lz = fc.light.z - (ray.entry.z + t * ray.dir.z);
    const double ll = std::sqrt((lx * lx + ly * ly) + lz * lz);
    const double glen = std::sqrt(gg);
    double diffuse = 0.0, specular = 0.0;
    if (ll > 0.0) {
        const double ndl = ((gx * lx + gy * ly) + gz * lz) / (glen * ll);
        diffuse = ndl < 0.0 ? -ndl : ndl;
        // h = l / |l| + v, v = -dir (towards the eye).
        const double hx = lx / ll - ray.dir.x, hy = ly / ll - ray.dir.y, hz = lz / ll - ray.dir.z;
        const double hh = std::sqrt((hx * hx + hy * hy) + hz * hz);
        if (hh > 0.0) {
            double ndh = ((gx * hx + gy * hy) + gz * hz) / (glen * hh);
            ndh = ndh < 0.0 ? -ndh : ndh;
            double power = 1.0;
            for (int i = 0; i < fc.shininess; ++i) power = power * ndh;
            specular = power;
        }
    }
    return {fc.ambient + fc.diffuse * diffuse, fc.specular * specular};
}

RaycastResult raycast_march(const RaycastFrameConstants& fc, const RaycastRay& ray, const RaycastTextures& tex)
{
    RaycastResult out;
    const int n = ray.samples;
    auto position = [&](int k) {
        const float kf = float(k);
        return glm::vec3(ray.tex0.x + kf * ray.dtex.x, ray.tex0.y + kf * ray.dtex.y, ray.tex0.z + kf * ray.dtex.z);
    };
    auto scalar = [&](const glm::vec3& p) {
        const float u = sample_3d(tex.volume, p.x, p.y, p.z, TextureFilter::linear, tex.cpu).x;
        return u * fc.scalar_scale + fc.scalar_bias;
    };
    auto shaded = [&](glm::vec4 c, const glm::vec3& p, double t) {
        if (fc.shade) c = raycast_lit(c, raycast_light(fc, ray, t, raycast_gradient(fc, tex, p)));
        return c;
    };
    glm::vec4& acc = out.colour;
    if (!fc.preintegrate) {
        const ClassificationTable::Sampler classify = tex.classification->sampler(tex.cpu);
        for (int k = 0; k < n; ++k) {
            const glm::vec3 p = position(k);
            const glm::vec4 c = shaded(classify(scalar(p)), p, double(k) * fc.step);
            raycast_composite(acc, c);
            ++out.samples;
            if (acc.a > fc.threshold) break;
        }
        return out;
    }
    if (n == 0) return out;
    // `segment` a SegmentShader or the table's plain TableSegmentShader: the same values.
    const auto march = [&](const auto& segment) {
        float previous = scalar(position(0));
        out.samples = 1;
        for (int k = 1; k <= n; ++k) {
            const bool last = k == n;
            const glm::vec3 p = last ? ray.tex_exit : position(k);
            const float length = last ? ray.last_length : fc.step_f;
            const float x = scalar(p);
            ++out.samples;
            if (length > 0.0f) {
                const float t_z = length * fc.length_scale + fc.length_bias;
                const glm::vec4 c =
                    shaded(segment(previous, x, t_z, length), p, last ? ray.length : double(k) * fc.step);
                raycast_composite(acc, c);
            }
            previous = x;
            if (acc.a > fc.threshold) break;
        }
    };
    if (tex.table_segment)
        march(*tex.table_segment);
    else
        march(tex.segment);
    return out;
}

}  // namespace uvr::gpu
