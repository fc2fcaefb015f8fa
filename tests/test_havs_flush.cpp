// HAVS's flush (gpu/havs/havs_fragment.h, havs_flush) against what it replaces: k runs of the k-buffer program on the
// flush fragment, bit for bit, on random k-buffer states with ties, empties, every kind of entry and k up to 1000; and
// the emulation rendering k beyond the GL limit.
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "case_rng.h"
#include "kbuffer_shade.h"
#include "gpu/havs/havs.h"
#include "gpu/havs/havs_fragment.h"
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

// Random k-buffer contents as the geometry passes leave them: real entries of every kind (exit, interior,
// extrapolated, entry) at distances drawn from a few values (ties), empty entries, sometimes a NaN distance.
struct FlushGen : test::CaseRng {
    explicit FlushGen(uint64_t seed) : CaseRng(seed) {}

    KEntry entry(const std::vector<float>& distances)
    {
        if (pick(6) == 0) return kEmptyEntry;
        const float sides[4] = {kSideExit, kSideInterior, kSideOutside, kSideEntry};
        const float s = pick(8) == 0 ? float(pick(2)) : unif(0.0f, 1.0f);
        const float x = sides[pick(4)] * (1.0f + s);
        const float y = pick(200) == 0 ? std::nanf("") : distances[std::size_t(pick(int(distances.size())))];
        return {x, y};
    }

    std::vector<KEntry> state(int k)
    {
        // Few distinct distances for many entries: ties are common.
        std::vector<float> distances(std::size_t(1 + pick(k + 1)));
        for (float& d : distances) d = unif(0.5f, 20.0f);
        std::vector<KEntry> e(static_cast<std::size_t>(k));
        for (KEntry& x : e) x = entry(distances);
        return e;
    }
};

}  // namespace

TEST_CASE("the flush composites the bits of k runs of the program on the flush fragment")
{
    const SegmentShader shade = shade_of;
    FlushGen g(2026);
    uint64_t states = 0, with_nan = 0, killed_early = 0;
    for (int k : {1, 2, 3, 6, 7, 16, 64, 255, 512, 1000}) {
        const int n = k <= 64 ? 3000 : k <= 255 ? 300 : 40;
        for (int i = 0; i < n; ++i) {
            HavsFrameConstants fc;
            fc.threshold = g.pick(3) == 0 ? 1.0f : 0.99f;
            fc.max_gap = g.pick(3) == 0 ? g.unif(0.5f, 5.0f) : 0.0f;
            fc.length_scale = 0.05f;
            fc.length_bias = 0.5f / 128.0f;
            const std::vector<KEntry> entries = g.state(k);
            const float a0 = g.pick(4) == 0 ? g.unif(0.9f, 1.0f) : g.unif(0.0f, 0.5f);
            const glm::vec4 fb0(0.5f * a0, 0.25f * a0, 0.1f * a0, a0);
            KBufferDiagnostics d0;
            d0.fragments = uint32_t(g.pick(50));
            d0.max_held = uint32_t(k);
            d0.last_back = g.pick(2) ? 0.0f : g.unif(0.5f, 20.0f);

            // The reference: k runs of the program.
            std::vector<KEntry> buffer = entries;
            glm::vec4 fb_passes = fb0;
            KBufferDiagnostics d_passes = d0;
            for (int pass = 0; pass < k; ++pass) havs_kbuffer(fc, kFlushFragment, buffer.data(), k, fb_passes, shade, &d_passes);

            glm::vec4 fb_flush = fb0;
            KBufferDiagnostics d_flush = d0;
            havs_flush(fc, entries.data(), k, fb_flush, shade, &d_flush);

            ++states;
            for (const KEntry& e : entries) with_nan += std::isnan(e.y) ? 1 : 0;
            killed_early += fb_passes.a > fc.threshold ? 1 : 0;
            INFO("k " << k << ", state " << i << ": fb " << fb_passes.r << " " << fb_passes.g << " " << fb_passes.b
                      << " " << fb_passes.a << " by the passes, " << fb_flush.r << " " << fb_flush.g << " " << fb_flush.b
                      << " " << fb_flush.a << " by the flush");
            REQUIRE(same_bits(fb_passes, fb_flush));
            REQUIRE(d_passes.ordering_errors == d_flush.ordering_errors);
            REQUIRE(d_passes.fragments == d_flush.fragments);
            REQUIRE(d_passes.max_held == d_flush.max_held);
            REQUIRE(std::memcmp(&d_passes.last_back, &d_flush.last_back, sizeof(float)) == 0);
        }
    }
    INFO(states << " states, " << with_nan << " NaN distances, " << killed_early << " killed");
    CHECK(with_nan > 0);
    CHECK(killed_early > 100);
}

TEST_CASE("the emulation renders any k: 512 and 1000 on a small mesh equal the reference and k = 255's frame")
{
    const test::Scene s = test::make_scene(load_builtin("builtin:torus-small"), 0);
    const Camera cam = default_camera(mesh_bounds(s.mesh), 1.0, 30.0, 20.0);
    const HavsFrame base = HavsRenderer(s.mesh, s.topo, s.field, s.tf, test::exact_havs_options(255)).render(cam, 64, 64);
    REQUIRE(base.stats.max_fragments <= 255u);
    const RayIntegrator ri(s.mesh, s.topo, s.field, s.tf);
    ReferenceStats rs;
    const Image ref = render_reference(ri, cam, 64, 64, rs);
    for (int k : {512, 1000}) {
        const HavsFrame f = HavsRenderer(s.mesh, s.topo, s.field, s.tf, test::exact_havs_options(k)).render(cam, 64, 64);
        const test::ImageErrors e = test::image_errors(f.image, ref, test::kConvergenceMax);
        INFO("k " << k << ": RMSE " << e.rmse << ", max " << e.max_abs);
        CHECK(e.rmse <= test::kConvergenceRmse);
        CHECK(e.max_abs <= test::kConvergenceMax);
        // More entries than fragments on any pixel: every fragment is held until the flush, which composites them
        // in the same order whatever k is.
        CHECK(std::memcmp(f.image.rgba.data(), base.image.rgba.data(), base.image.rgba.size() * sizeof(float)) == 0);
    }
}

TEST_CASE("a k whose k-buffer would not fit in memory is refused before any work, with the sizes in the message")
{
    const test::Scene s = test::make_scene(load_builtin("builtin:torus-small"), 0);
    const HavsRenderer havs(s.mesh, s.topo, s.field, s.tf, test::exact_havs_options(1 << 30));
    const Camera cam = default_camera(mesh_bounds(s.mesh), 1.0);
    try {
        havs.render(cam, 4096, 4096);
        FAIL("a k-buffer of 2^30 entries a pixel at 4096x4096 was not refused");
    } catch (const InputError& e) {
        INFO(e.what());
        CHECK(std::string(e.what()).find("GiB") != std::string::npos);
    }
}
