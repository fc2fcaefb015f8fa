// The three kinds of field (reference/field.h) against images known in closed form: a seam where per-cell vertex data
// jumps, and a box of cell data, rendered by the reference and by HAVS and VICP with every switch exact.
#include <algorithm>
#include <cmath>
#include <functional>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "gpu/havs/havs.h"
#include "gpu/vicp/vicp.h"
#include "reference/cells.h"
#include "reference/field.h"
#include "reference/ray_integrator.h"
#include "reference/reference_renderer.h"
#include "reference/write_vtk.h"
#include "field_scenes.h"
#include "havs_convergence.h"
#include "image_errors.h"
#include "mesh_scenes.h"
#include "test_support.h"
#include "vicp_bars.h"

using namespace uvr;
using test::box_chord;
using test::cell_data_box;
using test::cell_value;
using test::left_field;
using test::right_field;
using test::two_cube_seam;

namespace {

// The reference against a closed form: the integral is exact to ~1e-15, a chord is a sum of double plane distances,
// the image is float32 (6e-8 relative); test_reference_analytic.cpp's bar. A segment that starts from the wrong side's
// value costs 1e-2 and more on these scenes.
constexpr double kReferenceTolerance = 1e-6;
// HAVS and VICP with every switch exact against the same closed form: docs/spec.md §6's bar for float32 fragment values
// and compositing (bench/budget.h's kBudgetBaselineMax).
constexpr double kExactGpuTolerance = 2e-6;

// A segment in closed form under one of two transfer functions chosen so that a closed form exists for a linear
// scalar: `opacity` (constant colour, extinction linear in s: the optical depth is the mean extinction times the
// length) shows a wrong scalar in alpha; `colour` (colour linear in s, constant extinction) shows it in colour.
enum class Tf { opacity, colour };
constexpr glm::dvec3 kColour{0.9, 0.6, 0.3};
constexpr double kTau0 = 0.4, kTau1 = 2.0;       // opacity: tau(s) = kTau0 + kTau1 s over s in [0, 1]
constexpr double kTauC = 1.1;                    // colour: tau constant
glm::dvec3 colour_of(double s) { return {s, 1.0 - s, 0.5}; }  // colour: linear in s over [0, 1]

TransferFunction transfer_function(Tf tf)
{
    TransferFunction t;
    if (tf == Tf::opacity) {
        t.color = {{0.0, kColour}};
        t.extinction = {{0.0, kTau0}, {1.0, kTau0 + kTau1}};
    } else {
        t.color = {{0.0, colour_of(0.0)}, {1.0, colour_of(1.0)}};
        t.extinction = {{0.0, kTauC}};
    }
    return t;
}

glm::dvec4 segment(Tf tf, double sf, double sb, double len)
{
    if (tf == Tf::opacity) {
        const double alpha = 1.0 - std::exp(-len * (kTau0 + kTau1 * 0.5 * (sf + sb)));
        return glm::dvec4(kColour * alpha, alpha);
    }
    // C = int_0^L (A + B t) tau e^{-tau t} dt with A = c(sf), B = c'(s) (sb - sf) / L.
    const double e = std::exp(-kTauC * len);
    const glm::dvec3 a = colour_of(sf), b = (colour_of(sb) - colour_of(sf)) / len;
    return glm::dvec4(a * (1.0 - e) + b * ((1.0 - e) / kTauC - len * e), 1.0 - e);
}

struct Piece {
    glm::dvec3 lo, hi;
    std::function<double(const glm::dvec3&)> field;
};

// The ray through the pieces (disjoint boxes, each with its own field), composited front to back.
glm::dvec4 closed_form(Tf tf, const std::vector<Piece>& pieces, const Ray& r)
{
    struct Hit {
        double t0, t1;
        const Piece* piece;
    };
    std::vector<Hit> hits;
    for (const Piece& p : pieces) {
        double t0, t1;
        if (box_chord(r, p.lo, p.hi, t0, t1)) hits.push_back({t0, t1, &p});
    }
    std::sort(hits.begin(), hits.end(), [](const Hit& a, const Hit& b) { return a.t0 < b.t0; });
    glm::dvec4 acc(0.0);
    for (const Hit& h : hits) {
        const glm::dvec4 c = segment(tf, h.piece->field(r.origin + h.t0 * r.dir), h.piece->field(r.origin + h.t1 * r.dir),
                                     h.t1 - h.t0);
        acc += (1.0 - acc.a) * c;
    }
    return acc;
}

double largest_error(const Image& img, const Camera& cam, Tf tf, const std::vector<Piece>& pieces)
{
    double worst = 0.0;
    for (int j = 0; j < img.height; ++j)
        for (int i = 0; i < img.width; ++i) {
            const glm::dvec4 e = closed_form(tf, pieces, camera_ray(cam, img.width, img.height, i, j));
            for (int k = 0; k < 4; ++k) worst = std::max(worst, std::fabs(img.pixel(i, j)[k] - e[k]));
        }
    return worst;
}

Camera orthographic(glm::dvec3 eye, glm::dvec3 target, glm::dvec3 up, double height)
{
    Camera c;
    c.eye = eye;
    c.target = target;
    c.up = up;
    c.orthographic = true;
    c.ortho_height = height;
    return c;
}

Camera perspective(glm::dvec3 eye, glm::dvec3 target)
{
    Camera c;
    c.eye = eye;
    c.target = target;
    c.up = {0.0, 0.0, 1.0};
    c.fovy_deg = 40.0;
    return c;
}

// Views of the two cubes: along the seam's normal both ways (each cube one constant segment per ray), in the seam's
// plane (the pixel centres miss it: 32 columns over [-0.1, 2.1]) and nearly in it, and oblique perspective views. No
// pixel centre lies in the plane of an internal face (the views along x are centred at z = 0.47, off the cubes'
// diagonals y = z and y + z = 1): a ray in a face's plane is an edge case of coverage, not of the field.
std::vector<Camera> seam_views()
{
    const glm::dvec3 c(1.0, 0.5, 0.5), off(1.0, 0.5, 0.47);
    return {orthographic({-3, 0.5, 0.47}, off, {0, 0, 1}, 1.2), orthographic({5, 0.5, 0.47}, off, {0, 1, 0}, 1.2),
            orthographic({1, -3, 0.5}, c, {0, 0, 1}, 2.2),   orthographic({1.02, 3, 0.45}, c, {0, 0, 1}, 2.2),
            perspective({-2.5, 2.2, 1.9}, c),                perspective({4.0, -1.8, -1.2}, c)};
}

std::vector<Piece> seam_pieces()
{
    return {{{0, 0, 0}, {1, 1, 1}, left_field}, {{1, 0, 0}, {2, 1, 1}, right_field}};
}

std::vector<Piece> box_pieces()
{
    std::vector<Piece> p;
    for (int k = 0; k < 3; ++k)
        for (int j = 0; j < 3; ++j)
            for (int i = 0; i < 3; ++i) {
                const double v = cell_value(i, j, k);
                p.push_back({{i, j, k}, {i + 1, j + 1, k + 1}, [v](const glm::dvec3&) { return v; }});
            }
    return p;
}

std::vector<Camera> box_views()
{
    const glm::dvec3 c(1.5), off(1.5, 1.5, 1.45);  // off: no pixel centre in an internal face's plane (seam_views)
    return {orthographic({-3, 1.5, 1.45}, off, {0, 0, 1}, 3.4), orthographic({1.55, -4, 1.45}, c, {0, 0, 1}, 3.4),
            perspective({-3.0, 4.5, 5.0}, c), perspective({6.0, -2.0, -1.5}, c)};
}

// Each renderer on each view against the closed form.
void check_scene(const TetMesh& mesh, const std::vector<Piece>& pieces, const std::vector<Camera>& views)
{
    constexpr int kSize = 32;
    const MeshTopology topo = build_topology(mesh);
    for (const Tf tf : {Tf::opacity, Tf::colour}) {
        const TransferFunction t = transfer_function(tf);
        const RayIntegrator ri(mesh, topo, 0, t);
        const gpu::HavsRenderer havs(mesh, topo, 0, t, test::havs_every_switch_exact());
        const gpu::VicpRenderer vicp(mesh, topo, 0, t, test::vicp_every_switch_exact());
        for (std::size_t v = 0; v < views.size(); ++v) {
            INFO("transfer function " << (tf == Tf::opacity ? "opacity" : "colour") << ", view " << v);
            ReferenceStats rs;
            const double ref = largest_error(render_reference(ri, views[v], kSize, kSize, rs), views[v], tf, pieces);
            CHECK(rs.failures == 0);
            CHECK(ref <= kReferenceTolerance);
            CHECK(largest_error(havs.render(views[v], kSize, kSize).image, views[v], tf, pieces) <= kExactGpuTolerance);
            CHECK(largest_error(vicp.render(views[v], kSize, kSize).image, views[v], tf, pieces) <= kExactGpuTolerance);
        }
    }
}

}  // namespace

