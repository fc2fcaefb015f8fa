// VICP emulated against the ground truth: the exact configuration equals the reference, the centroid
// order's error is measured, degenerate geometry gives finite, complete images, and visibility cycles are reported.
#include <cmath>
#include <cstring>

#include "box_mesh.h"
#include "gpu/vicp/vicp.h"
#include "gpu/vicp/vicp_published_lanes.h"
#include "mesh_scenes.h"
#include "vicp_bars.h"
#include "image_errors.h"
#include "reference/reference_renderer.h"

using namespace uvr;
using namespace uvr::gpu;
using test::Scene;

namespace {

constexpr double kConvergenceRmse = test::kVicpConvergenceRmse;  // tests/vicp_bars.h says why
constexpr double kConvergenceMax = test::kVicpConvergenceMax;

VicpOptions exact_options(CellOrder order)
{
    VicpOptions o;
    o.order = order;
    o.segment = SegmentMode::exact;
    o.threshold = 1.0f;
    o.interpolation =
        InterpolationMode::exact;  // the variant these bars hold for (the published: test_vicp_published.cpp)
    return o;
}

Image reference(const Scene& s, const Camera& cam, int w, int h) { return test::mesh_reference(s, cam, w, h); }

}  // namespace

TEST_CASE("VICP with exact segments and the MPVONC order equals the reference")
{
    auto check = [](const Scene& s, const Camera& cam, int size) {
        const VicpFrame f = VicpRenderer(s.mesh, s.topo, s.field, s.tf, exact_options(CellOrder::mpvonc))
                                .render(cam, size, size);
        const test::ImageErrors e = test::image_errors(f.image, reference(s, cam, size, size), kConvergenceMax);
        INFO("view eye " << cam.eye.x << " " << cam.eye.y << " " << cam.eye.z << ": RMSE " << e.rmse << ", max "
                         << e.max_abs << ", pixels over " << kConvergenceMax << ": " << e.over << "; "
                         << f.stats.order.face_dependencies << " face and " << f.stats.order.ray_dependencies
                         << " ray dependencies, " << f.stats.order.cycle_breaks << " cycle breaks, "
                         << f.stats.ordering_errors << " ordering errors");
        REQUIRE(f.stats.order.cycle_breaks == 0);
        // The order is exact along every pixel's ray: no segment arrives behind one drawn before it.
        CHECK(f.stats.ordering_errors == 0);
        CHECK(e.rmse <= kConvergenceRmse);
        CHECK(e.max_abs <= kConvergenceMax);
    };
    SECTION("the built-in torus, three views")
    {
        const Scene s = test::make_scene(load_builtin("builtin:torus-small"), 0);
        for (const auto& [az, el] : {std::pair{0.0, 0.0}, {35.0, 40.0}, {-70.0, 15.0}})
            check(s, default_camera(mesh_bounds(s.mesh), 1.0, az, el), 160);
    }
    SECTION("Blunt Fin, two views")
    {
        const Scene s = test::blunt_fin();
        for (const auto& [az, el] : {std::pair{0.0, 0.0}, {-40.0, 70.0}})
            check(s, default_camera(mesh_bounds(s.mesh), 1.0, az, el), 256);
    }
    SECTION("an orthographic view of the torus")
    {
        const Scene s = test::make_scene(load_builtin("builtin:torus-small"), 0);
        const Camera cam = test::orthographic_view(s.mesh, 20.0, 50.0);
        check(s, cam, 160);
    }
}

TEST_CASE("the centroid order's error is measured: pixels without an ordering error equal the MPVONC image")
{
    const Scene s = test::blunt_fin();
    const Camera cam = default_camera(mesh_bounds(s.mesh), 1.0, -40.0, 70.0);
    const int size = 256;
    const VicpFrame exact =
        VicpRenderer(s.mesh, s.topo, s.field, s.tf, exact_options(CellOrder::mpvonc)).render(cam, size, size);
    const VicpFrame centroid =
        VicpRenderer(s.mesh, s.topo, s.field, s.tf, exact_options(CellOrder::centroid)).render(cam, size, size);
    std::size_t clean_differ = 0, with_errors = 0, with_errors_differ = 0;
    for (std::size_t p = 0; p < centroid.ordering_errors.size(); ++p) {
        const bool same = std::memcmp(&exact.image.rgba[4 * p], &centroid.image.rgba[4 * p], 16) == 0;
        if (centroid.ordering_errors[p] == 0) {
            clean_differ += same ? 0 : 1;
        } else {
            ++with_errors;
            with_errors_differ += same ? 0 : 1;
        }
    }
    const test::ImageErrors e = test::image_errors(centroid.image, reference(s, cam, size, size));
    INFO("centroid order: " << centroid.stats.ordering_errors << " ordering errors on " << with_errors
                            << " pixels, of which " << with_errors_differ << " differ from MPVONC's; RMSE "
                            << e.rmse << ", max " << e.max_abs);
    CHECK(clean_differ == 0);
    // Blunt Fin's cells vary in size by orders of magnitude: the centroid order is wrong somewhere on this view.
    CHECK(with_errors > 0);
    CHECK(with_errors_differ > 0);
    CHECK(e.rmse > kConvergenceRmse / 10.0);  // measured, not assumed zero: 4.3e-6 on this view
}

