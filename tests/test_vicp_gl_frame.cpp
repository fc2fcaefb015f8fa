// VICP on GL (OSMesa, llvmpipe) against the emulation, frame by frame (issues 6 and 25, docs/spec.md §5 frame level):
// the GL frame and the emulated frame must be the same float32 RGBA bits at every pixel, with the same coverage and the
// same per-pixel diagnostics (fragments, ordering errors), with the published programs and with the exact variant.
#include "box_mesh.h"
#include "gpu/vicp/gl_vicp.h"
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

FrameDiff diff(const VicpFrame& gl, const VicpFrame& emu)
{
    return test::diff_frames(
        gl.image, emu.image,
        [&](std::size_t p) {
            return gl.fragments[p] != emu.fragments[p] || gl.ordering_errors[p] != emu.ordering_errors[p];
        },
        [&](std::size_t p) {
            return "; fragments GL " + std::to_string(gl.fragments[p]) + ", emulation " +
                   std::to_string(emu.fragments[p]);
        });
}

VicpOptions options(CellOrder order, float threshold = 1.0f)
{
    VicpOptions o;
    o.order = order;
    o.threshold = threshold;
    o.table_size = test::table_side(o.table_size);
    return o;
}

// Renders `cam` with both backends and requires bit identity, in both interpolation modes: the published programs
// (gpu, the default) and the exact variant.
void require_identical(const Scene& s, const Camera& cam, int width, int height, VicpOptions o,
                       GlContext& ctx = osmesa(), std::size_t cells_per_draw = 0,
                       FramebufferAccess access = FramebufferAccess::automatic)
{
    for (InterpolationMode mode : {InterpolationMode::gpu, InterpolationMode::exact}) {
        o.interpolation = mode;
        const VicpFrame emu = VicpRenderer(s.mesh, s.topo, s.field, s.tf, o).render(cam, width, height);
        GlVicpRenderer gl(ctx, s.mesh, s.topo, s.field, s.tf, o, access);
        gl.set_cells_per_draw(cells_per_draw);
        const VicpFrame frame = gl.render(cam, width, height);
        const FrameDiff d = diff(frame, emu);
        INFO("--interpolation " << (mode == InterpolationMode::gpu ? "gpu" : "exact") << ", "
                                << cell_order_name(o.order) << ", " << width << " x " << height << ", view "
                                << cam.eye.x << " " << cam.eye.y << " " << cam.eye.z << ": " << emu.stats.fragments
                                << " fragments (emulation), " << frame.stats.fragments << " (GL), "
                                << emu.stats.ordering_errors << " ordering errors, " << emu.stats.clipped_cells
                                << " cut cells");
        INFO(d.differing << " of " << d.pixels << " pixels differ; " << d.first);
        REQUIRE(emu.stats.fragments > 0);
        // Without cut cells, one draw a chunk; with them, the published chunks are broken by the cut cells' exact
        // draws.
        if (cells_per_draw && (mode == InterpolationMode::exact || frame.stats.clipped_cells == 0))
            CHECK(frame.stats.draws == (frame.stats.drawn_cells + cells_per_draw - 1) / cells_per_draw);
        CHECK(d.differing == 0);
        CHECK(d.coverage_differs == 0);
        CHECK(d.diagnostics_differ == 0);
        CHECK(frame.stats.fragments == emu.stats.fragments);
        CHECK(frame.stats.ordering_errors == emu.stats.ordering_errors);
    }
}

}  // namespace

