// HAVS on GL (OSMesa, llvmpipe) against the emulation, frame by frame (the frame-level tests, docs/spec.md §5):
// the GL frame and the emulated frame must be the same float32 RGBA bits at every pixel, with the same coverage and the
// same diagnostics.
#include <cmath>
#include <cstring>
#include <sstream>

#include "gpu/havs/gl_havs.h"
#include "field_scenes.h"
#include "gl_frames.h"
#include "mesh_scenes.h"
#include "image_errors.h"
#include "reference/reference_renderer.h"

using namespace uvr;
using namespace uvr::gpu;
using test::FrameDiff;
using test::osmesa;
using test::Scene;

namespace {

FrameDiff diff(const HavsFrame& gl, const HavsFrame& emu)
{
    const bool diagnostics = !gl.fragments.empty();
    return test::diff_frames(
        gl.image, emu.image,
        [&](std::size_t p) {
            return diagnostics && (gl.fragments[p] != emu.fragments[p] || gl.max_held[p] != emu.max_held[p] ||
                                   gl.ordering_errors[p] != emu.ordering_errors[p]);
        },
        [&](std::size_t p) {
            return diagnostics ? "; fragments GL " + std::to_string(gl.fragments[p]) + ", emulation " +
                                     std::to_string(emu.fragments[p])
                               : std::string();
        });
}

// Renders `cam` with both backends at every k of `ks` and requires bit identity.
void require_identical(const Scene& s, const Camera& cam, int width, int height, std::initializer_list<int> ks,
                       bool diagnostics = true, GlContext& ctx = osmesa(), std::size_t faces_per_draw = 0,
                       InterpolationMode interpolation = InterpolationMode::gpu,
                       FramebufferAccess access = FramebufferAccess::automatic)
{
    for (int k : test::configurations(ks)) {
        HavsOptions o;
        o.k = k;
        o.interpolation = interpolation;
        o.table_size = test::table_side(o.table_size);
        const HavsFrame emu = HavsRenderer(s.mesh, s.topo, s.field, s.tf, o).render(cam, width, height);
        GlHavsRenderer gl(ctx, s.mesh, s.topo, s.field, s.tf, o, diagnostics, access);
        gl.set_faces_per_draw(faces_per_draw);
        const HavsFrame frame = gl.render(cam, width, height);
        const FrameDiff d = diff(frame, emu);
        INFO("k = " << k << ", " << width << " x " << height << ", view " << cam.eye.x << " " << cam.eye.y << " "
                    << cam.eye.z << ": " << emu.stats.fragments << " fragments (emulation), " << frame.stats.fragments
                    << " (GL), " << emu.stats.ordering_errors << " ordering errors");
        INFO(d.differing << " of " << d.pixels << " pixels differ; " << d.first);
        REQUIRE(emu.stats.fragments > 0);
        if (faces_per_draw) CHECK(frame.stats.draws == (frame.stats.triangles + faces_per_draw - 1) / faces_per_draw);
        // The clip stage left the GPU nothing to clip: the draw module's own clipping would not match the emulation.
        CHECK(emu.stats.gpu_clipped == 0);
        CHECK(d.differing == 0);
        CHECK(d.coverage_differs == 0);
        if (diagnostics) {
            CHECK(d.diagnostics_differ == 0);
            CHECK(frame.stats.fragments == emu.stats.fragments);
            CHECK(frame.stats.ordering_errors == emu.stats.ordering_errors);
        }
    }
}

}  // namespace

