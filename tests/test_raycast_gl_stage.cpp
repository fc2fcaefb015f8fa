// The ray caster's fragment program in GLSL (shaders/raycast_fragment.frag) against its emulation
// (gpu/raycast/raycast_fragment.cpp), bit for bit, through the ray caster's stage harness
// (gpu/raycast/gl_raycast_harness.h) under OSMesa (llvmpipe). docs/spec.md §5 (stage level): a million random inputs
// for each part of the program:
//   - the ray (double): random cameras and boxes, rays along the box's faces and parallel to its planes, eyes inside
//     and on a face, flat boxes, steps that hit the sample cap; every double compared before its rounding to float;
//   - the march (float): rays of real frames and made-up ones (entries outside the texture, last segments of no
//     length), three texel formats, both classifications, shading, thresholds at 1 and below;
//   - the lighting (double): zero and denormal gradients, a light at the sample, a half vector of zero length;
//   - the published ray (float, then double): entry and exit texels equal, along one axis, ulps apart, unwritten.
// The emulation runs with denormals flushed, as llvmpipe runs shaders and as the emulated driver runs.
#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include "bit_compare.h"
#include "case_rng.h"
#include "gl_harness.h"
#include "test_support.h"
#include "gpu/pipeline/denormals.h"
#include "gpu/raycast/gl_raycast_harness.h"
#include "gpu/pipeline/pixel_rays.h"
#include "volume_scenes.h"

using namespace uvr;
using namespace uvr::gpu;
using test::Mismatches;