TEST_CASE("the GL VICP frame equals the emulated frame bit for bit")
{
    SECTION("the built-in torus, three views, both orders")
    {
        const Scene s = test::make_scene(load_builtin("builtin:torus-small"), 0);
        for (CellOrder order : {CellOrder::mpvonc, CellOrder::centroid})
            for (const auto& [az, el] : test::views({std::pair{0.0, 0.0}, {35.0, 40.0}, {-70.0, 15.0}}))
                require_identical(s, default_camera(mesh_bounds(s.mesh), 1.0, az, el), 160, 120, options(order));
    }
    SECTION("an orthographic view of the torus")
    {
        const Scene s = test::make_scene(load_builtin("builtin:torus-small"), 0);
        Camera cam = default_camera(mesh_bounds(s.mesh), 1.0, 20.0, 50.0);
        cam.orthographic = true;
        cam.ortho_height = 1.2 * mesh_bounds(s.mesh).extent().y;
        require_identical(s, cam, 128, 128, options(CellOrder::mpvonc));
    }
    SECTION("Blunt Fin, two views, both orders")
    {
        const Scene s = test::blunt_fin();
        for (CellOrder order : {CellOrder::mpvonc, CellOrder::centroid})
            for (const auto& [az, el] : test::views({std::pair{0.0, 0.0}, {-40.0, 70.0}}))
                require_identical(s, default_camera(mesh_bounds(s.mesh), 1.0, az, el), 256, 192, options(order));
    }
    SECTION("the Oxygen Post, with the opacity kill at the published 0.99")
    {
        const Scene s = test::oxygen_post();
        require_identical(s, default_camera(mesh_bounds(s.mesh), 1.0, 60.0, -20.0), 192, 256,
                          options(CellOrder::mpvonc, 0.99f));
    }
    SECTION("degenerate views of an unjittered grid: faces edge-on, pixel centres on grid lines")
    {
        const auto linear = [](const glm::dvec3& p) { return 0.1 * p.x + 0.2 * p.y + 0.3 * p.z; };
        const Scene s = test::make_scene(test::box_mesh(4, linear, 0.0), 0);
        for (int view = 0; view < 3; ++view) {
            Camera cam = default_camera(mesh_bounds(s.mesh), 1.0, view == 2 ? 90.0 : 0.0, view == 1 ? 89.0 : 0.0);
            if (view == 0) {
                cam.orthographic = true;
                cam.ortho_height = 9.0;
            }
            require_identical(s, cam, 81, 81, options(CellOrder::mpvonc));
        }
    }
    SECTION("fields that jump: per-cell vertex data and cell data (each cell's own values)")
    {
        const Scene seam = test::make_scene(test::two_cube_seam(), 0);
        require_identical(seam, default_camera(mesh_bounds(seam.mesh), 1.0, 70.0, 20.0), 96, 96,
                          options(CellOrder::mpvonc));
        const Scene cells = test::make_scene(test::cell_data_box(), 0);
        require_identical(cells, default_camera(mesh_bounds(cells.mesh), 1.0, 30.0, 35.0), 96, 96,
                          options(CellOrder::mpvonc));
    }
    SECTION("the stream in many draws (as a mesh beyond the storage block size is drawn)")
    {
        const Scene s = test::blunt_fin();
        require_identical(s, default_camera(mesh_bounds(s.mesh), 1.0, 0.0, 0.0), 256, 192, options(CellOrder::mpvonc),
                          osmesa(), 50000);
    }
    SECTION("the compositing through image load/store, as on a GPU without framebuffer fetch")
    {
        // The desktop route (an interlock around imageLoad / imageStore) with the interlock compiled out: llvmpipe
        // shades one pixel's fragments in primitive order without it (gpu/gl/gl_fragment_access.h).
        const Scene torus = test::make_scene(load_builtin("builtin:torus-small"), 0);
        require_identical(torus, default_camera(mesh_bounds(torus.mesh), 1.0, 35.0, 40.0), 160, 120,
                          options(CellOrder::mpvonc, 0.99f), osmesa(), 0, FramebufferAccess::images);
        const Scene s = test::blunt_fin();
        require_identical(s, default_camera(mesh_bounds(s.mesh), 1.0, 0.0, 0.0), 256, 192, options(CellOrder::mpvonc),
                          osmesa(), 0, FramebufferAccess::images);
    }
}

TEST_CASE(
    "the GL VICP frame with the published program is the same whether ProjectTet sends every face or only those that make "
    "fragments")
{
    // --send all is the published stream (four faces a cell, back faces dropped by the fragment program); covered, the
    // default, sends the faces llvmpipe's setup finds front-facing that cover a pixel (vicp_sent_faces): the same
    // fragments, so the same bits. What each sent is counted by the GL itself (a pipeline-statistics query), not by
    // the driver's own tally, and the emulation's count must agree with it.
    REQUIRE(osmesa().info().has_extension("GL_ARB_pipeline_statistics_query"));
    const Scene s = test::blunt_fin();
    const Camera cam = default_camera(mesh_bounds(s.mesh), 1.0, -40.0, 70.0);
    VicpOptions o = options(CellOrder::mpvonc);
    const VicpFrame emu = VicpRenderer(s.mesh, s.topo, s.field, s.tf, o).render(cam, 256, 192);
    GlVicpRenderer gl(osmesa(), s.mesh, s.topo, s.field, s.tf, o);
    VicpFrame covered, all;
    const uint64_t gl_covered = test::primitives_submitted(osmesa(), [&] { covered = gl.render(cam, 256, 192); });
    gl.set_submission(TriangleSubmission::all);
    const uint64_t gl_all = test::primitives_submitted(osmesa(), [&] { all = gl.render(cam, 256, 192); });
    INFO("faces sent: covered " << covered.stats.sent_faces << " (GL counted " << gl_covered << "), all "
                                << all.stats.sent_faces << " (GL counted " << gl_all << "), emulation "
                                << emu.stats.sent_faces << "; " << emu.stats.drawn_cells << " cells drawn");
    REQUIRE(covered.stats.clipped_cells == 0);  // whole cells only: every primitive is one sent face
    CHECK(gl_all == 4 * all.stats.drawn_cells);
    CHECK(gl_all == all.stats.sent_faces);
    CHECK(gl_covered == covered.stats.sent_faces);
    CHECK(emu.stats.sent_faces == gl_covered);
    // Front-facing and covering a pixel: under two faces a cell (measured 132,054 of 749,272 faces here).
    CHECK(covered.stats.sent_faces < all.stats.sent_faces / 2);
    for (const VicpFrame* f : {&covered, &all}) {
        const FrameDiff d = diff(*f, emu);
        INFO(d.differing << " of " << d.pixels << " pixels differ; " << d.first);
        CHECK(d.differing == 0);
        CHECK(d.diagnostics_differ == 0);
    }
}

