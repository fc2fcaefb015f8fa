#include "gpu/havs/havs_fragment.h"

#include "gpu/havs/havs_kbuffer.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace uvr::gpu {

FragmentValues havs_fragment_values(const HavsFrameConstants& fc, const HavsFace& f, int pix_x, int pix_y,
                                    bool covered_exactly)
{
    // Edge functions of the triangle at the pixel centre (their sum: the doubled signed area).
    const double fx = double(pix_x) + 0.5, fy = double(pix_y) + 0.5;
    const glm::dvec2* v = f.v;
    double e0 = (v[2].x - v[1].x) * (fy - v[1].y) - (v[2].y - v[1].y) * (fx - v[1].x);
    double e1 = (v[0].x - v[2].x) * (fy - v[2].y) - (v[0].y - v[2].y) * (fx - v[2].x);
    double e2 = (v[1].x - v[0].x) * (fy - v[0].y) - (v[1].y - v[0].y) * (fx - v[0].x);
    const double sum = (e0 + e1) + e2;
    const double lim = -kOutsideTolerance * sum;
    const bool inside = covered_exactly ||
                        (sum > 0.0 ? (e0 >= lim && e1 >= lim && e2 >= lim) : (e0 <= lim && e1 <= lim && e2 <= lim));
    FragmentValues out;
    out.snapped = !inside;
    out.outside = !covered_exactly &&
                  (sum > 0.0 ? (e0 < 0.0 || e1 < 0.0 || e2 < 0.0) : (e0 > 0.0 || e1 > 0.0 || e2 > 0.0));
    if (!inside) {
        // Covered only because of snapping: the snapped triangle's edge functions (fixed value 256 * p is pixel p's
        // centre), integers held in double and exact (kSnappedEdgeBits).
        const double cx = double(pix_x) * 256.0, cy = double(pix_y) * 256.0;
        auto edge = [&](int a, int b) {
            return (double(f.fx[b]) - double(f.fx[a])) * (cy - double(f.fy[a])) -
                   (double(f.fy[b]) - double(f.fy[a])) * (cx - double(f.fx[a]));
        };
        e0 = edge(1, 2);
        e1 = edge(2, 0);
        e2 = edge(0, 1);
    }
    // The float constants widen exactly to double (as the shader's double() does).
    const double w0 = e0 * double(f.inv_w[0]), w1 = e1 * double(f.inv_w[1]), w2 = e2 * double(f.inv_w[2]);
    const double inv_sum = 1.0 / ((w0 + w1) + w2);
    const double l0 = w0 * inv_sum, l1 = w1 * inv_sum, l2 = w2 * inv_sum;
    // The eye-space point, and its distance from the pixel's ray origin o = (ndc_x * ox, ndc_y * oy, 0).
    const double px = (l0 * double(f.q[0].x) + l1 * double(f.q[1].x)) + l2 * double(f.q[2].x);
    const double py = (l0 * double(f.q[0].y) + l1 * double(f.q[1].y)) + l2 * double(f.q[2].y);
    const double pz = (l0 * double(f.q[0].z) + l1 * double(f.q[1].z)) + l2 * double(f.q[2].z);
    const double ndc_x = fx * fc.two_over_width - 1.0;
    const double ndc_y = fy * fc.two_over_height - 1.0;
    const double dx = px - ndc_x * fc.origin_x, dy = py - ndc_y * fc.origin_y;
    const double distance = std::sqrt((dx * dx + dy * dy) + pz * pz);
    // The scalar, clamped to [0, 1] before encoding: the weights of a pixel outside the triangle are negative down
    // to -kOutsideTolerance, so an extrapolated scalar can leave the range, and side * (1 + s) with s < 0 would fall
    // into the range of another kind (4 (1 - 0.03) = 3.88 decodes as an interior fragment with scalar 2.88; an entry
    // face's 16 (1 - 0.01) is no entry face). Written as comparisons, so that a NaN stays NaN in both twins.
    const double s_raw = (l0 * double(f.s[0]) + l1 * double(f.s[1])) + l2 * double(f.s[2]);
    const double s = s_raw < 0.0 ? 0.0 : s_raw > 1.0 ? 1.0 : s_raw;
    const double side = f.side == kSideInterior && out.outside ? kSideOutside : f.side;
    out.x = side * (1.0 + s);
    out.distance = distance;
    return out;
}