TEST_CASE("VICP on degenerate views: faces edge-on, vertices behind vertices, rays along edges")
{
    // An unjittered grid of unit cubes seen along its axes: every cube's faces parallel to the view are edge-on,
    // points line up behind one another, and pixel rays run along the faces and edges between cells.
    const auto linear = [](const glm::dvec3& p) { return 0.1 * p.x + 0.2 * p.y + 0.3 * p.z; };
    const Scene s = test::make_scene(test::box_mesh(4, linear, 0.0), 0);
    const Bounds b = mesh_bounds(s.mesh);
    for (int view = 0; view < 3; ++view) {
        Camera cam = default_camera(b, 1.0, view == 2 ? 90.0 : 0.0, view == 1 ? 89.0 : 0.0);
        if (view == 0) {
            // Orthographic along the axis, pixel centres on the grid's lines: a 27-pixel image of height 9 puts every
            // third pixel centre on an integer coordinate.
            cam.orthographic = true;
            cam.ortho_height = 9.0;
        }
        const int size = 27 * 3;
        const VicpFrame f = VicpRenderer(s.mesh, s.topo, s.field, s.tf, exact_options(CellOrder::mpvonc))
                                .render(cam, size, size);
        const Image ref = reference(s, cam, size, size);
        std::size_t nonfinite = 0, missing = 0;
        for (std::size_t p = 0; p < f.image.rgba.size() / 4; ++p) {
            for (int c = 0; c < 4; ++c) nonfinite += std::isfinite(f.image.rgba[4 * p + c]) ? 0 : 1;
            missing += ref.rgba[4 * p + 3] > 0.0f && !(f.image.rgba[4 * p + 3] > 0.0f) ? 1 : 0;
        }
        const test::ImageErrors e = test::image_errors(f.image, ref, kConvergenceMax);
        INFO("view " << view << ": " << nonfinite << " non-finite values, " << missing << " missing pixels, RMSE "
                     << e.rmse << ", max " << e.max_abs);
        CHECK(nonfinite == 0);
        CHECK(missing == 0);
        CHECK(e.rmse <= kConvergenceRmse);
        CHECK(e.max_abs <= kConvergenceMax);
    }
}

namespace {

// Three thin cells, each the extension of one side of a triangle in the xy plane, tilted so that A lies above B where
// they cross, B above C, and C above A: seen from above, every order is wrong somewhere (the classic cyclic overlap).
Scene three_sticks(bool cyclic)
{
    TetMesh m;
    m.source = "three sticks";
    const glm::dvec3 v[3] = {{0, 0, 0}, {2, 0, 0}, {1, std::sqrt(3.0), 0}};
    const double z_start[3] = {0.0, 0.5, 0.5}, z_end[3] = {1.0, 1.0, cyclic ? 1.0 : -0.5};
    for (int i = 0; i < 3; ++i) {
        const glm::dvec3 a = v[i], b = v[(i + 1) % 3];
        const glm::dvec3 along = (b - a) / glm::length(b - a), perp(-along.y, along.x, 0.0);
        const glm::dvec3 s = a - 0.4 * along, e = b + 0.4 * along;
        const double w = 0.1;
        const auto at = [](glm::dvec3 p, double z) { return glm::dvec3(p.x, p.y, z); };
        const uint32_t base = uint32_t(m.points.size());
        // Slopes extended over the overhang, so that the heights at the triangle's corners are z_start and z_end.
        const double dz = (z_end[i] - z_start[i]) / 2.0 * 0.4;
        m.points.push_back(at(s - w * perp, z_start[i] - dz));
        m.points.push_back(at(s + w * perp, z_start[i] - dz + 0.05));
        m.points.push_back(at(e - w * perp, z_end[i] + dz + 0.05));
        m.points.push_back(at(e + w * perp, z_end[i] + dz));
        m.tets.push_back({base, base + 1, base + 2, base + 3});
    }
    ScalarField f{"f", {}};
    for (std::size_t i = 0; i < m.points.size(); ++i) f.values.push_back(double(i % 4) / 3.0);
    m.fields.push_back(f);
    finalize_mesh(m);
    return test::make_scene(std::move(m), 0);
}

Camera from_above()
{
    Camera c;
    c.eye = {1.0, 0.6, 12.0};
    c.target = {1.0, 0.6, 0.0};
    c.up = {0.0, 1.0, 0.0};
    c.fovy_deg = 25.0;
    return c;
}

}  // namespace