TEST_CASE("a field that jumps across a seam of repeated points is per-cell vertex data, and the seam faces jump")
{
    const TetMesh mesh = two_cube_seam();
    const MeshTopology topo = build_topology(mesh);
    // The shared square is cut the same way from both cubes (canonical points), so the cubes are neighbours there.
    CHECK(topo.boundary_faces == 20);
    const FieldSummary s = summarize_field(mesh, topo, mesh.fields[0]);
    CHECK(s.kind == FieldKind::cell_vertex);
    CHECK(s.jump_faces == 2);
    // The same mesh with one continuous field is point data.
    TetMesh smooth = mesh;
    for (std::size_t i = 0; i < smooth.points.size(); ++i) smooth.fields[0].values[i] = smooth.points[i].x;
    const FieldSummary c = summarize_field(smooth, topo, smooth.fields[0]);
    CHECK(c.kind == FieldKind::point);
    CHECK(c.jump_faces == 0);
}

TEST_CASE("a cell field is constant per tetrahedron and jumps where neighbouring cells differ")
{
    const TetMesh mesh = cell_data_box();
    REQUIRE(mesh.fields.size() == 1);
    CHECK(mesh.fields[0].association == FieldAssociation::cell);
    CHECK(mesh.fields[0].values.size() == mesh.tets.size());
    const MeshTopology topo = build_topology(mesh);
    const FieldSummary s = summarize_field(mesh, topo, mesh.fields[0]);
    CHECK(s.kind == FieldKind::cell);
    // Every pair of face-neighbouring hexahedra differs (cell_value), and each shared square is two triangles.
    CHECK(s.jump_faces == 2 * 3 * 3 * 2 * 3);
}

