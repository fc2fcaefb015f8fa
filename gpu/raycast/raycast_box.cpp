#include "gpu/raycast/raycast_box.h"

#include <algorithm>
#include <array>
#include <atomic>

#include <tbb/parallel_for.h>

#include "gpu/pipeline/clip.h"
#include "gpu/pipeline/clip_position.h"
#include "gpu/pipeline/denormals.h"

namespace uvr::gpu {

namespace {

// Corner c of the box has bit 0 for x, bit 1 for y, bit 2 for z set at the high end.
glm::dvec3 corner_of(const RaycastFrameConstants& fc, int c)
{
    return {c & 1 ? fc.box_hi.x : fc.box_lo.x, c & 2 ? fc.box_hi.y : fc.box_lo.y, c & 4 ? fc.box_hi.z : fc.box_lo.z};
}

// The six faces, each counter-clockwise about its outward normal (so front-facing, GL_CCW, seen from outside), each
// starting at corner 0 or 7: split into (q0, q1, q2) and (q0, q2, q3), every face's diagonal runs through corner 0 or
// 7, which are the face triangles of the six tetrahedra around the diagonal 0-7 (kBoxTets). So the near plane's
// sections of those tetrahedra meet the clipped faces on the same edges, with the same crossings.
constexpr int kBoxFaces[6][4] = {{0, 4, 6, 2}, {7, 5, 1, 3}, {0, 1, 5, 4}, {7, 3, 2, 6}, {0, 2, 3, 1}, {7, 6, 4, 5}};
constexpr int kBoxTets[6][4] = {{0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7}, {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7}};

// Twice the signed area of a polygon's projection in normalized device coordinates (positive: counter-clockwise in GL
// window coordinates, front-facing).
double ndc_area(const std::vector<ClipVertex>& poly)
{
    double a = 0.0;
    for (std::size_t i = 0; i < poly.size(); ++i) {
        const glm::dvec4& p = poly[i].c;
        const glm::dvec4& q = poly[(i + 1) % poly.size()].c;
        a += (p.x / p.w) * (q.y / q.w) - (q.x / q.w) * (p.y / p.w);
    }
    return a;
}

}  // namespace

RaycastBoxFrame raycast_box_frame(const RaycastFrameConstants& fc, const Camera& cam, const glm::dvec3& origin,
                                  int width, int height)
{
    RaycastBoxFrame bf;
    bf.width = width;
    bf.height = height;
    const Bounds box{origin + fc.box_lo, origin + fc.box_hi};
    bf.view = view_setup(cam, width, height, box, cam.eye);
    const ClipPlanes planes = inner_clip_planes(width, height);
    const Framebuffer fbuf{width, height, RenderTarget::fbo};

    // A vertex's texture coordinate: a corner's from its sample index (texel centres), a crossing's from its position,
    // both in double and rounded once.
    const glm::dvec3 centre_from_eye = origin - cam.eye;
    auto tex_of = [&](const ClipVertex& v) {
        const glm::dvec3 p = v.id != ClipVertex::kNewVertex ? corner_of(fc, int(v.id)) : v.p - centre_from_eye;
        return glm::vec3((p - fc.box_lo) * fc.tex_scale + fc.tex_half);
    };
    std::array<ClipVertex, 8> corners;
    std::array<unsigned, 8> codes{};
    for (int c = 0; c < 8; ++c) {
        corners[std::size_t(c)] = clip_vertex(bf.view, corner_of(fc, c) + centre_from_eye, 0.0);
        corners[std::size_t(c)].id = uint32_t(c);
        codes[std::size_t(c)] = outcode(planes, corners[std::size_t(c)].c);
    }
    auto emit_fan = [&](const std::vector<ClipVertex>& poly) {
        for (std::size_t i = 1; i + 1 < poly.size(); ++i) {
            bool clipped = false;
            for (const ClipVertex* v : {&poly[0], &poly[i], &poly[i + 1]}) {
                const RaycastBoxVertex bv{glm::vec3(v->p), tex_of(*v)};
                const auto clip = vertex_position(bf.view, bv.position);
                bf.vertices.push_back(bv);
                bf.win.push_back(viewport_transform(clip.data(), fbuf));
                bf.setup.push_back(setup_vertex(clip.data(), fbuf));
                clipped = clipped || outside_gpu_frustum(clip);
            }
            if (clipped) ++bf.gpu_clipped;
        }
    };

    // The near plane's section first, where the near plane cuts the box: the entry of the rays that start inside it.
    std::vector<ClipVertex> poly, scratch;
    constexpr unsigned kNearBit = 1u << kClipNear;
    if (bf.view.near_cuts) {
        for (const auto& t : kBoxTets) {
            unsigned any = 0, all = ~0u;
            for (int c : t) any |= codes[std::size_t(c)], all &= codes[std::size_t(c)];
            if (!(any & kNearBit) || (all & kNearBit) || (all & ~kNearBit)) continue;
            const ClipVertex v[4] = {corners[std::size_t(t[0])], corners[std::size_t(t[1])],
                                     corners[std::size_t(t[2])], corners[std::size_t(t[3])]};
            near_section(bf.view, planes, v, poly);
            clip_polygon(bf.view, planes, poly, scratch, kClipLeft);
            if (poly.size() < 3) continue;
            if (ndc_area(poly) < 0.0) std::reverse(poly.begin(), poly.end());  // facing the eye
            bf.near_sections += uint32_t(poly.size() - 2);
            emit_fan(poly);
        }
    }
    // Then the faces, two triangles each: as they are inside every plane, not at all outside one, else as the fan of
    // the clipped polygon.
    for (const auto& f : kBoxFaces) {
        for (const std::array<int, 3> tri : {std::array<int, 3>{f[0], f[1], f[2]}, std::array<int, 3>{f[0], f[2], f[3]}}) {
            unsigned any = 0, all = ~0u;
            for (int c : tri) any |= codes[std::size_t(c)], all &= codes[std::size_t(c)];
            if (all != 0) {
                ++bf.culled_faces;
                continue;
            }
            poly.assign({corners[std::size_t(tri[0])], corners[std::size_t(tri[1])], corners[std::size_t(tri[2])]});
            if (any != 0) {
                ++bf.clipped_faces;
                clip_polygon(bf.view, planes, poly, scratch);
            }
            emit_fan(poly);
        }
    }
    return bf;
}

RaycastBoxPass raycast_box_pass(const RaycastBoxFrame& bf, Facing facing)
{
    RaycastBoxPass out;
    const std::size_t npix = std::size_t(bf.width) * std::size_t(bf.height);
    out.position.assign(npix, glm::vec4(0.0f));
    const Framebuffer fbuf{bf.width, bf.height, RenderTarget::fbo};
    const ViewportArithmetic arith = host_viewport_arithmetic();
    std::vector<uint8_t> written(npix, 0);
    std::atomic<uint64_t> covered{0}, overlaps{0};
    const FlushDenormals llvmpipe_mxcsr;  // llvmpipe's setup runs with denormals flushed, as its shader threads
    for (std::size_t t = 0; t < bf.triangles(); ++t) {
        const WindowCoord wv[3] = {bf.win[3 * t], bf.win[3 * t + 1], bf.win[3 * t + 2]};
        const TriangleSetup ts = setup_triangle(wv, fbuf);
        if (ts.empty() || ts.facing != facing) continue;  // culled (GL_CULL_FACE), or covering nothing
        const SetupVertex sv[3] = {bf.setup[3 * t], bf.setup[3 * t + 1], bf.setup[3 * t + 2]};
        const AttributeSetup as = setup_attributes(sv, ts);
        AttributePlane planes[3];
        for (int c = 0; c < 3; ++c) {
            const float value[3] = {bf.vertices[3 * t].tex[c], bf.vertices[3 * t + 1].tex[c],
                                    bf.vertices[3 * t + 2].tex[c]};
            planes[c] = attribute_plane(as, sv, value, Qualifier::smooth);
        }
        // Rows in parallel: a triangle covers a pixel at most once, so rows write disjoint pixels. A pixel an earlier
        // triangle wrote keeps its value (the depth test would decide there) and counts as an overlap.
        tbb::parallel_for(ts.y0, ts.y1 + 1, [&](int py) {
            const FlushDenormals row_mxcsr;  // each worker thread's own
            int first = 0, last = -1;
            row_span(ts, py, first, last);
            uint64_t row_covered = 0, row_overlaps = 0;
            for (int px = first; px <= last; ++px) {
                const std::size_t p = std::size_t(py) * std::size_t(bf.width) + std::size_t(px);
                if (written[p]) {
                    ++row_overlaps;
                    continue;
                }
                const float factor = perspective_factor(as, px, py, arith);
                float tex[3];
                interpolate(planes, 3, Qualifier::smooth, px, py, factor, arith, tex);
                out.position[p] = glm::vec4(tex[0], tex[1], tex[2], 1.0f);
                written[p] = 1;
                ++row_covered;
            }
            covered += row_covered;
            overlaps += row_overlaps;
        });
    }
    out.covered = covered;
    out.overlaps = overlaps;
    return out;
}

}  // namespace uvr::gpu