TEST_CASE("MPVONC reports a visibility cycle and still draws every cell")
{
    SECTION("three cells in cyclic overlap")
    {
        const Scene s = three_sticks(true);
        const Camera cam = from_above();
        const VicpFrame f = VicpRenderer(s.mesh, s.topo, s.field, s.tf, exact_options(CellOrder::mpvonc))
                                .render(cam, 128, 128);
        INFO(f.stats.order.ray_dependencies << " ray dependencies");
        CHECK(f.stats.order.ray_dependencies == 3);
        CHECK(f.stats.order.cycle_breaks >= 1);
        CHECK(f.stats.drawn_cells == 3);
        CHECK(f.stats.ordering_errors > 0);  // the broken cycle is drawn out of order somewhere
    }
    SECTION("the same cells without the cycle")
    {
        const Scene s = three_sticks(false);
        const Camera cam = from_above();
        const VicpFrame f = VicpRenderer(s.mesh, s.topo, s.field, s.tf, exact_options(CellOrder::mpvonc))
                                .render(cam, 128, 128);
        INFO(f.stats.order.ray_dependencies << " ray dependencies");
        CHECK(f.stats.order.ray_dependencies == 3);
        CHECK(f.stats.order.cycle_breaks == 0);
        CHECK(f.stats.ordering_errors == 0);
    }
}

namespace {

// VICP (exact segments, MPVONC) on a view that cuts the mesh, against the reference, with the clip stage's counts.
void require_clipped_converges(const Scene& s, const Camera& cam, int width, int height, bool expect_near_sections)
{
    const VicpFrame f = VicpRenderer(s.mesh, s.topo, s.field, s.tf, exact_options(CellOrder::mpvonc))
                            .render(cam, width, height);
    const Image ref = reference(s, cam, width, height);
    const test::ImageErrors e = test::image_errors(f.image, ref, kConvergenceMax);
    const VicpStats& st = f.stats;
    INFO("RMSE " << e.rmse << ", max " << e.max_abs << ", pixels over " << kConvergenceMax << ": " << e.over << "; "
                 << st.clipped_cells << " cells clipped, " << st.culled_cells << " culled, " << st.near_sections
                 << " near sections, " << st.fan_triangles << " fan triangles, " << st.gpu_clipped
                 << " triangles left for the GPU to clip; " << st.order.cycle_breaks << " cycle breaks, "
                 << st.ordering_errors << " ordering errors");
    CHECK(st.clipped_cells > 0);
    CHECK(st.gpu_clipped == 0);
    CHECK((st.near_sections > 0) == expect_near_sections);
    CHECK(st.order.cycle_breaks == 0);
    CHECK(st.ordering_errors == 0);
    CHECK(e.rmse <= kConvergenceRmse);
    CHECK(e.max_abs <= kConvergenceMax);
    // The scene is not empty: the comparison has something to compare.
    float largest_alpha = 0.0f;
    for (std::size_t p = 3; p < ref.rgba.size(); p += 4) largest_alpha = std::max(largest_alpha, ref.rgba[p]);
    CHECK(largest_alpha > 0.1f);
}

}  // namespace

TEST_CASE("a camera inside the mesh or on its boundary: VICP equals the reference")
{
    // The views of HAVS's clip test (test_havs_clip.cpp), after the reference's own inside-camera test, which checks
    // the reference against the analytic chord.
    for (const test::CutView& v : test::inside_box_views())
        DYNAMIC_SECTION(v.name)
        {
            require_clipped_converges(test::box_scene(6, v.jitter), v.camera, v.width, v.height, true);
        }
    SECTION("Blunt Fin, from inside its flow region")
    {
        const Scene s = test::blunt_fin();
        require_clipped_converges(s, test::inside_view(s), 96, 96, true);
    }
}

TEST_CASE("a view that cuts the mesh at the image's sides: VICP equals the reference")
{
    // The camera outside the mesh but so close that the mesh fills more than the image: cells cross the side planes
    // (the draw module would clip them), none the near plane.
    require_clipped_converges(test::box_scene(6, 0.25), test::looking({3.1, 2.8, -1.5}, {3.0, 3.0, 6.0}, 60.0), 64,
                              64, false);
}

