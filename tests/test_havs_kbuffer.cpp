// The k-buffer fragment program (the HAVS paper, Appendix II) on hand-made inputs, one behaviour per case.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <vector>

#include "gpu/havs/havs_fragment.h"
#include "gpu/havs/havs_kbuffer.h"
#include "gpu/pipeline/denormals.h"
#include "gpu/pipeline/rasterize.h"
#include "gpu/pipeline/segment.h"
#include "reference/transfer_function.h"
#include "bit_compare.h"
#include "kbuffer_cases.h"
#include "test_support.h"

using namespace uvr;
using namespace uvr::gpu;

namespace {

struct Call {
    float u_front, u_back, t_z, length;
};

// A segment shader that records its calls and returns a fixed colour, so compositing is checkable by hand.
struct Recorder {
    std::vector<Call> calls;
    glm::vec4 colour{0.25f, 0.5f, 0.125f, 0.5f};
    SegmentShader shader()
    {
        return [this](float uf, float ub, float tz, float len) {
            calls.push_back({uf, ub, tz, len});
            return colour;
        };
    }
};

HavsFrameConstants frame(float threshold = 0.99f)
{
    HavsFrameConstants fc;
    fc.threshold = threshold;
    fc.length_scale = 0.5f;
    fc.length_bias = 0.125f;
    return fc;
}

KEntry frag(float s, float d, float side = 1.0f) { return {side * (1.0f + s), d}; }

// An orthographic view of an 8 x 8 window onto eye-space x, y in [-1, 1].
HavsFrameConstants ortho_frame()
{
    HavsFrameConstants fc;
    fc.two_over_width = fc.two_over_height = 2.0 / 8.0;
    fc.origin_x = fc.origin_y = 1.0;
    return fc;
}

// A face perpendicular to the view axis at eye-space z = -4, over window [0, 16]^2 (the right triangle at the
// origin), with the scalars 0, 1, 0: its scalar is window x / 16.
HavsFace square_face()
{
    HavsFace f;
    f.q[0] = {-1.0, -1.0, -4.0};
    f.q[1] = {3.0, -1.0, -4.0};
    f.q[2] = {-1.0, 3.0, -4.0};
    f.v[0] = {0.0, 0.0};
    f.v[1] = {16.0, 0.0};
    f.v[2] = {0.0, 16.0};
    for (int j = 0; j < 3; ++j) {
        f.fx[j] = int32_t((f.v[j].x - 0.5) * 256);
        f.fy[j] = int32_t((f.v[j].y - 0.5) * 256);
        f.inv_w[j] = 1.0;
    }
    f.s[0] = 0.0;
    f.s[1] = 1.0;
    f.s[2] = 0.0;
    return f;
}

}  // namespace

TEST_CASE("k-buffer keeps the nearest entry on a tie")
{
    // Two entries at the same distance: the one already stored is taken as the front; the incoming one stays.
    Recorder rec;
    std::vector<KEntry> buf{frag(0.25f, 2.0f), frag(0.5f, 3.0f)};
    glm::vec4 fb(0.0f);
    REQUIRE(havs_kbuffer(frame(), frag(0.75f, 2.0f), buf.data(), 2, fb, rec.shader(), nullptr));
    REQUIRE(rec.calls.size() == 1);
    CHECK(rec.calls[0].u_front == 0.25f);  // the stored entry
    CHECK(rec.calls[0].u_back == 0.75f);   // the incoming one, at zero distance behind
    CHECK(rec.calls[0].length == 0.0f);
    // The incoming entry was written back, the winner discarded.
    CHECK(((buf[0].x == frag(0.75f, 2.0f).x && buf[0].y == 2.0f) || (buf[1].x == frag(0.75f, 2.0f).x && buf[1].y == 2.0f)));
}

