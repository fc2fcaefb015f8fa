// VICP's published programs (--interpolation gpu) in GLSL (shaders/vicp_published_vertex.vert,
// shaders/vicp_published_fragment.frag) against their emulations (gpu/vicp/vicp_published_vertex.cpp,
// gpu/vicp/vicp_published_fragment.cpp), bit for bit, through the VICP stage harness under OSMesa (llvmpipe) and EGL.
// docs/spec.md §5 (stage level), a million random inputs each:
//   - VertexProg: the vertices of random tetrahedra near and far from the eye, perspective and orthographic, each
//     vertex's ProjectTet record (the plane of its opposite face in three components, the gradient); faces the view
//     ray runs along (a distance of 1 / 0), zero gradients;
//   - FragmentProg's exit: ties, every distance <= 0, infinite and NaN distances (a face the ray runs along), zeros
//     and denormals, scalars outside [0, 1].
#include <cmath>
#include <limits>
#include <vector>

#include <glm/geometric.hpp>

#include "bit_compare.h"
#include "case_rng.h"
#include "gl_harness.h"
#include "gpu/pipeline/denormals.h"
#include "gpu/vicp/gl_vicp_harness.h"

using namespace uvr;
using namespace uvr::gpu;
using test::Mismatches;

namespace {

using Gl = test::GlHarness<GlVicpHarness>;
Gl& gl(GlPlatform p)
{
    return test::gl_harness<GlVicpHarness>(p);
}

struct Rng : test::CaseRng {
    explicit Rng(uint64_t seed) : CaseRng(seed) {}
};

struct VertexTally {
    uint64_t cases = 0, along = 0, flat_field = 0, negative = 0;
};

// The 12 records ProjectTet sends for a random tetrahedron (4 faces, 3 vertices each), relative to the eye: cells of
// sizes 1e-3 to 10 at distances 0.01 to 1000; a quarter of them with a face the view ray of some vertex runs along
// (the opposite face's plane through the eye under perspective, or containing the view direction orthographic).
void published_records(Rng& r, const VicpPublishedView& view, std::vector<VicpPublishedVertex>& out, VertexTally& t)
{
    const double sizes[4] = {1e-3, 0.1, 1.0, 10.0};
    const double size = sizes[r.pick(4)];
    const double dist = std::pow(10.0, r.uni(-2.0, 3.0));
    const glm::dvec3 centre = glm::dvec3(view.direction) * dist + r.vec(0.3 * dist);
    glm::dvec3 p[4];
    for (auto& q : p) q = centre + r.vec(size);
    if (r.pick(4) == 0) {
        // The face opposite vertex 0 made to hold vertex 0's view direction (the line from the eye through it, or the
        // orthographic direction): n . r is then 0 up to rounding, a distance of 1 / (almost) 0.
        const glm::dvec3 along = view.orthographic ? glm::dvec3(view.direction) : glm::normalize(p[0]);
        const double on_edge = r.uni(0.2, 0.8), off = r.uni(0.5, 1.5);  // in this order
        p[3] = p[1] + on_edge * (p[2] - p[1]) + off * size * along;
    }
    const double s[4] = {r.uni(0.0, 1.0), r.uni(0.0, 1.0), r.pick(5) == 0 ? 0.5 : r.uni(0.0, 1.0), r.uni(-0.1, 1.1)};
    // The gradient of the linear field through the four points (0 for a constant cell).
    const glm::dvec3 e1 = p[1] - p[0], e2 = p[2] - p[0], e3 = p[3] - p[0];
    const double det = glm::dot(e1, glm::cross(e2, e3));
    if (det == 0.0) return;
    glm::dvec3 g =
        (glm::cross(e2, e3) * (s[1] - s[0]) + glm::cross(e3, e1) * (s[2] - s[0]) + glm::cross(e1, e2) * (s[3] - s[0])) /
        det;
    if (r.pick(8) == 0) {
        g = glm::dvec3(0.0);
        ++t.flat_field;
    }
    constexpr int kFace[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
    for (const auto& f : kFace)
        for (int j = 0; j < 3; ++j) {
            const int v = f[j];
            int o[3], n = 0;
            for (int k = 0; k < 4; ++k)
                if (k != v) o[n++] = k;
            VicpPublishedVertex rec;
            rec.position = glm::vec3(p[v]);
            rec.s = float(s[v]);
            rec.gradient = glm::vec3(g);
            rec.plane = glm::vec3(vicp_published_plane(p[v], p[o[0]], p[o[1]], p[o[2]]));
            rec.index = float(j);
            out.push_back(rec);
        }
}

}  // namespace

TEST_CASE("VICP's published vertex program in GLSL computes the emulation's bits for 1,049,088 vertices")
{
    GlVicpHarness& h = *gl(GlPlatform::osmesa).harness;
    Rng r(120);
    Mismatches mm;
    VertexTally t;
    constexpr int kViews = 32;
    constexpr std::size_t kPerView = 32784;  // a multiple of 12, near 2^20 / 32
    for (int k = 0; k < kViews; ++k) {
        VicpPublishedView view;
        view.orthographic = k % 4 == 3 ? 1 : 0;
        view.direction = glm::vec3(glm::normalize(r.vec(1.0) + glm::dvec3(0, 0, -0.5)));
        std::vector<VicpPublishedVertex> cases;
        while (cases.size() < kPerView) published_records(r, view, cases, t);
        cases.resize(kPerView);
        const std::vector<VicpPublishedVaryings> g = h.run_published_vertex(view, cases);
        const FlushDenormals as_llvmpipe_runs;
        for (std::size_t i = 0; i < cases.size(); ++i) {
            const VicpPublishedVaryings e = vicp_published_vertex_program(view, cases[i]);
            const int idx = int(cases[i].index);
            ++t.cases;
            t.along += std::abs(e.distance[idx]) > 1e4f * float(glm::length(cases[i].position)) ? 1 : 0;
            t.negative += e.distance[idx] < 0.0f ? 1 : 0;
            const std::size_t c = std::size_t(k) * kPerView + i;
            mm.check(e.s, g[i].s, c, "s");
            for (int j = 0; j < 3; ++j) {
                mm.check(e.distance[j], g[i].distance[j], c, "distance");
                mm.check(e.scalar[j], g[i].scalar[j], c, "scalar");
            }
        }
    }
    INFO(t.cases << " vertices: " << t.along
                 << " with a distance beyond 1e4 times their own (a face almost along the ray), " << t.negative
                 << " with the opposite face behind, " << t.flat_field << " cells of constant scalar");
    CHECK(t.cases == 1049088u);
    CHECK(t.negative > 100000);
    CHECK(t.along > 1000);
    CHECK(t.flat_field > 10000);
    mm.report("vicp_published_vertex_program");
}

TEST_CASE("VICP's published program exit in GLSL chooses the emulation's face on 1,048,576 fragments")
{
    GlVicpHarness& h = *gl(GlPlatform::osmesa).harness;
    Rng r(130);
    const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
    const float special[8] = {0.0f, -0.0f, inf, -inf, nan, std::ldexp(1.0f, -130), -std::ldexp(1.0f, -130), 1e-30f};
    std::vector<VicpPublishedVaryings> cases(1u << 20);
    uint64_t ties = 0, none = 0, nonfinite = 0;
    for (VicpPublishedVaryings& v : cases) {
        for (int i = 0; i < 3; ++i) {
            switch (r.pick(8)) {
                case 0:
                    v.distance[i] = special[r.pick(8)];
                    break;
                case 1:
                    v.distance[i] = -r.unif(0.0f, 2.0f);
                    break;
                default:
                    v.distance[i] = r.unif(0.0f, 2.0f);
            }
            v.scalar[i] = r.unif(-0.2f, 1.2f);
        }
        if (r.pick(6) == 0) v.distance[r.pick(3)] = v.distance[(r.pick(2) + 1) % 3];  // a tie (or a copy)
        // The scalars are never denormal: the rasterizer interpolates them with denormals flushed. (Fed one, the
        // GLSL clamp passes its bits through, where the emulation's compiled clamp flushes it.)
        v.s = r.pick(10) == 0 ? special[r.pick(5)] : r.unif(-0.2f, 1.2f);
    }
    const std::vector<VicpPublishedExit> g = h.run_published_exit(cases);
    Mismatches mm;
    const FlushDenormals as_llvmpipe_runs;
    for (std::size_t c = 0; c < cases.size(); ++c) {
        const VicpPublishedExit e = vicp_published_exit(cases[c]);
        const glm::vec3& d = cases[c].distance;
        none += e.face < 0 ? 1 : 0;
        nonfinite += !std::isfinite(d.x) || !std::isfinite(d.y) || !std::isfinite(d.z) ? 1 : 0;
        ties += e.face >= 0 && ((d.x == d.y && d.x > 0.0f) || (d.y == d.z && d.y > 0.0f) || (d.x == d.z && d.x > 0.0f))
                    ? 1
                    : 0;
        mm.check(double(e.face), double(g[c].face), c, "face");
        mm.check(e.s_front, g[c].s_front, c, "s_front");
        mm.check(e.s_back, g[c].s_back, c, "s_back");
        mm.check(e.length, g[c].length, c, "length");
    }
    INFO(none << " fragments with no positive distance, " << ties << " with tied distances, " << nonfinite
              << " with an infinite or NaN distance");
    CHECK(none > 10000);
    CHECK(ties > 50000);
    CHECK(nonfinite > 50000);
    mm.report("vicp_published_exit");
}

TEST_CASE("EGL: VICP's published programs compute the same bits through the surfaceless (or device) context")
{
    Gl& e = gl(GlPlatform::egl);
    INFO(e.ctx->info().summary());
    Rng r(140);
    Mismatches mm;
    VertexTally t;
    VicpPublishedView view;
    view.direction = glm::vec3(glm::normalize(glm::dvec3(0.3, -0.2, -1.0)));
    std::vector<VicpPublishedVertex> cases;
    while (cases.size() < 49152) published_records(r, view, cases, t);
    const std::vector<VicpPublishedVaryings> g = e.harness->run_published_vertex(view, cases);
    const FlushDenormals as_llvmpipe_runs;
    for (std::size_t i = 0; i < cases.size(); ++i) {
        const VicpPublishedVaryings v = vicp_published_vertex_program(view, cases[i]);
        for (int j = 0; j < 3; ++j) {
            mm.check(v.distance[j], g[i].distance[j], i, "distance");
            mm.check(v.scalar[j], g[i].scalar[j], i, "scalar");
        }
    }
    const std::vector<VicpPublishedExit> gx = e.harness->run_published_exit(g);
    for (std::size_t i = 0; i < g.size(); ++i) {
        const VicpPublishedExit x = vicp_published_exit(g[i]);
        mm.check(x.length, gx[i].length, i, "length");
        mm.check(double(x.face), double(gx[i].face), i, "face");
    }
    mm.report("EGL: vicp_published_vertex_program, vicp_published_exit");
}
