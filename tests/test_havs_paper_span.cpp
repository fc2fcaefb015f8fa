// The paper's fragment entries a row span at a time (gpu/havs/havs_paper_span.h): the fast path (eight pixels a lane
// on an AVX2 + FMA3 host) gives the bits of the per-pixel definition, havs_paper_entry of havs_varyings_at.
#include <cmath>
#include <cstring>
#include <ios>
#include <vector>

#include "case_rng.h"
#include "gpu/havs/havs_paper_span.h"
#include "gpu/pipeline/denormals.h"
#include "gpu/pipeline/interpolation.h"
#include "test_support.h"

using namespace uvr::gpu;

namespace {

// At least this many (triangle, pixel) cases per configuration, as the stage tests draw (docs/spec.md §5: a million).
constexpr std::size_t kCases = 1u << 20;

bool same(float a, float b)
{
    // NaN results (a degenerate plane's 0 / 0) are equal whatever their payload: x86 keeps the first operand's, and
    // the compiler may swap a product's operands.
    return std::memcmp(&a, &b, 4) == 0 || (std::isnan(a) && std::isnan(b));
}

struct Config {
    bool paper_entries, orthographic;
};

// Random triangles: clip positions with w from 0.05 to 20 and x, y up to 1.3 w (some beyond the framebuffer), eye
// positions near (a unit), far (1e4) or tiny (1e-3), scalars in [-0.2, 1.2] (the clamp's both sides), every side.
std::size_t compare_paths(const Config& cfg, uint64_t seed, std::size_t& differing)
{
    const FlushDenormals llvmpipe_mxcsr;
    const ViewportArithmetic arith = host_viewport_arithmetic();
    const Framebuffer fb{1024, 768, RenderTarget::fbo};
    HavsFrameConstants fc;
    fc.paper_entries = cfg.paper_entries;
    fc.orthographic = cfg.orthographic;
    uvr::test::CaseRng r(seed);
    const float sides[3] = {kSideExit, kSideInterior, kSideEntry};
    const float scales[3] = {1.0f, 1e4f, 1e-3f};
    std::size_t cases = 0;
    std::vector<KEntry> fast, slow;
    while (cases < kCases) {
        SetupVertex sv[3];
        WindowCoord win[3];
        glm::vec3 eye[3];
        float s[3];
        const float scale = scales[r.pick(3)];
        for (int v = 0; v < 3; ++v) {
            const float w = r.unif(0.05f, 20.0f);
            const float clip[4] = {r.unif(-1.3f, 1.3f) * w, r.unif(-1.3f, 1.3f) * w, r.unif(-1.0f, 1.0f) * w, w};
            sv[v] = setup_vertex(clip, fb, arith);
            win[v] = WindowCoord{sv[v].x, sv[v].y};
            eye[v] = glm::vec3(r.unif(-1.0f, 1.0f), r.unif(-1.0f, 1.0f), r.unif(-2.0f, -0.01f)) * scale;
            s[v] = r.unif(-0.2f, 1.2f);
        }
        const TriangleSetup ts = setup_triangle(win, fb);
        if (ts.empty()) continue;
        const HavsVaryingPlanes planes = havs_varying_planes(sv, eye, s, sides[r.pick(3)], ts);
        for (int py = ts.y0; py <= ts.y1 && cases < kCases; ++py) {
            int first = 0, last = -1;
            row_span(ts, py, first, last);
            if (first > last) continue;
            // Sometimes a piece of the row, as a tile cuts it: any start, any length.
            if (r.pick(3) == 0) {
                first += r.pick(last - first + 1);
                last = first + r.pick(last - first + 1);
            }
            const std::size_t n = std::size_t(last - first + 1);
            fast.assign(n, KEntry{});
            slow.assign(n, KEntry{});
            havs_paper_entries(fc, planes, py, first, last, arith, fast.data(), SpanPath::fastest);
            havs_paper_entries(fc, planes, py, first, last, arith, slow.data(), SpanPath::per_pixel);
            for (std::size_t i = 0; i < n; ++i) {
                if (!same(fast[i].x, slow[i].x) || !same(fast[i].y, slow[i].y)) {
                    if (differing++ < 5)
                        UNSCOPED_INFO(std::hexfloat << "pixel (" << first + int(i) << ", " << py << "): fast ("
                                                    << fast[i].x << ", " << fast[i].y << "), per pixel (" << slow[i].x
                                                    << ", " << slow[i].y << ")");
                }
            }
            cases += n;
        }
    }
    return cases;
}

}  // namespace

TEST_CASE("the paper's entries of a span equal those computed pixel by pixel, bit for bit")
{
    SECTION("uvr's marked entries, perspective")
    {
        std::size_t differing = 0;
        const std::size_t n = compare_paths({false, false}, 24, differing);
        INFO(differing << " of " << n << " entries differ");
        CHECK(differing == 0);
    }
    SECTION("the paper's entries, perspective")
    {
        std::size_t differing = 0;
        const std::size_t n = compare_paths({true, false}, 25, differing);
        INFO(differing << " of " << n << " entries differ");
        CHECK(differing == 0);
    }
    SECTION("marked entries, orthographic (the distance is -e.z)")
    {
        std::size_t differing = 0;
        const std::size_t n = compare_paths({false, true}, 26, differing);
        INFO(differing << " of " << n << " entries differ");
        CHECK(differing == 0);
    }
}