TEST_CASE("the nearest entry is composited with the second nearest, and the rest is written back")
{
    Recorder rec;
    std::vector<KEntry> buf{frag(0.1f, 5.0f), frag(0.2f, 1.0f), frag(0.3f, 4.0f)};
    glm::vec4 fb(0.0f);
    REQUIRE(havs_kbuffer(frame(), frag(0.4f, 3.0f), buf.data(), 3, fb, rec.shader(), nullptr));
    REQUIRE(rec.calls.size() == 1);
    CHECK(rec.calls[0].u_front == Approx(0.2f));
    CHECK(rec.calls[0].u_back == Approx(0.4f));
    CHECK(rec.calls[0].length == 2.0f);
    CHECK(rec.calls[0].t_z == 2.0f * 0.5f + 0.125f);  // the paper's scale and bias
    std::vector<float> kept;
    for (const KEntry& e : buf) kept.push_back(e.y);
    std::sort(kept.begin(), kept.end());
    CHECK(kept == std::vector<float>{3.0f, 4.0f, 5.0f});
}

TEST_CASE("with no stored entry (k = 0) the program composites nothing and writes nothing")
{
    // The renderers refuse --k 0; the program itself must not read a second entry that does not exist.
    Recorder rec;
    glm::vec4 fb(0.25f, 0.25f, 0.25f, 0.5f);
    const glm::vec4 before = fb;
    KEntry none[1] = {frag(0.3f, 7.0f)};  // past the end of a k = 0 buffer: never read or written
    CHECK_FALSE(havs_kbuffer(frame(), frag(0.2f, 2.0f), none, 0, fb, rec.shader(), nullptr));
    CHECK(rec.calls.empty());
    CHECK(fb == before);
    CHECK(none[0].y == 7.0f);
}

TEST_CASE("compositing is front to back: the framebuffer gains c (1 - alpha)")
{
    Recorder rec;
    std::vector<KEntry> buf{frag(0.1f, 1.0f)};
    glm::vec4 fb(0.1f, 0.2f, 0.3f, 0.5f);
    REQUIRE(havs_kbuffer(frame(), frag(0.2f, 2.0f), buf.data(), 1, fb, rec.shader(), nullptr));
    CHECK(fb.r == 0.25f * 0.5f + 0.1f);
    CHECK(fb.g == 0.5f * 0.5f + 0.2f);
    CHECK(fb.b == 0.125f * 0.5f + 0.3f);
    CHECK(fb.a == 0.5f * 0.5f + 0.5f);
}

TEST_CASE("the opacity kill stops a fragment above the threshold and writes nothing")
{
    Recorder rec;
    std::vector<KEntry> buf{frag(0.1f, 1.0f)};
    SECTION("alpha exactly at the threshold is not killed")
    {
        glm::vec4 fb(0.0f, 0.0f, 0.0f, 0.99f);
        CHECK(havs_kbuffer(frame(0.99f), frag(0.2f, 2.0f), buf.data(), 1, fb, rec.shader(), nullptr));
    }
    SECTION("alpha one ulp above is killed: buffer and framebuffer untouched")
    {
        glm::vec4 fb(0.0f, 0.0f, 0.0f, std::nextafter(0.99f, 1.0f));
        const glm::vec4 before = fb;
        CHECK_FALSE(havs_kbuffer(frame(0.99f), frag(0.2f, 2.0f), buf.data(), 1, fb, rec.shader(), nullptr));
        CHECK(fb == before);
        CHECK(buf[0].y == 1.0f);
        CHECK(rec.calls.empty());
    }
    SECTION("threshold 1 never kills")
    {
        glm::vec4 fb(0.0f, 0.0f, 0.0f, 1.0f);
        CHECK(havs_kbuffer(frame(1.0f), frag(0.2f, 2.0f), buf.data(), 1, fb, rec.shader(), nullptr));
    }
}

