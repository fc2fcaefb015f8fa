// --k all (gpu/havs/havs_pixel_sort.h): each pixel's fragments sorted once give the bits of the k-buffer program at any
// k at least the pixel's fragment count: on random fragment streams with exact ties, and on whole frames with their
// diagnostics; the options that refuse it.
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "case_rng.h"
#include "kbuffer_shade.h"
#include "gpu/havs/havs.h"
#include "gpu/havs/havs_kbuffer.h"
#include "gpu/havs/havs_pixel_sort.h"
#include "havs_convergence.h"
#include "mesh_scenes.h"
#include "reference/builtin_mesh.h"
#include "reference/error.h"
#include "test_support.h"

using namespace uvr;
using namespace uvr::gpu;

namespace {

using test::same_bits;
using test::shade_of;

// Fragment streams as the rasterizer delivers them to one pixel: every kind of entry, distances from a few values so
// that fragments tie exactly (the order at one distance is what the sorted path must get right); with `odd`, now and
// then a distance the sorted path leaves to the program (NaN, +inf, 0, a denormal, one past the flush fragment).
struct StreamGen : test::CaseRng {
    explicit StreamGen(uint64_t seed) : CaseRng(seed) {}

    std::vector<KEntry> stream(int n, bool odd, bool paper_entries)
    {
        std::vector<float> distances(std::size_t(1 + pick(n)));
        for (float& d : distances) d = unif(0.5f, 20.0f);
        std::vector<KEntry> e(static_cast<std::size_t>(n));
        for (KEntry& x : e) {
            const float s = pick(8) == 0 ? float(pick(2)) : unif(0.0f, 1.0f);
            if (paper_entries) {
                x.x = pick(4) == 0 ? paper_exit_scalar(s) : s;
            } else {
                const float sides[4] = {kSideExit, kSideInterior, kSideOutside, kSideEntry};
                x.x = sides[pick(4)] * (1.0f + s);
            }
            x.y = distances[std::size_t(pick(int(distances.size())))];
            if (odd && pick(40) == 0) {
                const float flush = paper_entries ? kPaperFlushFragment.y : kFlushFragment.y;
                const float odd_values[5] = {std::nanf(""), INFINITY, 0.0f, 1e-40f, std::nextafter(flush, INFINITY)};
                x.y = odd_values[pick(5)];
            }
        }
        return e;
    }
};

// What the k-buffer program with `k` entries makes of `stream` on one pixel: a run per fragment, then the flush.
void program(const HavsFrameConstants& fc, const std::vector<KEntry>& stream, int k, glm::vec4& fb,
             KBufferDiagnostics& d)
{
    const SegmentShader shade = shade_of;
    std::vector<KEntry> buffer(std::size_t(k), kEmptyEntry);
    for (const KEntry& e : stream) havs_kbuffer(fc, e, buffer.data(), k, fb, shade, &d);
    havs_flush(fc, buffer.data(), k, fb, shade, &d);
}

// Streams on every pixel of one 64 x 64 tile through PixelSortTile, each against the program at k = its length
// and at k = its length + `extra`. Returns how many pixels had a tie.
uint64_t check_tile(StreamGen& g, bool odd, bool paper_entries, int extra)
{
    const FlushDenormals llvmpipe_mxcsr;  // as the frame's tiles run
    constexpr int kSide = ScreenTiles::kTile;
    HavsFrameConstants fc;
    fc.threshold = g.pick(3) == 0 ? 0.99f : 1.0f;
    fc.max_gap = g.pick(3) == 0 ? g.unif(0.5f, 5.0f) : 0.0f;
    fc.length_scale = 0.05f;
    fc.length_bias = 0.5f / 128.0f;
    fc.paper_entries = paper_entries;
    std::vector<std::vector<KEntry>> streams(kSide * kSide);
    for (auto& s : streams) s = g.pick(8) == 0 ? std::vector<KEntry>{} : g.stream(1 + g.pick(40), odd, paper_entries);
    std::vector<glm::vec4> fb(streams.size(), glm::vec4(0.0f));
    std::vector<KBufferDiagnostics> diag(streams.size());
    const SegmentShader shade = shade_of;
    PixelSortTile<SegmentShader> tile(TileRect{0, kSide - 1, 0, kSide - 1}, fc, fb.data(), diag.data(), kSide, shade);
    // The fragments arrive interleaved across pixels, as a tile's triangles deliver them.
    std::vector<std::size_t> next(streams.size(), 0);
    for (bool more = true; more;) {
        more = false;
        for (std::size_t p = 0; p < streams.size(); ++p)
            if (next[p] < streams[p].size()) {
                tile(streams[p][next[p]++], int(p % kSide), int(p / kSide), false);
                more = true;
            }
    }
    tile.close();
    uint64_t ties = 0;
    for (std::size_t p = 0; p < streams.size(); ++p) {
        const int n = int(streams[p].size());
        for (int i = 0; i < n; ++i)
            for (int j = i + 1; j < n; ++j) ties += streams[p][std::size_t(i)].y == streams[p][std::size_t(j)].y;
        // k = n, and k = n + extra when that is another k.
        std::vector<int> ks{std::max(n, 1)};
        if (extra > 0) ks.push_back(n + extra);
        for (int k : ks) {
            glm::vec4 fb_program(0.0f);
            KBufferDiagnostics d_program;
            if (n > 0) program(fc, streams[p], k, fb_program, d_program);
            INFO("pixel " << p << ", " << n << " fragments, k " << k << (paper_entries ? ", the paper's entries" : "")
                          << ": alpha " << fb_program.a << " by the program, " << fb[p].a << " sorted");
            REQUIRE(same_bits(fb_program, fb[p]));
            REQUIRE(d_program.fragments == diag[p].fragments);
            REQUIRE(d_program.max_held == diag[p].max_held);
            REQUIRE(d_program.ordering_errors == diag[p].ordering_errors);
        }
    }
    return ties;
}

// A frame under --k all and under a k above its fullest pixel: images and the three diagnostics, bit for bit.
void check_frame(const test::Scene& s, const Camera& cam, HavsOptions o, int size)
{
    o.k = kEveryFragment;
    const HavsFrame all = HavsRenderer(s.mesh, s.topo, s.field, s.tf, o).render(cam, size, size);
    o.k = int(all.stats.max_fragments) + 3;
    const HavsFrame deep = HavsRenderer(s.mesh, s.topo, s.field, s.tf, o).render(cam, size, size);
    INFO("k " << o.k << ", fragments " << all.stats.fragments << ", fullest pixel " << all.stats.max_fragments);
    REQUIRE(all.stats.fragments > 0);
    CHECK(all.stats.fragments == deep.stats.fragments);
    CHECK(std::memcmp(all.image.rgba.data(), deep.image.rgba.data(), all.image.rgba.size() * sizeof(float)) == 0);
    CHECK(all.fragments == deep.fragments);
    CHECK(all.max_held == deep.max_held);
    CHECK(all.ordering_errors == deep.ordering_errors);
}

}  // namespace