namespace {

using Gl = test::GlHarness<GlRaycastHarness>;
Gl& gl(GlPlatform p) { return test::gl_harness<GlRaycastHarness>(p); }

struct Rng : test::CaseRng {
    explicit Rng(uint64_t seed) : CaseRng(seed) {}
};

// ---- the ray ----

// A frame of raycast_ray_exact: a box of dims x spacing centred on the origin, seen by a camera of one of these kinds.
enum class FrameKind { outside, inside, on_face, axis_ortho, random_constants, count };

RaycastFrameConstants random_ray_frame(Rng& r, FrameKind kind, int size)
{
    RaycastFrameConstants fc;
    // z first, in this statement and the ones below: the statements fix the order of the draws, not the compiler.
    const int nz = r.pick(6) == 0 ? 1 : 2 + r.pick(80);  // 1: a flat box
    const int ny = 2 + r.pick(80), nx = 2 + r.pick(80);
    const glm::dvec3 dims(nx, ny, nz);
    const double scales[4] = {1e-3, 0.37, 1.0, 250.0};
    const double unit = scales[r.pick(4)];
    const double hz = r.uni(0.5, 2.0), hy = r.uni(0.5, 2.0), hx = r.uni(0.5, 2.0);
    const glm::dvec3 spacing = unit * glm::dvec3(hx, hy, hz);
    const glm::dvec3 extent = (dims - 1.0) * spacing;
    fc.box_hi = 0.5 * extent;
    fc.box_lo = -fc.box_hi;
    fc.tex_scale = 1.0 / (dims * spacing);
    fc.tex_half = 0.5 / dims;
    const double smallest = std::min(spacing.x, std::min(spacing.y, spacing.z));
    switch (r.pick(4)) {
    case 0: fc.step = 0.5 * smallest; break;           // the default
    case 1: fc.step = smallest * r.uni(0.05, 3.0); break;
    case 2: fc.step = glm::length(extent) * 2.0; break;  // one sample a ray
    default: fc.step = smallest * 1e-4;                 // the cap decides
    }
    fc.max_samples = int(std::min(1e6, glm::length(extent) / fc.step)) + 2;
    if (r.pick(4) == 0) fc.max_samples = 1 + r.pick(8);
    Camera cam;
    const double radius = 0.5 * glm::length(extent) + unit;
    switch (kind) {
    case FrameKind::outside:
        cam.eye = glm::normalize(r.vec(1.0) + glm::dvec3(0, 0, 1e-3)) * radius * r.uni(1.5, 4.0);
        cam.target = r.vec(0.2 * radius);
        break;
    case FrameKind::inside:
        cam.eye = r.vec(1.0) * fc.box_hi;
        cam.target = r.vec(radius);
        break;
    case FrameKind::on_face: {
        const int axis = r.pick(3);
        cam.eye = r.vec(1.0) * fc.box_hi;
        cam.eye[axis] = r.pick(2) ? fc.box_lo[axis] : fc.box_hi[axis];
        cam.target = r.vec(radius);
        break;
    }
    case FrameKind::axis_ortho: {
        // Along an axis, the image plane's corners on the box's edges: rays parallel to two planes, some in them.
        const int axis = r.pick(3);
        cam.eye = glm::dvec3(0.0);
        cam.eye[axis] = radius * 3.0;
        cam.target = glm::dvec3(0.0);
        cam.up = axis == 1 ? glm::dvec3(0, 0, 1) : glm::dvec3(0, 1, 0);
        cam.orthographic = true;
        cam.ortho_height = 2.0 * fc.box_hi[axis == 1 ? 2 : 1];
        if (cam.ortho_height == 0.0) cam.ortho_height = unit;
        break;
    }
    default: break;
    }
    if (kind == FrameKind::random_constants) {
        // No camera: every vector drawn, some components exactly zero (rays parallel to a plane).
        static_cast<PixelRays&>(fc) = PixelRays{};
        fc.two_over_width = fc.two_over_height = 2.0 / size;
        auto maybe_zero = [&](glm::dvec3 v) {
            for (int i = 0; i < 3; ++i)
                if (r.pick(3) == 0) v[i] = 0.0;
            return v;
        };
        fc.eye = r.vec(radius * 2.0);
        fc.ray_ox = maybe_zero(r.vec(radius));
        fc.ray_oy = maybe_zero(r.vec(radius));
        fc.ray_d0 = maybe_zero(r.vec(1.0));
        fc.ray_dx = maybe_zero(r.vec(0.5));
        fc.ray_dy = maybe_zero(r.vec(0.5));
        return fc;
    }
    if (!cam.orthographic && r.pick(3) == 0) {
        cam.orthographic = true;
        cam.ortho_height = radius * r.uni(0.5, 2.5);
    }
    cam.fovy_deg = r.uni(10.0, 120.0);
    const glm::dvec3 f = glm::normalize(cam.target - cam.eye);
    if (std::abs(glm::dot(f, cam.up)) > 0.99) cam.up = glm::dvec3(1, 0, 0);
    static_cast<PixelRays&>(fc) = pixel_rays(cam, size, size, glm::dvec3(0.0));
    return fc;
}

void compare_rays(const RaycastRayExact& e, const RaycastRayExact& g, std::size_t c, Mismatches& mm)
{
    mm.check(double(e.samples), double(g.samples), c, "samples");
    mm.check(e.last_length, g.last_length, c, "last_length");
    mm.check(e.length, g.length, c, "length");
    for (int i = 0; i < 3; ++i) {
        mm.check(e.tex0[i], g.tex0[i], c, "tex0");
        mm.check(e.dtex[i], g.dtex[i], c, "dtex");
        mm.check(e.tex_exit[i], g.tex_exit[i], c, "tex_exit");
        mm.check(e.entry[i], g.entry[i], c, "entry");
        mm.check(e.dir[i], g.dir[i], c, "dir");
    }
}

// ---- the march ----

// A volume of random values (every texel a different neighbourhood for the filter), small enough that made-up rays
// cross it in tens of samples.
Volume random_volume(uint64_t seed)
{
    Rng r(seed);
    return test::grid({13, 11, 9}, {-1.0, 2.0, 0.5}, {0.5, 0.75, 1.25}, [&](const glm::dvec3&) { return r.uni(-3.0, 5.0); });
}

// A ray made up rather than computed: its entry anywhere near the texture (outside it too: CLAMP_TO_EDGE), its step
// in any direction, a last segment of full, partial, denormal, zero or negative length.
RaycastRay made_up_ray(Rng& r, float step_f)
{
    RaycastRay ray;
    ray.samples = r.pick(10) == 0 ? 0 : 1 + r.pick(40);
    ray.tex0 = {r.unif(-0.1f, 1.1f), r.unif(-0.1f, 1.1f), r.unif(-0.1f, 1.1f)};
    ray.dtex = {r.unif(-0.05f, 0.05f), r.unif(-0.05f, 0.05f), r.unif(-0.05f, 0.05f)};
    if (r.pick(5) == 0) ray.dtex[r.pick(3)] = 0.0f;
    const float frac = r.unif(0.0f, 1.0f);
    ray.tex_exit = ray.tex0 + (float(ray.samples - 1) + frac) * ray.dtex;
    switch (r.pick(6)) {
    case 0: ray.last_length = step_f; break;
    case 1: ray.last_length = 0.0f; break;
    case 2: ray.last_length = -r.unif(0.0f, step_f); break;
    case 3: ray.last_length = std::ldexp(1.0f, -130); break;  // denormal: flushed, as no length
    default: ray.last_length = step_f * r.unif(0.0f, 1.0f);
    }
    ray.length = r.uni(0.0, 100.0);
    ray.entry = r.vec(20.0);
    ray.dir = glm::normalize(r.vec(1.0) + glm::dvec3(1e-6));
    return ray;
}

struct MarchTally {
    uint64_t rays = 0, samples = 0, empty = 0, stopped = 0, ties = 0;
};

// The ray's first m steps as a ray of their own: its march composites what the full ray's does up to step m (the
// same positions and lengths; the last segment ends at sample m, a full step from the one before).
RaycastRay truncated(const RaycastFrameConstants& fc, const RaycastRay& ray, int m)
{
    RaycastRay t = ray;
    t.samples = m;
    const float mf = float(m);
    t.tex_exit = {ray.tex0.x + mf * ray.dtex.x, ray.tex0.y + mf * ray.dtex.y, ray.tex0.z + mf * ray.dtex.z};
    t.last_length = fc.step_f;
    t.length = double(m) * fc.step;
    return t;
}

// A threshold that the ray's accumulated alpha meets exactly after some step (and passes later): the comparison
// `acc.a > threshold` must keep it marching there. 0 where the ray has no such step.
float tie_threshold(RaycastFrameConstants fc, const RaycastRay& ray, const RaycastTextures& tex)
{
    fc.threshold = 1.0f;
    const float total = raycast_march(fc, ray, tex).colour.a;
    for (int m = ray.samples - 1; m >= 1; --m) {
        const float a = raycast_march(fc, truncated(fc, ray, m), tex).colour.a;
        if (a > 0.0f && a < total) return a;
    }
    return 0.0f;
}

// `count` rays over the volume's textures; with `tie`, the threshold is one a ray of the frame meets exactly (that
// ray goes first), otherwise one of a few.
void check_march(GlRaycastHarness& h, const Volume& v, const TransferFunction& tf, RaycastOptions o, bool tie, Rng& r,
                 std::size_t count, Mismatches& mm, MarchTally& t)
{
    o.table_size = 32;  // small: lookups land between texels at every level
    const RaycastVolume rv(v, tf, o);
    const Bounds b = volume_bounds(v);
    const double elevation = r.uni(-80.0, 80.0), azimuth = r.uni(-180.0, 180.0);  // in this order
    const Camera base = default_camera(b, 1.0, azimuth, elevation);
    RaycastFrameConstants fc = raycast_frame_constants(rv, base, 64, 64);
    const RaycastTextures tex = raycast_textures(rv);
    std::vector<RaycastRay> rays(count);
    const FlushDenormals as_the_renderer_runs;
    const float thresholds[4] = {0.95f, 1.0f, 0.5f, 0.05f};
    fc.threshold = thresholds[r.pick(4)];
    std::size_t first = 0;
    if (tie) {
        for (int tries = 0; tries < 4096 && first == 0; ++tries) {
            const int py = r.pick(64), px = r.pick(64);  // in this order
            const RaycastRay ray = raycast_ray(fc, px, py);
            const float a = ray.samples > 2 ? tie_threshold(fc, ray, tex) : 0.0f;
            if (a > 0.0f) fc.threshold = a, rays[first++] = ray;
        }
        REQUIRE(first == 1);
        ++t.ties;
    }
    for (std::size_t i = first; i < count; ++i) {
        if (r.pick(2) == 0) {
            rays[i] = made_up_ray(r, fc.step_f);
        } else {
            // A real ray: a pixel of the frame, or of a camera inside the volume looking anywhere.
            RaycastFrameConstants cam_fc = fc;
            if (r.pick(2) == 0) {
                Camera in = base;
                in.eye = b.center() + r.vec(0.5) * b.extent();
                in.target = in.eye + r.vec(1.0) + glm::dvec3(1e-3);
                static_cast<PixelRays&>(cam_fc) = pixel_rays(in, 64, 64, rv.origin());
            }
            const int py = r.pick(64), px = r.pick(64);  // in this order
            rays[i] = raycast_ray(cam_fc, px, py);
        }
    }
    const std::vector<RaycastResult> g = h.run_march(rv, fc, rays);
    for (std::size_t i = 0; i < count; ++i) {
        const RaycastResult e = raycast_march(fc, rays[i], tex);
        ++t.rays;
        t.samples += e.samples;
        t.empty += e.samples == 0 ? 1 : 0;
        t.stopped += e.colour.a > fc.threshold ? 1 : 0;
        mm.check(float(e.samples), float(g[i].samples), i, "samples");
        for (int ch = 0; ch < 4; ++ch) mm.check(e.colour[ch], g[i].colour[ch], i, "colour");
    }
}

// ---- the lighting ----

struct LightTally {
    uint64_t flat = 0, at_light = 0, no_half = 0;
};

RaycastFrameConstants random_light_frame(Rng& r)
{
    RaycastFrameConstants fc;
    fc.shade = 1;
    fc.light = r.vec(50.0);
    fc.ambient = r.uni(0.0, 1.0);
    fc.diffuse = r.uni(0.0, 1.0);
    fc.specular = r.uni(0.0, 1.0);
    fc.shininess = r.pick(5) == 0 ? 0 : r.pick(130);
    return fc;
}

RaycastLightCase random_light_case(Rng& r, const RaycastFrameConstants& fc)
{
    RaycastLightCase c;
    c.entry = r.vec(40.0);
    c.dir = glm::normalize(r.vec(1.0) + glm::dvec3(1e-9));
    c.t = r.uni(0.0, 60.0);
    switch (r.pick(8)) {
    case 0: c.g = glm::vec3(0.0f); break;                                      // a homogeneous region
    case 1: c.g = {std::ldexp(1.0f, -140), 0.0f, -std::ldexp(3.0f, -135)}; break;  // denormal: flushed to zero
    case 2: c.g = {r.unif(-1e-20f, 1e-20f), r.unif(-1e-20f, 1e-20f), 0.0f}; break;
    default: c.g = {r.unif(-10.0f, 10.0f), r.unif(-10.0f, 10.0f), r.unif(-10.0f, 10.0f)};
    }
    switch (r.pick(10)) {
    case 0: c.entry = fc.light, c.t = 0.0; break;                    // the sample is at the light
    case 1: c.entry = fc.light - c.dir * std::ldexp(1.0, r.pick(5)), c.t = 0.0; break;  // the light straight ahead
    default: break;
    }
    return c;
}

std::vector<RaycastLightCase> light_cases(Rng& r, const RaycastFrameConstants& fc, std::size_t count)
{
    std::vector<RaycastLightCase> cs(count);
    for (auto& c : cs) c = random_light_case(r, fc);
    return cs;
}

void compare_light(const RaycastFrameConstants& fc, const std::vector<RaycastLightCase>& cs,
                   const std::vector<glm::dvec2>& g, Mismatches& mm, LightTally& t)
{
    const FlushDenormals as_the_renderer_runs;
    for (std::size_t i = 0; i < cs.size(); ++i) {
        RaycastRay ray;
        ray.entry = cs[i].entry;
        ray.dir = cs[i].dir;
        const glm::dvec2 e = raycast_light_factors(fc, ray, cs[i].t, cs[i].g);
        const glm::dvec3 l = fc.light - (ray.entry + cs[i].t * ray.dir);
        t.flat += e == glm::dvec2(1.0, 0.0) ? 1 : 0;
        t.at_light += l == glm::dvec3(0.0) ? 1 : 0;
        t.no_half += glm::length(l) > 0.0 && glm::length(l / glm::length(l) - ray.dir) == 0.0 ? 1 : 0;
        mm.check(e.x, g[i].x, i, "ambient + diffuse");
        mm.check(e.y, g[i].y, i, "specular");
    }
}

// ---- the published ray (raycast_ray_published) ----

// A frame's constants for raycast_ray_published: the box's extent per texture unit, the step, the sample cap, and the
// box (for shading's entry).
RaycastFrameConstants random_published_frame(Rng& r)
{
    RaycastFrameConstants fc;
    // z first: the statements fix the order of the draws, not the compiler.
    const int nz = 1 + r.pick(300), ny = 1 + r.pick(300), nx = 1 + r.pick(300);
    const glm::dvec3 dims(nx, ny, nz);
    const double scales[4] = {1e-3, 0.37, 1.0, 250.0};
    const double unit = scales[r.pick(4)];
    const double hz = r.uni(0.5, 2.0), hy = r.uni(0.5, 2.0), hx = r.uni(0.5, 2.0);
    const glm::dvec3 spacing = unit * glm::dvec3(hx, hy, hz);
    fc.tex_scale = 1.0 / (dims * spacing);
    fc.tex_half = 0.5 / dims;
    fc.tex_extent = glm::vec3(dims * spacing);
    fc.box_hi = 0.5 * (dims - 1.0) * spacing;
    fc.box_lo = -fc.box_hi;
    const double smallest = std::min(spacing.x, std::min(spacing.y, spacing.z));
    switch (r.pick(4)) {
    case 0: fc.step = 0.5 * smallest; break;
    case 1: fc.step = smallest * r.uni(0.05, 3.0); break;
    case 2: fc.step = glm::length(dims * spacing) * 2.0; break;  // one sample a ray
    default: fc.step = smallest * 1e-4;                         // the cap decides
    }
    fc.step_f = float(fc.step);
    fc.max_samples = int(std::min(1e6, glm::length(dims * spacing) / fc.step)) + 2;
    if (r.pick(4) == 0) fc.max_samples = 1 + r.pick(8);
    return fc;
}

struct PublishedRayTally {
    uint64_t rays = 0, unwritten = 0, zero_length = 0, capped = 0, one_axis = 0;
};

// `count` entry and exit pairs as the box passes could write them: texture coordinates in and around [0, 1], an
// exit equal to the entry, differing in one component only or by a few ulps, and unwritten texels (alpha 0).
std::vector<glm::vec4> published_texels(Rng& r, std::size_t count)
{
    std::vector<glm::vec4> t(2 * count);
    for (std::size_t i = 0; i < count; ++i) {
        glm::vec4 f(r.unif(-0.01f, 1.01f), r.unif(-0.01f, 1.01f), r.unif(-0.01f, 1.01f), 1.0f);
        glm::vec4 b(r.unif(-0.01f, 1.01f), r.unif(-0.01f, 1.01f), r.unif(-0.01f, 1.01f), 1.0f);
        switch (r.pick(12)) {
        case 0: b = f; break;  // no length
        case 1: {              // along one axis
            b = f;
            const int a = r.pick(3);
            b[a] = r.unif(0.0f, 1.0f);
            break;
        }
        case 2:  // a few ulps apart: a length at float rounding (flushed, or one sample)
            b = f;
            for (int a = 0; a < 3; ++a) b[a] = std::nextafter(b[a], 2.0f);
            break;
        case 3: (r.pick(2) ? f : b).w = 0.0f; break;  // no entry or no exit written
        default: break;
        }
        t[2 * i] = f;
        t[2 * i + 1] = b;
    }
    return t;
}

void compare_published_rays(const RaycastFrameConstants& fc, const std::vector<glm::vec4>& texels,
                            const std::vector<RaycastRay>& g, std::size_t base, Mismatches& mm, PublishedRayTally& t)
{
    const FlushDenormals as_the_renderer_runs;
    for (std::size_t i = 0; i < g.size(); ++i) {
        const glm::vec4& f = texels[2 * i];
        const glm::vec4& b = texels[2 * i + 1];
        const RaycastRay e = raycast_ray_published(fc, f, b);
        ++t.rays;
        t.unwritten += f.w == 0.0f || b.w == 0.0f ? 1 : 0;
        t.zero_length += f.w != 0.0f && b.w != 0.0f && e.samples == 0 ? 1 : 0;
        t.capped += e.samples == fc.max_samples ? 1 : 0;
        t.one_axis += e.samples > 0 && int(f.x == b.x) + int(f.y == b.y) + int(f.z == b.z) == 2 ? 1 : 0;
        const std::size_t c = base + i;
        mm.check(double(e.samples), double(g[i].samples), c, "samples");
        mm.check(double(e.last_length), double(g[i].last_length), c, "last_length");
        mm.check(e.length, g[i].length, c, "length");
        for (int k = 0; k < 3; ++k) {
            mm.check(double(e.tex0[k]), double(g[i].tex0[k]), c, "tex0");
            mm.check(double(e.dtex[k]), double(g[i].dtex[k]), c, "dtex");
            mm.check(double(e.tex_exit[k]), double(g[i].tex_exit[k]), c, "tex_exit");
            mm.check(e.entry[k], g[i].entry[k], c, "entry");
            mm.check(e.dir[k], g[i].dir[k], c, "dir");
        }
    }
}

}  // namespace