TEST_CASE("a segment that starts on an exit face, an empty entry or ends on a flush is nullified")
{
    Recorder rec;
    glm::vec4 fb(0.0f);
    SECTION("exit face: a gap follows")
    {
        std::vector<KEntry> buf{frag(0.3f, 1.0f, -1.0f)};
        havs_kbuffer(frame(), frag(0.2f, 2.0f), buf.data(), 1, fb, rec.shader(), nullptr);
        CHECK(rec.calls.empty());
        CHECK(fb == glm::vec4(0.0f));
    }
    SECTION("empty entries are consumed first without a contribution")
    {
        std::vector<KEntry> buf(3, kEmptyEntry);
        for (float d : {1.0f, 2.0f, 3.0f}) havs_kbuffer(frame(), frag(0.5f, d), buf.data(), 3, fb, rec.shader(), nullptr);
        CHECK(rec.calls.empty());
        // The fourth fragment composites the first two real ones.
        havs_kbuffer(frame(), frag(0.5f, 4.0f), buf.data(), 3, fb, rec.shader(), nullptr);
        REQUIRE(rec.calls.size() == 1);
        CHECK(rec.calls[0].length == 1.0f);
    }
    SECTION("the flush passes composite what is left and nothing reaches infinity")
    {
        std::vector<KEntry> buf{frag(0.1f, 1.0f), frag(0.2f, 2.0f), frag(0.3f, 3.0f, -1.0f)};
        for (int pass = 0; pass < 3; ++pass) havs_kbuffer(frame(), kFlushFragment, buf.data(), 3, fb, rec.shader(), nullptr);
        REQUIRE(rec.calls.size() == 2);  // 1 -> 2 and 2 -> 3; the exit face's segment to the flush is nullified
        CHECK(rec.calls[0].length == 1.0f);
        CHECK(rec.calls[1].length == 1.0f);
        for (const KEntry& e : buf) CHECK(e.y == kFlushFragment.y);
    }
    SECTION("--gaps maxgap: a segment longer than the gap is nullified, exit faces are not marked")
    {
        HavsFrameConstants fc = frame();
        fc.max_gap = 1.5f;
        std::vector<KEntry> buf{frag(0.1f, 1.0f)};
        havs_kbuffer(fc, frag(0.2f, 3.0f), buf.data(), 1, fb, rec.shader(), nullptr);
        CHECK(rec.calls.empty());
        havs_kbuffer(fc, frag(0.2f, 4.0f), buf.data(), 1, fb, rec.shader(), nullptr);
        CHECK(rec.calls.size() == 1);
    }
}

TEST_CASE("an ordering error is counted when a front nearer than an earlier front is composited")
{
    Recorder rec;
    KBufferDiagnostics diag;
    std::vector<KEntry> buf{frag(0.1f, 1.0f)};
    glm::vec4 fb(0.0f);
    havs_kbuffer(frame(), frag(0.2f, 3.0f), buf.data(), 1, fb, rec.shader(), &diag);  // composites 1 -> 3
    havs_kbuffer(frame(), frag(0.2f, 2.0f), buf.data(), 1, fb, rec.shader(), &diag);  // 2 arrives too late
    CHECK(diag.ordering_errors == 1);
    CHECK(diag.fragments == 2);
    CHECK(diag.max_held == 1);
}

TEST_CASE("fragment values: a face's distance and scalar at a pixel centre")
{
    // A face perpendicular to the view axis at distance 4, seen by an orthographic camera (eye-space z = -4): every
    // pixel inside it gets distance 4, and the scalar interpolates linearly in window x.
    const HavsFrameConstants fc = ortho_frame();
    HavsFace f = square_face();
    const KEntry e = havs_fragment_entry(fc, f, 3, 2);  // pixel centre (3.5, 2.5): ndc (-0.125, -0.375)
    CHECK(e.y == Approx(4.0).epsilon(1e-6));
    CHECK(e.x == Approx(1.0 + 3.5 / 16.0).epsilon(1e-6));
    f.side = -1.0;
    CHECK(havs_fragment_entry(fc, f, 3, 2).x < 0.0f);
}