TEST_CASE("far from the origin: VICP on coordinates at 1e8 with features at 1e-3 still equals the reference")
{
    // The vertex buffer relative to the eye (as HAVS's), the cells' constants and the rays relative to the mesh's
    // centre in double, keep the features.
    TetMesh m = load_builtin("builtin:torus-small");
    for (auto& p : m.points) p = glm::dvec3(1e8) + p * 1e-3;
    const Scene s = test::make_scene(std::move(m), 0);
    const Camera cam = default_camera(mesh_bounds(s.mesh), 1.0, 30.0, 20.0);
    const VicpFrame f = VicpRenderer(s.mesh, s.topo, s.field, s.tf, exact_options(CellOrder::mpvonc)).render(cam, 96, 96);
    const test::ImageErrors e = test::image_errors(f.image, reference(s, cam, 96, 96));
    INFO("RMSE " << e.rmse << ", max " << e.max_abs);
    CHECK(e.rmse <= kConvergenceRmse);
    CHECK(e.max_abs <= kConvergenceMax);
}

TEST_CASE("the VICP frame without diagnostics has the same bits and no per-pixel counts or wrong exits")
{
    const Scene s = test::make_scene(load_builtin("builtin:torus-small"), 0);
    const Camera cam = default_camera(mesh_bounds(s.mesh), 1.0, 30.0, 50.0);
    for (const InterpolationMode mode : {InterpolationMode::gpu, InterpolationMode::exact}) {
        INFO("--interpolation " << (mode == InterpolationMode::gpu ? "gpu" : "exact"));
        VicpOptions o;
        o.interpolation = mode;
        const VicpFrame with = VicpRenderer(s.mesh, s.topo, s.field, s.tf, o, true).render(cam, 160, 120);
        const VicpFrame without = VicpRenderer(s.mesh, s.topo, s.field, s.tf, o, false).render(cam, 160, 120);
        CHECK(with.image.rgba == without.image.rgba);
        CHECK(with.stats.fragments > 0);
        CHECK(without.fragments.empty());
        CHECK(without.ordering_errors.empty());
        CHECK(without.stats.fragments == 0);
        CHECK(without.wrong_exits.empty());
        // The published program's wrong exits are found with diagnostics (there are some on this view).
        if (mode == InterpolationMode::gpu) CHECK(with.stats.wrong_exits > 0);
    }
}

TEST_CASE("the published fragments composited eight at a time give each fragment's scalar bits, kills included")
{
    // The frame without diagnostics runs the published program and the table's compositing in AVX2 lanes where the
    // host has them (gpu/vicp/vicp_published_lanes.h); with diagnostics, one fragment at a time. Every pixel of every
    // view must be the same bits, over thousands of fragments, with the opacity kill on and off.
    if (!vicp_published_lanes_available(host_viewport_arithmetic())) {
        WARN("no AVX2 and FMA3 on this host: every frame takes the scalar path, nothing to compare");
        return;
    }
    const Scene torus = test::make_scene(load_builtin("builtin:torus-small"), 0);
    const Scene fin = test::blunt_fin();
    std::size_t fragments = 0;
    // Under the sanitizers the torus only (the lanes' loads and stores are what they check; Blunt Fin adds frames).
    const std::vector<const Scene*> scenes =
        test::sanitized() ? std::vector<const Scene*>{&torus} : std::vector<const Scene*>{&torus, &fin};
    for (const Scene* s : scenes)
        for (const auto& [az, el] : {std::pair{30.0, 50.0}, {-40.0, 70.0}, {200.0, -10.0}})
            for (const float threshold : {1.0f, 0.3f}) {
                INFO(s->mesh.source << " from (" << az << ", " << el << "), threshold " << threshold);
                const Camera cam = default_camera(mesh_bounds(s->mesh), 4.0 / 3.0, az, el);
                VicpOptions o;
                o.threshold = threshold;
                const VicpFrame scalar = VicpRenderer(s->mesh, s->topo, s->field, s->tf, o, true).render(cam, 160, 120);
                const VicpFrame lanes = VicpRenderer(s->mesh, s->topo, s->field, s->tf, o, false).render(cam, 160, 120);
                std::size_t differ = 0;
                for (std::size_t i = 0; i < scalar.image.rgba.size(); ++i)
                    differ += std::memcmp(&scalar.image.rgba[i], &lanes.image.rgba[i], sizeof(float)) != 0;
                CHECK(differ == 0);
                fragments += scalar.stats.fragments;
            }
    CHECK(fragments > 100000);
}