TEST_CASE("the GL VICP frame through EGL equals the emulated frame bit for bit")
{
    // Without a GPU, EGL gives Mesa's software device: the same llvmpipe as OSMesa, reached another way.
    GlContext egl(GlPlatform::egl);
    INFO(egl.info().summary());
    const Scene s = test::make_scene(load_builtin("builtin:torus-small"), 0);
    require_identical(s, default_camera(mesh_bounds(s.mesh), 1.0, 35.0, 40.0), 160, 120, options(CellOrder::mpvonc),
                      egl);
}

TEST_CASE("the GL VICP frame equals the emulated frame bit for bit when the view cuts the mesh")
{
    // The clip stage's views (test_vicp.cpp, test_havs_clip.cpp): the near plane cuts the mesh, or the image's sides
    // do. The cut cells are drawn as fans between the runs of whole cells (shaders/vicp.vert).
    auto require_cuts = [](const Scene& s, const Camera& cam, bool near) {
        const VicpFrame f = VicpRenderer(s.mesh, s.topo, s.field, s.tf, VicpOptions{}).render(cam, 64, 64);
        CHECK(f.stats.clipped_cells > 0);
        CHECK(f.stats.gpu_clipped == 0);
        CHECK((f.stats.near_sections > 0) == near);
    };
    SECTION("a camera inside a cell, on a grid vertex, on a boundary face")
    {
        require_cuts(test::box_scene(6, 0.25), test::looking({2.3, 3.1, 2.7}, {6.0, 4.0, 5.0}), true);
        require_identical(test::box_scene(6, 0.25), test::looking({2.3, 3.1, 2.7}, {6.0, 4.0, 5.0}), 96, 80,
                          options(CellOrder::mpvonc));
        require_identical(test::box_scene(6, 0.0), test::looking({3.0, 3.0, 3.0}, {6.0, 3.0, 3.0}), 96, 80,
                          options(CellOrder::mpvonc));
        require_identical(test::box_scene(6, 0.0), test::looking({3.2, 2.9, 0.0}, {3.0, 3.0, 6.0}), 96, 80,
                          options(CellOrder::centroid));
    }
    SECTION("orthographic, the image plane inside the mesh")
    {
        Camera cam = test::looking({2.3, 3.1, 2.7}, {6.0, 4.0, 5.0});
        cam.orthographic = true;
        cam.ortho_height = 3.0;
        require_cuts(test::box_scene(6, 0.25), cam, true);
        require_identical(test::box_scene(6, 0.25), cam, 96, 80, options(CellOrder::mpvonc));
    }
    SECTION("Blunt Fin from inside its flow region, in one draw and in many")
    {
        const Scene s = test::blunt_fin();
        const Camera cam = test::inside_view(s);
        require_cuts(s, cam, true);
        require_identical(s, cam, 160, 128, options(CellOrder::mpvonc));
        // Chunks of 700 cells: fans at a chunk's start and end, and chunks with no cut cell.
        require_identical(s, cam, 160, 128, options(CellOrder::mpvonc), osmesa(), 700);
    }
    SECTION("the Oxygen Post, closer than its size: cells cross the image's sides")
    {
        const Scene s = test::oxygen_post();
        Camera cam = default_camera(mesh_bounds(s.mesh), 1.0, 30.0, 10.0);
        cam.eye = cam.target + 0.4 * (cam.eye - cam.target);
        require_cuts(s, cam, false);
        require_identical(s, cam, 128, 128, options(CellOrder::mpvonc, 0.99f));
    }
}

TEST_CASE("VICP on GL refuses --segment exact with a clear error")
{
    const Scene s = test::make_scene(load_builtin("builtin:torus-small"), 0);
    VicpOptions exact;
    exact.segment = SegmentMode::exact;
    test::require_input_error([&] { GlVicpRenderer(osmesa(), s.mesh, s.topo, s.field, s.tf, exact); },
                              {"--segment exact runs only in the emulation"});
}