KEntry havs_fragment_entry(const HavsFrameConstants& fc, const HavsFace& f, int pix_x, int pix_y, bool covered_exactly)
{
    // The entry as the k-buffer stores it: float32.
    const FragmentValues v = havs_fragment_values(fc, f, pix_x, pix_y, covered_exactly);
    return {float(v.x), float(v.distance)};
}

HavsVaryingPlanes havs_varying_planes(const SetupVertex sv[3], const glm::vec3 eye[3], const float s[3], float side,
                                      const TriangleSetup& ts)
{
    HavsVaryingPlanes p;
    p.setup = setup_attributes(sv, ts);
    for (int c = 0; c < 3; ++c) {
        const float value[3] = {eye[0][c], eye[1][c], eye[2][c]};
        p.smooth[c] = attribute_plane(p.setup, sv, value, Qualifier::smooth);
    }
    p.smooth[3] = attribute_plane(p.setup, sv, s, Qualifier::smooth);
    for (int c = 0; c < 3; ++c) {
        const float corner[3] = {c == 0 ? 1.0f : 0.0f, c == 1 ? 1.0f : 0.0f, c == 2 ? 1.0f : 0.0f};
        p.corner[c] = attribute_plane(p.setup, sv, corner, Qualifier::noperspective);
    }
    p.side = side;
    return p;
}

HavsVaryings havs_varyings_at(const HavsVaryingPlanes& p, int px, int py, ViewportArithmetic arith)
{
    const float factor = perspective_factor(p.setup, px, py, arith);
    float smooth[4], corner[3];
    interpolate(p.smooth, 4, Qualifier::smooth, px, py, factor, arith, smooth);
    interpolate(p.corner, 3, Qualifier::noperspective, px, py, factor, arith, corner);
    HavsVaryings v;
    v.eye = glm::vec3(smooth[0], smooth[1], smooth[2]);
    v.s = smooth[3];
    v.side = havs_paper_side(p.side, glm::vec3(corner[0], corner[1], corner[2]));
    return v;
}

float havs_paper_side(float side, const glm::vec3& corner)
{
    const bool outside = corner.x < 0.0f || corner.y < 0.0f || corner.z < 0.0f;
    return side == kSideInterior && outside ? kSideOutside : side;
}

KEntry havs_paper_entry(const HavsFrameConstants& fc, const HavsVaryings& v)
{
    // DP3 t, e, e: llvmpipe lowers the dot product to ((z * z) + (y * y)) + (x * x), unfused (lower_fdot splits it
    // from the last component; lower_ffma32 keeps multiply and add apart: docs/havs-arb.md "Compilation"), and the shader
    // writes it in that order. RSQ: inversesqrt is 1 / sqrt(t), two roundings (lp_build_rsqrt's estimate is compiled
    // out). MUL: t * rsq(t) = |e|.
    float distance;
    if (fc.orthographic) {
        distance = -v.eye.z;
    } else {
        const float zz = v.eye.z * v.eye.z, yy = v.eye.y * v.eye.y, xx = v.eye.x * v.eye.x;
        const float t = (zz + yy) + xx;
        const float root = std::sqrt(t);
        const float rsq = 1.0f / root;
        distance = t * rsq;
    }
    if (fc.paper_entries) return KEntry{v.s, distance};  // MOV a0.x, v.x
    // The scalar clamped as in havs_fragment_values (comparisons: a NaN stays NaN), then side * (1 + s) in float.
    const float s = v.s < 0.0f ? 0.0f : v.s > 1.0f ? 1.0f : v.s;
    const float one_plus_s = 1.0f + s;
    return KEntry{v.side * one_plus_s, distance};
}

bool havs_kbuffer(const HavsFrameConstants& fc, KEntry a0, KEntry* a, int k, glm::vec4& fb, const SegmentShader& shade,
                  KBufferDiagnostics* diag)
{
    return kbuffer_program::run<0>(fc, a0, a, k, fb, shade, diag);
}

void havs_flush(const HavsFrameConstants& fc, const KEntry* a, int k, glm::vec4& fb, const SegmentShader& shade,
                KBufferDiagnostics* diag)
{
    kbuffer_program::flush(fc, a, k, fb, shade, diag);
}

}  // namespace uvr::gpu