TEST_CASE("the published ray in GLSL computes the emulation's bits from 1,048,576 entry and exit pairs")
{
    GlRaycastHarness& h = *gl(GlPlatform::osmesa).harness;
    Rng r(110);
    Mismatches mm;
    PublishedRayTally t;
    constexpr int kFrames = 64;
    const std::size_t kPairs = test::random_cases(16384);
    for (int f = 0; f < kFrames; ++f) {
        const RaycastFrameConstants fc = random_published_frame(r);
        const std::vector<glm::vec4> texels = published_texels(r, kPairs);
        compare_published_rays(fc, texels, h.run_ray_published(fc, texels), std::size_t(f) * kPairs, mm, t);
    }
    INFO(t.rays << " pairs: " << t.unwritten << " with a texel unwritten, " << t.zero_length
                << " of no length, " << t.capped << " capped, " << t.one_axis << " along one axis");
    CHECK(t.rays == kFrames * kPairs);
    CHECK(t.unwritten > test::random_cases(50000));
    CHECK(t.zero_length > test::random_cases(50000));
    CHECK(t.capped > test::random_cases(50000));
    CHECK(t.one_axis > test::random_cases(50000));
    mm.report("raycast_ray_published");
}

TEST_CASE("the ray caster's ray in GLSL computes the emulation's doubles at 1,048,576 pixels of random frames")
{
    GlRaycastHarness& h = *gl(GlPlatform::osmesa).harness;
    // Every frame, and under the sanitizers an eighth of each frame's pixels: the capped rays come from few frames
    // (those whose step is tiny or whose limit is a few samples cap nearly every ray), so fewer frames would not scale
    // the counts below by an eighth, fewer pixels of each does.
    const int kFrames = 256, kPixels = int(test::random_cases(4096)), kSize = 64, kStride = 4096 / kPixels;
    Rng r(70);
    Mismatches mm;
    uint64_t hits = 0, capped = 0, parallel = 0;
    for (int f = 0; f < kFrames; ++f) {
        const RaycastFrameConstants fc = random_ray_frame(r, FrameKind(f % int(FrameKind::count)), kSize);
        std::vector<glm::ivec2> pixels(kPixels);
        for (int i = 0; i < kPixels; ++i) {
            if (i < kPixels / 2) {  // the frame, every other row (every kStride-th of those pixels)
                const int j = i * kStride;
                pixels[std::size_t(i)] = glm::ivec2(j % kSize, (2 * j) / kSize);
                continue;
            }
            const int y = r.pick(3 * kSize) - kSize;  // around it; drawn in this order whatever the compiler
            const int x = r.pick(3 * kSize) - kSize;
            pixels[std::size_t(i)] = glm::ivec2(x, y);
        }
        const std::vector<RaycastRayExact> g = h.run_ray(fc, pixels);
        const FlushDenormals as_the_renderer_runs;
        for (std::size_t i = 0; i < pixels.size(); ++i) {
            const RaycastRayExact e = raycast_ray_exact(fc, pixels[i].x, pixels[i].y);
            hits += e.samples > 0 ? 1 : 0;
            capped += e.samples == fc.max_samples ? 1 : 0;
            parallel += e.samples > 0 && (e.dir.x == 0.0 || e.dir.y == 0.0 || e.dir.z == 0.0) ? 1 : 0;
            compare_rays(e, g[i], std::size_t(f) * kPixels + i, mm);
        }
    }
    INFO(hits << " rays hit their box, " << capped << " capped at the frame's sample limit, " << parallel
              << " parallel to a plane of it");
    CHECK(hits > test::random_cases(300000));
    CHECK(capped > test::random_cases(10000));
    CHECK(parallel > test::random_cases(10000));
    mm.report("raycast_ray_exact (double)");
}