TEST_CASE("the two-cube seam: the reference, HAVS and VICP with every switch exact equal the closed form")
{
    check_scene(two_cube_seam(), seam_pieces(), seam_views());
}

TEST_CASE("a box of cell data: the reference, HAVS and VICP with every switch exact equal the closed form")
{
    check_scene(cell_data_box(), box_pieces(), box_views());
}

TEST_CASE("a real mesh whose points are repeated per cell, with a field that jumps across a surface through it")
{
    // Blunt Fin with every point repeated per tetrahedron and its field raised by a fifth of its range beyond the
    // plane through its centre: HAVS and VICP with every switch exact against the reference.
    const test::Scene bf = test::blunt_fin();
    const Range r = field_range(bf.mesh.fields[bf.field]);
    const test::Scene s = test::with_jump(bf, 0.2 * (r.hi - r.lo));
    const FieldSummary fs = summarize_field(s.mesh, s.topo, s.mesh.fields[0]);
    REQUIRE(fs.kind == FieldKind::cell_vertex);
    CHECK(fs.jump_faces > 1000);
    constexpr int kSize = 96;
    for (const auto& [az, el] : {std::pair{0.0, 0.0}, {-40.0, 70.0}, {90.0, 10.0}}) {
        const Camera cam = default_camera(mesh_bounds(s.mesh), 1.0, az, el);
        const Image ref = test::mesh_reference(s, cam, kSize, kSize);
        const Image havs = gpu::HavsRenderer(s.mesh, s.topo, 0, s.tf, test::havs_every_switch_exact()).render(cam, kSize, kSize).image;
        const Image vicp = gpu::VicpRenderer(s.mesh, s.topo, 0, s.tf, test::vicp_every_switch_exact()).render(cam, kSize, kSize).image;
        const test::ImageErrors h = test::image_errors(havs, ref, kExactGpuTolerance);
        const test::ImageErrors v = test::image_errors(vicp, ref, kExactGpuTolerance);
        INFO("view " << az << ", " << el << ": HAVS largest " << h.max_abs << " (" << h.over << " pixels over), VICP "
                     << v.max_abs << " (" << v.over << ")");
        CHECK(h.max_abs <= kExactGpuTolerance);
        CHECK(v.max_abs <= kExactGpuTolerance);
    }
}

