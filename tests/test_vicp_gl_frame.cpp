// VICP on GL (OSMesa, llvmpipe) against the emulation, frame by frame (issue 6, SPEC §5 frame level): the GL frame and
// the emulated frame must be the same float32 RGBA bits at every pixel, with the same coverage and the same per-pixel
// diagnostics (fragments, ordering errors).
#include "box_mesh.h"
#include "gpu/gl_vicp.h"
#include "gl_frames.h"
#include "havs_scenes.h"
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
    return o;
}

// Renders `cam` with both backends and requires bit identity.
void require_identical(const Scene& s, const Camera& cam, int width, int height, const VicpOptions& o,
                       GlContext& ctx = osmesa(), std::size_t cells_per_draw = 0)
{
    const VicpFrame emu = VicpRenderer(s.mesh, s.topo, s.field, s.tf, o).render(cam, width, height);
    GlVicpRenderer gl(ctx, s.mesh, s.topo, s.field, s.tf, o);
    gl.set_cells_per_draw(cells_per_draw);
    const VicpFrame frame = gl.render(cam, width, height);
    const FrameDiff d = diff(frame, emu);
    INFO(cell_order_name(o.order) << ", " << width << " x " << height << ", view " << cam.eye.x << " " << cam.eye.y << " "
                             << cam.eye.z << ": " << emu.stats.fragments << " fragments (emulation), "
                             << frame.stats.fragments << " (GL), " << emu.stats.ordering_errors
                             << " ordering errors");
    INFO(d.differing << " of " << d.pixels << " pixels differ; " << d.first);
    REQUIRE(emu.stats.fragments > 0);
    if (cells_per_draw)
        CHECK(frame.stats.draws == (frame.stats.drawn_cells + cells_per_draw - 1) / cells_per_draw);
    CHECK(d.differing == 0);
    CHECK(d.coverage_differs == 0);
    CHECK(d.diagnostics_differ == 0);
    CHECK(frame.stats.fragments == emu.stats.fragments);
    CHECK(frame.stats.ordering_errors == emu.stats.ordering_errors);
}

}  // namespace

TEST_CASE("the GL VICP frame equals the emulated frame bit for bit")
{
    SECTION("the built-in torus, three views, both orders")
    {
        const Scene s = test::make_scene(load_builtin("builtin:torus-small"), 0);
        for (CellOrder order : {CellOrder::mpvonc, CellOrder::centroid})
            for (const auto& [az, el] : {std::pair{0.0, 0.0}, {35.0, 40.0}, {-70.0, 15.0}})
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
            for (const auto& [az, el] : {std::pair{0.0, 0.0}, {-40.0, 70.0}})
                require_identical(s, default_camera(mesh_bounds(s.mesh), 1.0, az, el), 256, 192, options(order));
    }
    SECTION("the Oxygen Post, with the opacity kill at the seed's 0.99")
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
    SECTION("the stream in many draws (as a mesh beyond the storage block size is drawn)")
    {
        const Scene s = test::blunt_fin();
        require_identical(s, default_camera(mesh_bounds(s.mesh), 1.0, 0.0, 0.0), 256, 192, options(CellOrder::mpvonc),
                          osmesa(), 50000);
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

TEST_CASE("VICP on GL refuses a camera inside the mesh's bounds, and --segment exact, with clear errors")
{
    const Scene s = test::make_scene(load_builtin("builtin:torus-small"), 0);
    Camera cam;
    cam.eye = mesh_bounds(s.mesh).center();
    cam.target = cam.eye + glm::dvec3(1.0, 0.0, 0.0);
    GlVicpRenderer gl(osmesa(), s.mesh, s.topo, s.field, s.tf, VicpOptions{});
    test::require_input_error([&] { gl.render(cam, 32, 32); }, {"camera is inside"});
    VicpOptions exact;
    exact.segment = SegmentMode::exact;
    test::require_input_error([&] { GlVicpRenderer(osmesa(), s.mesh, s.topo, s.field, s.tf, exact); },
                              {"--segment exact runs only in the emulation"});
}