TEST_CASE("k all: each pixel's sorted fragments give the program's bits at k = n and beyond")
{
    StreamGen g(2611);
    uint64_t ties = 0;
    SECTION("uvr's marked entries")
    {
        for (int t = 0; t < 6; ++t) ties += check_tile(g, false, false, 1 + g.pick(20));
    }
    SECTION("the paper's entries")
    {
        for (int t = 0; t < 6; ++t) ties += check_tile(g, false, true, 1 + g.pick(20));
    }
    INFO(ties << " tied pairs");
    CHECK(ties > 10000);
}

TEST_CASE("k all: a pixel with a distance outside the sorted path's range runs the program itself, k = n")
{
    StreamGen g(2612);
    // extra = 0: the program at k = n only (with a NaN, +inf or a distance past the flush fragment the program's
    // result may depend on k; --k all is defined as k = n there).
    for (int t = 0; t < 4; ++t) check_tile(g, true, t % 2 == 1, 0);
}

TEST_CASE("k all: frames equal a k above the fullest pixel, images and diagnostics")
{
    SECTION("the torus, the paper's pipeline, the table, early termination")
    {
        const test::Scene s = test::make_scene(load_builtin("builtin:torus-small"), 0);
        check_frame(s, default_camera(mesh_bounds(s.mesh), 1.0, 30.0, 20.0), HavsOptions{}, 96);
    }
    SECTION("the torus, every switch exact")
    {
        const test::Scene s = test::make_scene(load_builtin("builtin:torus-small"), 0);
        HavsOptions o = test::exact_havs_options(1);
        o.coverage = Coverage::exact;
        o.interpolation = InterpolationMode::exact;
        check_frame(s, default_camera(mesh_bounds(s.mesh), 1.0, 30.0, 20.0), o, 96);
    }
    SECTION("the torus, the paper's entries")
    {
        const test::Scene s = test::make_scene(load_builtin("builtin:torus-small"), 0);
        HavsOptions o;
        o.entries = EntryEncoding::paper;
        check_frame(s, default_camera(mesh_bounds(s.mesh), 1.0, 120.0, -30.0), o, 96);
    }
    SECTION("Blunt Fin, exact segments")
    {
        const test::Scene s = test::blunt_fin();
        check_frame(s, default_camera(mesh_bounds(s.mesh), 1.0), test::exact_havs_options(1), 160);
    }
}

