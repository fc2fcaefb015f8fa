// The ray caster's packet march (gpu/raycast/raycast_packet.h) against the march one ray at a time: every ray's
// colour and sample count, bit for bit, in every mode the packet takes.
#include <bit>
#include <cmath>
#include <vector>

#include <catch2/catch.hpp>

#include "case_rng.h"
#include "gpu/pipeline/denormals.h"
#include "gpu/raycast/raycast_packet.h"
#include "gpu/raycast/raycast_setup.h"
#include "volume_scenes.h"

using namespace uvr;
using namespace uvr::gpu;

namespace {

struct Rng : test::CaseRng {
    explicit Rng(uint64_t seed) : CaseRng(seed) {}
};

// A ray that no camera makes: texture coordinates beyond the volume on every side, steps along or across an axis,
// last segments of every kind (full, none, negative, denormal).
RaycastRay made_up_ray(Rng& r, float step_f)
{
    RaycastRay ray;
    ray.samples = r.pick(8) == 0 ? 0 : 1 + r.pick(60);
    const float z0 = r.unif(-0.2f, 1.2f), y0 = r.unif(-0.2f, 1.2f), x0 = r.unif(-0.2f, 1.2f);  // in this order
    ray.tex0 = {x0, y0, z0};
    const float dz = r.unif(-0.04f, 0.04f), dy = r.unif(-0.04f, 0.04f), dx = r.unif(-0.04f, 0.04f);
    ray.dtex = {dx, dy, dz};
    if (r.pick(4) == 0) ray.dtex[r.pick(3)] = 0.0f;
    const float frac = r.unif(0.0f, 1.0f);
    ray.tex_exit = ray.tex0 + (float(ray.samples - 1) + frac) * ray.dtex;
    const float lengths[4] = {step_f, 0.0f, -0.5f * step_f, std::ldexp(1.0f, -130)};
    ray.last_length = r.pick(2) == 0 ? lengths[r.pick(4)] : step_f * r.unif(0.0f, 1.0f);
    ray.length = double(ray.samples) * step_f;
    return ray;
}

struct Tally {
    uint64_t rays = 0, samples = 0, stopped = 0, differing = 0;
};

// The frame's rays (every pixel of a 40 x 40 view from `azimuth`, `elevation`) and as many made-up ones, in packets of
// 1 to 8, against raycast_march one ray at a time.
void check_packets(const RaycastVolume& rv, RaycastTextures tex, float threshold, double azimuth, double elevation,
                   Rng& r, Tally& t)
{
    constexpr int kSize = 40;
    RaycastFrameConstants fc =
        raycast_frame_constants(rv, default_camera(volume_bounds(rv.volume()), 1.0, azimuth, elevation), kSize, kSize);
    fc.threshold = threshold;
    REQUIRE(packet_march_applies(fc, tex));
    std::vector<RaycastRay> rays;
    for (int py = 0; py < kSize; ++py)
        for (int px = 0; px < kSize; ++px) {
            rays.push_back(raycast_ray(fc, px, py));
            rays.push_back(made_up_ray(r, fc.step_f));
        }
    const FlushDenormals as_the_renderer_runs;
    for (std::size_t first = 0; first < rays.size();) {
        const int count = std::min<int>(1 + r.pick(kPacketRays), int(rays.size() - first));
        RaycastResult packet[kPacketRays];
        raycast_march_packet(fc, &rays[first], count, tex, packet);
        for (int l = 0; l < count; ++l) {
            const RaycastResult one = raycast_march(fc, rays[first + std::size_t(l)], tex);
            bool same = one.samples == packet[l].samples;
            for (int ch = 0; ch < 4; ++ch)
                same = same && std::bit_cast<uint32_t>(one.colour[ch]) == std::bit_cast<uint32_t>(packet[l].colour[ch]);
            if (!same && t.differing == 0)
                UNSCOPED_INFO("first difference: ray " << first + std::size_t(l) << ", samples " << one.samples << " / "
                                                       << packet[l].samples << ", alpha " << one.colour.a << " / "
                                                       << packet[l].colour.a);
            ++t.rays;
            t.samples += one.samples;
            t.stopped += one.colour.a > threshold ? 1 : 0;
            t.differing += same ? 0 : 1;
        }
        first += std::size_t(count);
    }
}

}  // namespace

TEST_CASE("the packet march gives every ray the one-ray march's bits, post-classified and pre-integrated, lit or not")
{
    const struct {
        const char* file;
        VolumeFormat format;
        const char* texture;
    } volumes[] = {{"vtk-data/neghip.slc", VolumeFormat::native, "8-bit"},  // the AoS path
                   {"vtk-data/neghip.slc", VolumeFormat::u16, "16-bit"},    // 16-bit and float: the SoA path
                   {"vtk-data/hydrogen.vti", VolumeFormat::native, "float"}};
    Rng r(20261128);
    for (const auto& v : volumes) {
        const test::VolumeScene s = test::volume_scene(v.file);
        Tally t;
        const Bounds b = volume_bounds(s.volume);
        for (const bool pre : {false, true})
            for (const bool exact_segment : {false, true})
                for (const bool lit : {false, true}) {
                    if (exact_segment && !pre) continue;
                    RaycastOptions o;
                    // Blinn-Phong from a light beside the volume: the gradient's six lookups and the light per lane.
                    if (lit) o.light = RaycastLight{b.center() + 2.0 * b.extent()};
                    o.step = 0.5;
                    o.preintegrate = pre;
                    o.segment = exact_segment ? SegmentMode::exact : SegmentMode::table;
                    o.table_size = 32;  // small: lookups land between texels
                    o.volume_format = v.format;
                    const RaycastVolume rv(s.volume, s.tf, o);
                    // Both of llvmpipe's 8-bit lerps and both float lerps (fused, and not: an emulated CPU without
                    // FMA3).
                    for (const bool fma : {true, false})
                        for (const bool rounds : {true, false}) {
                            RaycastTextures tex = raycast_textures(rv);
                            tex.cpu.fma = fma;
                            tex.cpu.lerp8_rounds = rounds;
                            const float threshold = r.pick(2) == 0 ? 0.95f : 0.3f;
                            const double azimuth = r.uni(-180.0, 180.0),
                                         elevation = r.uni(-80.0, 80.0);  // in this order
                            check_packets(rv, tex, threshold, azimuth, elevation, r, t);
                        }
                }
        INFO(v.file << ", " << v.texture << " texture: " << t.rays << " rays, " << t.samples << " samples, "
                    << t.stopped << " stopped by the threshold");
        CHECK(t.differing == 0);
        // The cases reach what they are for: long rays, and rays the threshold ends.
        CHECK(t.samples > 20 * t.rays);
        CHECK(t.stopped > 100);
    }
}