TEST_CASE("the GL HAVS frame equals the emulated frame bit for bit")
{
    const int kmax = GlHavsRenderer::max_k(osmesa().info(), true);
    SECTION("the built-in torus")
    {
        const Scene s = test::make_scene(load_builtin("builtin:torus-small"), 0);
        for (const auto& [az, el] : test::views({std::pair{0.0, 0.0}, {35.0, 40.0}}))
            require_identical(s, default_camera(mesh_bounds(s.mesh), 1.0, az, el), 160, 120, {1, 2, 6, kmax});
    }
    SECTION("the built-in torus at full resolution")
    {
        const Scene s = test::make_scene(load_builtin("builtin:torus"), 0);
        require_identical(s, default_camera(mesh_bounds(s.mesh), 1.0, -70.0, 15.0), 256, 256, {1, 2, 6, kmax});
    }
    SECTION("Blunt Fin")
    {
        const Scene s = test::blunt_fin();
        for (const auto& [az, el] : test::views({std::pair{0.0, 0.0}, {-40.0, 70.0}}))
            require_identical(s, default_camera(mesh_bounds(s.mesh), 1.0, az, el), 256, 192, {1, 2, 6, kmax});
    }
    SECTION("the Oxygen Post")
    {
        const Scene s = test::oxygen_post();
        for (const auto& [az, el] : test::views({std::pair{0.0, 0.0}, {60.0, -20.0}}))
            require_identical(s, default_camera(mesh_bounds(s.mesh), 1.0, az, el), 192, 256, {1, 2, 6, kmax});
    }
    SECTION("the faces in many draws (as a mesh beyond the storage block size is drawn)")
    {
        const Scene s = test::oxygen_post();
        require_identical(s, default_camera(mesh_bounds(s.mesh), 1.0, 0.0, 0.0), 192, 256, {6}, true, osmesa(), 100000);
    }
    SECTION("--interpolation exact: the flat per-face constants in double")
    {
        const Scene torus = test::make_scene(load_builtin("builtin:torus-small"), 0);
        require_identical(torus, default_camera(mesh_bounds(torus.mesh), 1.0, 35.0, 40.0), 160, 120, {1, 6}, true,
                          osmesa(), 0, InterpolationMode::exact);
        const Scene bf = test::blunt_fin();
        require_identical(bf, default_camera(mesh_bounds(bf.mesh), 1.0, -40.0, 70.0), 256, 192, {6}, true, osmesa(), 0,
                          InterpolationMode::exact);
    }
    SECTION("the k-buffer through image load/store, as on a GPU without framebuffer fetch")
    {
        // The desktop path (an interlock around imageLoad / imageStore) with the interlock compiled out: llvmpipe
        // shades one pixel's fragments in primitive order without it (docs/gl-backend.md).
        const Scene torus = test::make_scene(load_builtin("builtin:torus-small"), 0);
        require_identical(torus, default_camera(mesh_bounds(torus.mesh), 1.0, 35.0, 40.0), 160, 120, {1, 6, kmax},
                          true, osmesa(), 0, InterpolationMode::gpu, FramebufferAccess::images);
        const Scene bf = test::blunt_fin();
        require_identical(bf, default_camera(mesh_bounds(bf.mesh), 1.0, 0.0, 0.0), 256, 192, {6}, false, osmesa(), 0,
                          InterpolationMode::gpu, FramebufferAccess::images);
    }
    SECTION("fields that jump: per-cell vertex data and cell data (a jump face drawn twice, each side's scalars)")
    {
        const Scene seam = test::make_scene(test::two_cube_seam(), 0);
        require_identical(seam, default_camera(mesh_bounds(seam.mesh), 1.0, 70.0, 20.0), 96, 96, {1, 6, kmax});
        const Scene cells = test::make_scene(test::cell_data_box(), 0);
        require_identical(cells, default_camera(mesh_bounds(cells.mesh), 1.0, 30.0, 35.0), 96, 96, {2, 6, kmax});
        const Scene torus = test::make_scene(load_builtin("builtin:torus-small"), 0);
        const Scene jump = test::with_jump(torus, 0.5);
        require_identical(jump, default_camera(mesh_bounds(jump.mesh), 1.0, 35.0, 40.0), 160, 120, {6, kmax});
    }
    SECTION("k = 14: every draw buffer holds entries (no diagnostics)")
    {
        const Scene s = test::blunt_fin();
        const int k = GlHavsRenderer::max_k(osmesa().info(), false);
        REQUIRE(k == kmax + 2);
        require_identical(s, default_camera(mesh_bounds(s.mesh), 1.0, 20.0, 30.0), 200, 200, {k}, false);
    }
}

TEST_CASE("the GL HAVS frame leaves out the triangles that cover no pixel and keeps the bits of sending every one")
{
    // Blunt Fin at 256 x 192: most of its 381,355 faces are smaller than a pixel there, as at 512 x 512 (56 %).
    const Scene s = test::blunt_fin();
    const Camera cam = default_camera(mesh_bounds(s.mesh), 1.0, -40.0, 70.0);
    HavsOptions o;
    GlHavsRenderer gl(osmesa(), s.mesh, s.topo, s.field, s.tf, o, true);
    gl.set_faces_per_draw(50000);  // several draws, each with its own share left out
    const HavsFrame covered = gl.render(cam, 256, 192);
    gl.set_submission(TriangleSubmission::all);
    const HavsFrame all = gl.render(cam, 256, 192);
    INFO(covered.stats.uncovered << " of " << covered.stats.triangles << " triangles left out");
    CHECK(covered.stats.uncovered > covered.stats.triangles / 4);
    CHECK(covered.stats.uncovered < covered.stats.triangles);
    CHECK(all.stats.uncovered == 0);
    CHECK(covered.stats.draws == all.stats.draws);
    const FrameDiff d = diff(covered, all);
    INFO(d.differing << " of " << d.pixels << " pixels differ; " << d.first);
    CHECK(d.differing == 0);
    CHECK(d.coverage_differs == 0);
    CHECK(d.diagnostics_differ == 0);
    CHECK(covered.stats.fragments == all.stats.fragments);
    // The emulation's tiles skip the same triangles (its binning asks may_cover_pixel): every face through llvmpipe
    // gives its bits too.
    const HavsFrame emu = HavsRenderer(s.mesh, s.topo, s.field, s.tf, o).render(cam, 256, 192);
    const FrameDiff e = diff(all, emu);
    INFO(e.differing << " of " << e.pixels << " pixels differ from the emulation; " << e.first);
    CHECK(e.differing == 0);
    CHECK(e.diagnostics_differ == 0);
}