TEST_CASE("an extrapolated scalar below 0 keeps its fragment's kind: clamped to 0 before the encoding")
{
    // The face of the case above, s = 0, 1, 0: the scalar is window x / 16. Pixel (-1, 2) has its centre at x = -0.5,
    // outside the face by a weight of -1/32 (within kOutsideTolerance: the plane is extrapolated), where the scalar
    // is -1/32. Unclamped, the extrapolated fragment's x = 4 (1 - 1/32) = 3.875 would decode as an interior fragment
    // with scalar 2.875, and an entry face's 16 (1 - 1/32) = 15.5 as no entry face.
    const HavsFrameConstants fc = ortho_frame();
    HavsFace f = square_face();
    const FragmentValues v = havs_fragment_values(fc, f, -1, 2);
    REQUIRE(v.outside);
    REQUIRE_FALSE(v.snapped);
    const KEntry outside = havs_fragment_entry(fc, f, -1, 2);
    CHECK(outside.x == kSideOutside);

    SECTION("the k-buffer reads the extrapolated fragment's scalar as 0")
    {
        // The reproducer: stored {1.5, 1}, k = 1, the extrapolated fragment behind it.
        Recorder rec;
        std::vector<KEntry> buf{frag(0.5f, 1.0f)};
        glm::vec4 fb(0.0f);
        REQUIRE(havs_kbuffer(frame(), outside, buf.data(), 1, fb, rec.shader(), nullptr));
        REQUIRE(rec.calls.size() == 1);
        CHECK(rec.calls[0].u_front == 0.5f);
        CHECK(rec.calls[0].u_back == 0.0f);
    }
    SECTION("an entry face stays an entry face, and the segment that ends on it is a gap")
    {
        f.side = kSideEntry;
        const KEntry entry = havs_fragment_entry(fc, f, -1, 2);
        CHECK(entry.x == kSideEntry);
        Recorder rec;
        std::vector<KEntry> buf{frag(0.5f, 1.0f)};
        glm::vec4 fb(0.0f);
        REQUIRE(havs_kbuffer(frame(), entry, buf.data(), 1, fb, rec.shader(), nullptr));
        CHECK(rec.calls.empty());
        CHECK(fb == glm::vec4(0.0f));
    }
}

TEST_CASE("fragment values: the snapped weights are the exact integer edge functions across the largest viewport")
{
    // A triangle spanning a 16384-pixel viewport and a pixel far outside it (the snapped branch): the fixed-point
    // differences reach 2^22 and the edge functions 2^44, where a float or a rounded double would lose bits
    // (kSnappedEdgeBits). With s = (0, 0, 1) and 1 / w = 1, x = 4 (1 + e2 * (1 / (e0 + e1 + e2))) from the 64-bit
    // integer edge functions, bit for bit (4: kSideOutside, an interior face's fragment outside its triangle; the
    // scalar e2 / (e0 + e1 + e2) lies inside [0, 1], so the encoding's clamp leaves it alone).
    HavsFrameConstants fc;
    fc.two_over_width = fc.two_over_height = 2.0 / 16384.0;
    HavsFace f;
    const glm::dvec2 v[3] = {{0.7, 0.6}, {16383.3, 1.1}, {16382.9, 16383.4}};
    for (int j = 0; j < 3; ++j) {
        f.v[j] = v[j];
        f.q[j] = {v[j].x, v[j].y, -1.0};
        f.fx[j] = snap_to_fixed(float(v[j].x));
        f.fy[j] = snap_to_fixed(float(v[j].y));
        f.inv_w[j] = 1.0;
        f.s[j] = j == 2 ? 1.0 : 0.0;
    }
    const int px = 1, py = 16380;
    const FragmentValues got = havs_fragment_values(fc, f, px, py);
    REQUIRE(got.snapped);
    const int64_t cx = int64_t(px) * 256, cy = int64_t(py) * 256;
    auto edge = [&](int a, int b) {
        return (int64_t(f.fx[b]) - f.fx[a]) * (cy - f.fy[a]) - (int64_t(f.fy[b]) - f.fy[a]) * (cx - f.fx[a]);
    };
    const int64_t e0 = edge(1, 2), e1 = edge(2, 0), e2 = edge(0, 1);
    INFO("e0 " << e0 << ", e1 " << e1 << ", e2 " << e2);
    CHECK(std::llabs(e2) > (int64_t(1) << 43));  // the size the test is about
    const double expected = double(kSideOutside) * (1.0 + double(e2) * (1.0 / double(e0 + e1 + e2)));
    CHECK(got.x == expected);
}