TEST_CASE("HAVS's exact gaps on a non-convex mesh written with every point repeated")
{
    // The torus with its points repeated per cell: every point has coincident twins, yet the faces around each point
    // connect them, so no boundary face is a seam and every one can start a gap (the hole).
    const test::Scene torus = test::make_scene(load_builtin("builtin:torus-small"), 0);
    const test::Scene s = test::with_jump(torus, 0.0);
    const gpu::HavsMesh hm(s.mesh, s.topo, 0, s.tf, test::havs_every_switch_exact());
    std::size_t exits = 0;
    for (std::size_t f = 0; f < hm.face_count(); ++f) exits += hm.exit_capable(f) ? 1 : 0;
    CHECK(exits == s.topo.boundary_faces);
    constexpr int kSize = 96;
    const Camera cam = default_camera(mesh_bounds(s.mesh), 1.0, 20.0, 50.0);
    const Image ref = test::mesh_reference(s, cam, kSize, kSize);
    const Image havs = gpu::HavsRenderer(s.mesh, s.topo, 0, s.tf, test::havs_every_switch_exact()).render(cam, kSize, kSize).image;
    const test::ImageErrors e = test::image_errors(havs, ref, kExactGpuTolerance);
    INFO("largest error " << e.max_abs << ", " << e.over << " pixels over");
    CHECK(e.max_abs <= kExactGpuTolerance);
}


TEST_CASE("uvr info reports each field's kind and the faces it jumps across")
{
    test::TempDir dir("fields-info");
    const std::string seam = dir.file("seam.vtk"), cells = dir.file("cells.vtk");
    write_vtk_legacy(seam, two_cube_seam(), 0);
    write_vtk_legacy(cells, cell_data_box(), 0);
    const test::CommandResult s = test::run_uvr("info '" + seam + "' --json");
    INFO(s.err);
    REQUIRE(s.exit_code == 0);
    const auto j = nlohmann::json::parse(s.out);
    CHECK(j["repeated_points"] == 4);  // the shared square's corners, written once per cube
    CHECK(j["fields"][0]["kind"] == "cell_vertex");
    CHECK(j["fields"][0]["jump_faces"] == 2);
    const test::CommandResult c = test::run_uvr("info '" + cells + "' --json");
    REQUIRE(c.exit_code == 0);
    const auto k = nlohmann::json::parse(c.out);
    CHECK(k["fields"][0]["kind"] == "cell");
    CHECK(k["fields"][0]["jump_faces"] == 108);
    const test::CommandResult text = test::run_uvr("info '" + seam + "'");
    CHECK_THAT(text.out, Catch::Contains("cell_vertex, jumps across 2 faces"));
    CHECK_THAT(text.out, Catch::Contains("4 repeat a position"));
}