TEST_CASE("the GL HAVS frame through EGL equals the emulated frame bit for bit")
{
    // Without a GPU, EGL gives Mesa's software device: the same llvmpipe as OSMesa, reached another way.
    GlContext egl(GlPlatform::egl);
    INFO(egl.info().summary());
    const Scene s = test::make_scene(load_builtin("builtin:torus-small"), 0);
    require_identical(s, default_camera(mesh_bounds(s.mesh), 1.0, 35.0, 40.0), 160, 120, {6}, true, egl);
}

TEST_CASE("the GL HAVS frame converges to the reference as the table grows, as the emulated one does")
{
    // Early termination off and k large enough that no fragment arrives out of order (it need not hold all of a
    // pixel's fragments, only the local disorder): what remains is the table's error, which shrinks as it grows.
    const Scene s = test::make_scene(load_builtin("builtin:torus-small"), 0);
    const Camera cam = default_camera(mesh_bounds(s.mesh), 1.0, 10.0, 20.0);
    const RayIntegrator ri(s.mesh, s.topo, s.field, s.tf);
    ReferenceStats rs;
    const Image ref = render_reference(ri, cam, 128, 128, rs);
    HavsOptions o;
    o.k = GlHavsRenderer::max_k(osmesa().info(), true);
    o.threshold = 1.0f;
    double previous = INFINITY;
    for (int n : {64, 128, 256}) {
        o.table_size = n;
        GlHavsRenderer gl(osmesa(), s.mesh, s.topo, s.field, s.tf, o);
        const HavsFrame frame = gl.render(cam, 128, 128);
        const HavsFrame emu = HavsRenderer(s.mesh, s.topo, s.field, s.tf, o).render(cam, 128, 128);
        REQUIRE(frame.stats.ordering_errors == 0);
        const double e_gl = test::image_errors(frame.image, ref).rmse, e_emu = test::image_errors(emu.image, ref).rmse;
        INFO("table " << n << ": RMSE against the reference " << e_gl << " (GL), " << e_emu << " (emulation)");
        CHECK(e_gl == e_emu);
        CHECK(e_gl < previous);
        previous = e_gl;
    }
}

TEST_CASE("the GL HAVS frame equals the emulated frame bit for bit when the view cuts the mesh")
{
    // The clip stage's views (test_havs_clip.cpp): the near plane cuts the mesh, or the image's sides do. Without the
    // clip stage the draw module would clip these faces in float, its own way.
    const int kmax = GlHavsRenderer::max_k(osmesa().info(), true);
    // The view must cut the mesh, or the test tests nothing new.
    auto require_cuts = [](const Scene& s, const Camera& cam, bool near) {
        const HavsFrame f = HavsRenderer(s.mesh, s.topo, s.field, s.tf, HavsOptions{}).render(cam, 64, 64);
        CHECK(f.stats.clipped_faces > 0);
        CHECK((f.stats.near_sections > 0) == near);
    };
    SECTION("a camera inside a cell, on a grid vertex, on a boundary face")
    {
        require_cuts(test::box_scene(6, 0.25), test::looking({2.3, 3.1, 2.7}, {6.0, 4.0, 5.0}), true);
        require_identical(test::box_scene(6, 0.25), test::looking({2.3, 3.1, 2.7}, {6.0, 4.0, 5.0}), 96, 80,
                          {1, 6, kmax});
        require_identical(test::box_scene(6, 0.0), test::looking({3.0, 3.0, 3.0}, {6.0, 3.0, 3.0}), 96, 80, {6});
        require_identical(test::box_scene(6, 0.0), test::looking({3.2, 2.9, 0.0}, {3.0, 3.0, 6.0}), 96, 80, {6});
    }
    SECTION("orthographic, the image plane inside the mesh")
    {
        Camera cam = test::looking({2.3, 3.1, 2.7}, {6.0, 4.0, 5.0});
        cam.orthographic = true;
        cam.ortho_height = 3.0;
        require_cuts(test::box_scene(6, 0.25), cam, true);
        require_identical(test::box_scene(6, 0.25), cam, 96, 80, {6});
    }
    SECTION("Blunt Fin from inside its flow region, in one draw and in many")
    {
        const Scene s = test::blunt_fin();
        const Camera cam = test::inside_view(s);
        require_cuts(s, cam, true);
        require_identical(s, cam, 160, 128, {1, 6, kmax});
        require_identical(s, cam, 160, 128, {6}, true, osmesa(), 5000);
    }
    SECTION("the Oxygen Post, closer than its size: faces cross the image's sides")
    {
        const Scene s = test::oxygen_post();
        Camera cam = default_camera(mesh_bounds(s.mesh), 1.0, 30.0, 10.0);
        cam.eye = cam.target + 0.4 * (cam.eye - cam.target);
        require_cuts(s, cam, false);
        require_identical(s, cam, 128, 128, {6});
    }
}

TEST_CASE("HAVS on GL refuses --segment exact with a clear error")
{
    const Scene s = test::make_scene(load_builtin("builtin:torus-small"), 0);
    HavsOptions exact;
    exact.segment = SegmentMode::exact;
    test::require_input_error([&] { GlHavsRenderer(osmesa(), s.mesh, s.topo, s.field, s.tf, exact); },
                              {"--segment exact runs only in the emulation"});
}