TEST_CASE("the program for the paper's k with the table's direct path computes the run-time program's bits")
{
    // The emulated frame runs kbuffer_program::run<kPaperK, TableSegmentShader> (chains unrolled, the sample called
    // directly); havs_kbuffer, which the GL stage tests hold to GLSL's bits, is the run-time instance through
    // std::function. Both on the same random cases (ties, kills at the threshold, empty and flush entries, +inf, and
    // NaN distances), every output compared bit for bit.
    const TransferFunction tf = default_transfer_function(Range{0.0, 1.0}, 1.0);
    const SegmentIntegrator integrator(tf);
    const PreintegrationTable table = test::stage_test_table(integrator, TexelFormat::f32);
    const std::optional<TableSegmentShader> direct = table_segment_shader(&table, TextureFilter::linear);
    INFO("host has FMA3: " << host_has_fma() << " (without it no frame takes the direct path: nothing to check)");
    REQUIRE(direct.has_value() == host_has_fma());
    if (!direct) return;
    const SegmentShader through_function = segment_shader(&table, TextureFilter::linear, integrator, Range{0.0, 1.0});
    constexpr int k = kbuffer_program::kPaperK;
    constexpr std::size_t kCases = std::size_t(1) << 18;  // per section; four sections: a million in all

    const auto compare = [&](HavsFrameConstants fc, uint64_t seed) {
        fc.length_scale = table.length_scale();
        fc.length_bias = table.length_bias();
        test::KBufferGen g(seed, fc.max_gap);
        KBufferCases cs = test::make_kbuffer_cases(g, k, kCases, fc.threshold);
        for (KEntry& e : cs.entries)
            if (g.pick(64) == 0) e.y = NAN;
        test::Mismatches mm;
        uint64_t written = 0;
        const FlushDenormals llvmpipe_mxcsr;  // as the frame runs it
        for (std::size_t c = 0; c < cs.size(); ++c) {
            KEntry a[k], b[k];
            std::copy_n(cs.entries.begin() + std::ptrdiff_t(c * k), k, a);
            std::copy_n(a, k, b);
            glm::vec4 fa = cs.framebuffer[c], fb = fa;
            KBufferDiagnostics da, db;
            const bool wa = kbuffer_program::run<k>(fc, cs.incoming[c], a, k, fa, *direct, &da);
            const bool wb = havs_kbuffer(fc, cs.incoming[c], b, k, fb, through_function, &db);
            mm.check(float(wa), float(wb), c, "written");
            written += wb ? 1 : 0;
            for (int i = 0; i < k; ++i) {
                mm.check(a[i].x, b[i].x, c, "entry x");
                mm.check(a[i].y, b[i].y, c, "entry distance");
            }
            for (int ch = 0; ch < 4; ++ch) mm.check(fa[ch], fb[ch], c, "framebuffer");
            mm.check(float(da.fragments), float(db.fragments), c, "fragments");
            mm.check(float(da.max_held), float(db.max_held), c, "held");
            mm.check(float(da.ordering_errors), float(db.ordering_errors), c, "ordering errors");
            mm.check(da.last_back, db.last_back, c, "last back");
        }
        INFO(written << " of " << cs.size() << " cases written");
        CHECK(written > cs.size() / 2);
        CHECK(written < cs.size());
        mm.report("run<kPaperK> against havs_kbuffer");
    };
    HavsFrameConstants fc;
    fc.threshold = 0.99f;
    SECTION("uvr's marked entries") { compare(fc, 500); }
    SECTION("uvr's marked entries, segments longer than the gap nullified")
    {
        fc.max_gap = 0.5f;
        compare(fc, 501);
    }
    SECTION("the paper's entries")
    {
        fc.paper_entries = true;
        compare(fc, 502);
    }
    SECTION("no opacity kill")
    {
        fc.threshold = 1.0f;
        compare(fc, 503);
    }
}
