// The ray caster on GL (OSMesa, llvmpipe) against its emulation, frame by frame (docs/spec.md §5 frame level):
// the GL frame and the emulated frame must be the same float32 RGBA bits at every pixel, with the same number of
// samples per pixel, for every volume format, both classifications, shading, early termination and the hard views.
#include "gl_frames.h"
#include "gpu/raycast/gl_raycast.h"
#include "volume_scenes.h"

using namespace uvr;
using namespace uvr::gpu;
using test::FrameDiff;
using test::osmesa;

namespace {

// One llvmpipe tile (64 x 64 pixels) for most frames; kLargeSize covers 4 x 4 tiles, so that the binning of the box's
// faces across tiles and the tiles' order are compared too.
constexpr int kSize = 64;
constexpr int kLargeSize = 256;

RaycastOptions options(bool preintegrate = false, VolumeFormat format = VolumeFormat::native,
                       InterpolationMode mode = InterpolationMode::gpu)
{
    RaycastOptions o;
    o.preintegrate = preintegrate;
    o.volume_format = format;
    o.interpolation = mode;
    return o;
}

// Returns the emulated frame's statistics, for the callers' own checks.
RaycastStats require_identical(const Volume& v, const TransferFunction& tf, const Camera& cam, const RaycastOptions& o,
                               GlContext& ctx = osmesa(), int size = kSize)
{
    const RaycastFrame emu = RaycastRenderer(v, tf, o).render(cam, size, size);
    GlRaycastRenderer gl(ctx, v, tf, o);
    const RaycastFrame frame = gl.render(cam, size, size);
    const FrameDiff d = test::diff_frames(
        frame.image, emu.image, [&](std::size_t p) { return frame.samples[p] != emu.samples[p]; },
        [&](std::size_t p) {
            return "; samples GL " + std::to_string(frame.samples[p]) + ", emulation " + std::to_string(emu.samples[p]);
        });
    INFO(v.source << ", texture " << texel_format_name(gl.cpu_stage().texel_format())
                  << (o.preintegrate ? ", pre-integrated" : ", post-classified") << (o.light ? ", shaded" : "")
                  << (o.interpolation == InterpolationMode::gpu ? ", the published passes" : ", exact interpolation")
                  << ", threshold " << o.threshold << ", eye " << cam.eye.x << " " << cam.eye.y << " " << cam.eye.z
                  << ": " << emu.stats.samples << " samples (emulation), " << frame.stats.samples << " (GL)");
    INFO(d.differing << " of " << d.pixels << " pixels differ; " << d.first);
    REQUIRE(emu.stats.samples > 0);
    CHECK(d.differing == 0);
    CHECK(d.coverage_differs == 0);
    CHECK(d.diagnostics_differ == 0);
    CHECK(frame.stats.samples == emu.stats.samples);
    // The published passes: one fragment a pixel in each (the depth test never decides, so the emulation need not model
    // it: docs/raycast.md, "The published passes"), and an exit wherever there is an entry.
    CHECK(emu.stats.overlaps == 0);
    CHECK(emu.stats.unpaired == 0);
    CHECK(emu.stats.gpu_clipped == 0);
    return emu.stats;
}

RaycastLight light_beside(const Volume& v)
{
    const Bounds b = volume_bounds(v);
    RaycastLight l;
    l.position = b.hi + b.extent();
    return l;
}

}  // namespace

TEST_CASE("ray caster on GL equals its emulation on the shared volumes")
{
    for (const char* rel : {"vtk-data/neghip.slc", "vtk-data/ironProt.vtk", "vtk-data/hydrogen.vti"}) {
        SECTION(rel)
        {
            for (double az : {0.0, 37.0}) {
                const test::VolumeScene s = test::volume_scene(rel, az, 23.0);
                require_identical(s.volume, s.tf, s.camera, options(false));
                require_identical(s.volume, s.tf, s.camera, options(true));
                const VolumeFormat native = VolumeFormat::native;
                require_identical(s.volume, s.tf, s.camera, options(false, native, InterpolationMode::exact));
                require_identical(s.volume, s.tf, s.camera, options(true, native, InterpolationMode::exact));
            }
        }
    }
}