TEST_CASE("k all with --ties facing: the Oxygen Post's seam crossed by the cell the ray leaves first")
{
    // The Oxygen Post's O-grid seam: coincident faces from either side whose points carry two scalars
    // (docs/data-model.md, docs/havs.md "k = all"). With every switch exact, the k-buffer's order at one distance
    // (arrival) leaves pixels along the seam above docs/spec.md §6's bar; back faces first (facing) removes most of
    // them. What remains are the seam's near ties (its two sides cut each quadrilateral along different diagonals, so
    // their fragments differ by an ulp or more), which no order at one distance reaches.
    constexpr double kExactMax = 2e-6;  // docs/spec.md §6's bar (bench/budget.h's kBudgetBaselineMax)
    const test::Scene s = test::oxygen_post();
    const Camera cam = default_camera(mesh_bounds(s.mesh), 1.0, 120.0, 30.0);
    HavsOptions o = test::exact_havs_options(kEveryFragment);
    o.coverage = Coverage::exact;
    o.interpolation = InterpolationMode::exact;
    const test::HavsAndReference arrival = test::havs_and_reference(s, cam, 256, 256, o);
    o.ties = TieOrder::facing;
    const HavsFrame facing = HavsRenderer(s.mesh, s.topo, s.field, s.tf, o).render(cam, 256, 256);
    const test::ImageErrors a = test::image_errors(arrival.havs.image, arrival.reference, kExactMax);
    const test::ImageErrors f = test::image_errors(facing.image, arrival.reference, kExactMax);
    INFO("pixels above the bar: arrival " << a.over << " (largest " << a.max_abs << "), facing " << f.over
                                          << " (largest " << f.max_abs << ")");
    REQUIRE(a.over > 0);
    CHECK(2 * f.over < a.over);
    CHECK(f.max_abs < a.max_abs);
}

TEST_CASE("k all: --ties facing needs --k all")
{
    const test::Scene s = test::make_scene(load_builtin("builtin:torus-small"), 0);
    HavsOptions o;
    o.ties = TieOrder::facing;
    test::require_input_error([&] { HavsRenderer(s.mesh, s.topo, s.field, s.tf, o); }, {"--ties facing needs --k all"});
}

TEST_CASE("k all: the GL and ARB backends refuse it, and the program refuses a k that is neither a count nor all")
{
    test::TempDir tmp("k_all");
    const std::string havs = "render builtin:torus-small --algo havs --out '" + tmp.file("frame.npy") + "' --k ";
    SECTION("--backend gl")
    {
        const test::CommandResult r = test::run_uvr(havs + "all --backend gl");
        INFO(r.err);
        CHECK(r.exit_code == 1);
        CHECK(r.err.find("--k all runs only in the emulation") != std::string::npos);
    }
    SECTION("--backend arb")
    {
        const test::CommandResult r = test::run_uvr(havs + "all --backend arb");
        INFO(r.err);
        CHECK(r.exit_code == 1);
        CHECK(r.err.find("not all") != std::string::npos);
    }
    SECTION("not a count")
    {
        for (const char* bad : {"0", "-3", "six", "6x", "''"}) {
            const test::CommandResult r = test::run_uvr(havs + bad);
            INFO("--k " << bad << ": " << r.err);
            CHECK(r.exit_code != 0);
            CHECK(r.err.find("--k") != std::string::npos);
        }
    }
}