TEST_CASE("the ray caster's march in GLSL computes the emulation's bits on 1,000,000 rays")
{
    GlRaycastHarness& h = *gl(GlPlatform::osmesa).harness;
    const Volume v = random_volume(80);
    const TransferFunction tf = default_transfer_function(volume_range(v), glm::length(volume_bounds(v).extent()));
    const test::VolumeScene neghip = test::volume_scene("vtk-data/neghip.slc");
    Rng r(81);
    Mismatches mm;
    MarchTally t;
    struct Config {
        const Volume* volume;
        const TransferFunction* tf;
        VolumeFormat format;
        bool preintegrate, shade;
        std::size_t rays;
    };
    const Config configs[] = {
        {&v, &tf, VolumeFormat::f32, false, false, 150000},      {&v, &tf, VolumeFormat::u16, false, false, 100000},
        {&v, &tf, VolumeFormat::u8, false, false, 100000},       {&v, &tf, VolumeFormat::f32, true, false, 150000},
        {&v, &tf, VolumeFormat::u8, true, false, 100000},        {&v, &tf, VolumeFormat::f32, false, true, 100000},
        {&v, &tf, VolumeFormat::u16, true, true, 100000},        {&neghip.volume, &neghip.tf, VolumeFormat::native, false, false, 100000},
        {&neghip.volume, &neghip.tf, VolumeFormat::native, true, true, 100000}};
    for (const Config& c : configs) {
        RaycastOptions o;
        o.volume_format = c.format;
        o.preintegrate = c.preintegrate;
        if (c.shade) {
            RaycastLight l;
            l.position = volume_bounds(*c.volume).hi + r.vec(5.0);
            o.light = l;
        }
        check_march(h, *c.volume, *c.tf, o, (&c - configs) % 2 == 0, r, c.rays, mm, t);
    }
    INFO(t.rays << " rays, " << t.samples << " samples, " << t.empty << " without any, " << t.stopped
                << " stopped early, " << t.ties << " passes with a threshold met exactly");
    CHECK(t.rays >= 1000000);
    CHECK(t.empty > 20000);
    CHECK(t.stopped > 20000);
    CHECK(t.ties == 5);
    mm.report("raycast_march");
}