TEST_CASE("ray caster on GL equals its emulation at 256 x 256 pixels, across llvmpipe's tiles")
{
    const test::VolumeScene s = test::volume_scene("vtk-data/neghip.slc", 37.0, 23.0);
    for (bool preintegrate : {false, true}) {
        const RaycastStats st =
            require_identical(s.volume, s.tf, s.camera, options(preintegrate), osmesa(), kLargeSize);
        CHECK(st.samples > std::uint64_t(kLargeSize) * kLargeSize);  // the volume fills most of the frame
    }
}

TEST_CASE("ray caster on GL equals its emulation in every volume texture format")
{
    const test::VolumeScene s = test::volume_scene("vtk-data/neghip.slc", -50.0, 10.0);
    for (VolumeFormat f : {VolumeFormat::f32, VolumeFormat::u16, VolumeFormat::u8}) {
        SECTION(std::string("format ") + std::to_string(int(f)))
        {
            require_identical(s.volume, s.tf, s.camera, options(false, f));
            require_identical(s.volume, s.tf, s.camera, options(true, f));
        }
    }
}

TEST_CASE("ray caster on GL equals its emulation with shading and without early termination")
{
    const test::VolumeScene s = test::volume_scene("vtk-data/neghip.slc", 20.0, 30.0);
    RaycastOptions o = options(false);
    o.light = light_beside(s.volume);
    SECTION("shaded, post-classified") { require_identical(s.volume, s.tf, s.camera, o); }
    SECTION("shaded, pre-integrated")
    {
        o.preintegrate = true;
        require_identical(s.volume, s.tf, s.camera, o);
    }
    SECTION("no early termination, a step that is not a divisor of the spacing")
    {
        o.light.reset();
        o.threshold = 1.0f;
        o.step = 0.37;
        require_identical(s.volume, s.tf, s.camera, o);
    }
}

TEST_CASE("ray caster on GL equals its emulation from inside the volume and in orthographic projection")
{
    const test::VolumeScene s = test::volume_scene("vtk-data/hydrogen.vti");
    const Bounds b = volume_bounds(s.volume);
    SECTION("camera inside")
    {
        Camera cam = s.camera;
        cam.eye = b.center() + glm::dvec3(0.1, 0.2, 0.15) * b.extent();
        cam.target = b.lo;
        // The published passes see no front face: the near plane's section is the entry.
        CHECK(require_identical(s.volume, s.tf, cam, options(false)).near_sections > 0);
        require_identical(s.volume, s.tf, cam, options(true));
        require_identical(s.volume, s.tf, cam, options(false, VolumeFormat::native, InterpolationMode::exact));
    }
    SECTION("the near plane cuts the box, the eye outside it")
    {
        // Beside a face, outside it by less than the near distance (kNearPlane of the diagonal), looking along it:
        // the near plane cuts the box's front faces, and its section covers the pixels whose rays start inside the
        // box's part in front of the plane; the clipped faces cover the rest, meeting the section on shared edges.
        for (const char* rel : {"vtk-data/hydrogen.vti", "vtk-data/neghip.slc", "vtk-data/ironProt.vtk"}) {
            const test::VolumeScene t = test::volume_scene(rel);
            const Bounds c = volume_bounds(t.volume);
            Camera cam = t.camera;
            cam.eye = glm::dvec3(c.hi.x + 1e-7 * c.extent().x, c.center().y, c.center().z + 0.3 * c.extent().z);
            cam.target = glm::dvec3(c.lo.x, c.lo.y + 0.2 * c.extent().y, c.lo.z);
            cam.fovy_deg = 100.0;
            const RaycastStats st = require_identical(t.volume, t.tf, cam, options(false));
            CHECK(st.near_sections > 0);
            CHECK(st.clipped_faces > 0);
            require_identical(t.volume, t.tf, cam, options(true));
        }
    }
    SECTION("orthographic, rays in the box's faces")
    {
        Camera cam = s.camera;
        cam.orthographic = true;
        cam.ortho_height = b.extent().y * 1.25;
        cam.eye = {b.lo.x, b.lo.y, cam.eye.z};  // the centre pixel's ray runs along an edge of the box
        cam.target = {b.lo.x, b.lo.y, b.center().z};
        require_identical(s.volume, s.tf, cam, options(false));
    }
}

TEST_CASE("ray caster on EGL equals its emulation")
{
    gpu::GlContext ctx(gpu::GlPlatform::egl);
    const test::VolumeScene s = test::volume_scene("vtk-data/neghip.slc", 10.0, -20.0);
    require_identical(s.volume, s.tf, s.camera, options(false), ctx);
    require_identical(s.volume, s.tf, s.camera, options(true), ctx);
}