TEST_CASE("the ray caster's lighting in GLSL computes the emulation's doubles on 1,048,576 samples")
{
    GlRaycastHarness& h = *gl(GlPlatform::osmesa).harness;
    Rng r(90);
    Mismatches mm;
    LightTally t;
    for (int f = 0; f < 16; ++f) {
        const RaycastFrameConstants fc = random_light_frame(r);
        const std::vector<RaycastLightCase> cs = light_cases(r, fc, test::random_cases(65536));
        compare_light(fc, cs, h.run_light(fc, cs), mm, t);
    }
    INFO(t.flat << " without a gradient, " << t.at_light << " at the light, " << t.no_half
                << " with a half vector of no length");
    CHECK(t.flat > test::random_cases(100000));
    CHECK(t.at_light > test::random_cases(50000));
    CHECK(t.no_half > test::random_cases(1000));
    mm.report("raycast_light_factors (double)");
}

TEST_CASE("EGL: the ray caster's stages compute the same bits through the surfaceless (or device) context")
{
    Gl& e = gl(GlPlatform::egl);
    INFO(e.ctx->info().summary());
    Rng r(100);
    Mismatches mm;
    for (int f = 0; f < int(FrameKind::count); ++f) {
        const RaycastFrameConstants fc = random_ray_frame(r, FrameKind(f), 64);
        std::vector<glm::ivec2> pixels(4096);
        for (auto& p : pixels) p = {r.pick(64), r.pick(64)};
        const std::vector<RaycastRayExact> g = e.harness->run_ray(fc, pixels);
        const FlushDenormals as_the_renderer_runs;
        for (std::size_t i = 0; i < pixels.size(); ++i)
            compare_rays(raycast_ray_exact(fc, pixels[i].x, pixels[i].y), g[i], i, mm);
    }
    const Volume v = random_volume(101);
    const TransferFunction tf = default_transfer_function(volume_range(v), glm::length(volume_bounds(v).extent()));
    MarchTally t;
    RaycastOptions o;
    o.preintegrate = true;
    check_march(*e.harness, v, tf, o, true, r, 50000, mm, t);
    LightTally lt;
    const RaycastFrameConstants fc = random_light_frame(r);
    const std::vector<RaycastLightCase> cs = light_cases(r, fc, 50000);
    compare_light(fc, cs, e.harness->run_light(fc, cs), mm, lt);
    PublishedRayTally st;
    const RaycastFrameConstants sfc = random_published_frame(r);
    const std::vector<glm::vec4> texels = published_texels(r, 50000);
    compare_published_rays(sfc, texels, e.harness->run_ray_published(sfc, texels), 0, mm, st);
    mm.report("EGL: raycast_ray_exact, raycast_march, raycast_light_factors, raycast_ray_published");
}
