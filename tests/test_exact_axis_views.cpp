// Rays on faces, edges and vertices (docs/spec.md §7): blocks of cubes split into five and six tetrahedra, written
// as explicit tetrahedra, seen orthographically along each axis and at 45° about one, at image sizes that put pixel
// centres on the interior faces' planes, the interior edges and the vertices. With every switch exact, HAVS and VICP
// equal the reference there as everywhere: each such ray is taken by exactly one of the cells that share it.
#include <array>
#include <cmath>
#include <vector>

#include "gpu/havs/havs.h"
#include "gpu/vicp/vicp.h"
#include "havs_convergence.h"
#include "image_errors.h"
#include "mesh_scenes.h"
#include "reference/reference_renderer.h"
#include "test_support.h"

using namespace uvr;
using namespace uvr::gpu;

namespace {

// docs/spec.md §6: with every switch exact, HAVS and VICP equal the reference to float32 precision on images whose
// values are at most 1 (as tests/test_exact_coverage.cpp).
constexpr double kExactMax = 2e-6;

// A cube's corner v has bits (x, y, z) = (v & 1, v >> 1 & 1, v >> 2 & 1).
using CubeSplit = std::vector<std::array<int, 4>>;

// Six tetrahedra around the diagonal from corner 0 to corner 7: every translated copy cuts a shared face along the
// same diagonal, so the block conforms.
const CubeSplit kSixAroundDiagonal = {{0, 1, 3, 7}, {0, 3, 2, 7}, {0, 2, 6, 7},
                                      {0, 6, 4, 7}, {0, 4, 5, 7}, {0, 5, 1, 7}};
// Five tetrahedra: four corners and the central one, mirrored in every other cube so that shared faces agree.
const CubeSplit kFiveEven = {{0, 1, 2, 4}, {3, 2, 1, 7}, {5, 4, 7, 1}, {6, 7, 4, 2}, {1, 2, 4, 7}};
const CubeSplit kFiveOdd = {{1, 0, 5, 3}, {2, 3, 0, 6}, {4, 5, 6, 0}, {7, 6, 3, 5}, {0, 3, 5, 6}};

// An n x n x n block of unit cubes from the origin, split by `split` (or by the five-split's parity when `five`), with
// a smooth non-linear point field between 0.1 and 0.9.
TetMesh cube_block(int n, bool five)
{
    TetMesh m;
    m.source = five ? "five-split cubes" : "six-split cubes";
    const int np = n + 1;
    for (int z = 0; z < np; ++z)
        for (int y = 0; y < np; ++y)
            for (int x = 0; x < np; ++x) m.points.push_back({double(x), double(y), double(z)});
    ScalarField f{"s", {}};
    for (const glm::dvec3& p : m.points)
        f.values.push_back(0.5 + 0.4 * std::sin(0.9 * p.x + 0.4) * std::cos(0.7 * p.y - 0.3 * p.z));
    m.fields.push_back(f);
    for (int z = 0; z < n; ++z)
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) {
                const auto corner = [&](int v) {
                    return uint32_t((x + (v & 1)) + np * ((y + (v >> 1 & 1)) + np * (z + (v >> 2 & 1))));
                };
                const CubeSplit& split = !five ? kSixAroundDiagonal : ((x + y + z) & 1) ? kFiveOdd : kFiveEven;
                for (const auto& t : split) m.tets.push_back({corner(t[0]), corner(t[1]), corner(t[2]), corner(t[3])});
            }
    finalize_mesh(m);
    return m;
}

// Adds a cell field that differs in every tetrahedron, so that which cell takes a ray in a face's plane shows.
void with_cell_field(TetMesh& m)
{
    ScalarField f{"c", {}, FieldAssociation::cell};
    for (std::size_t t = 0; t < m.tets.size(); ++t) f.values.push_back(0.1 + 0.8 * double((t * 7) % 11) / 10.0);
    m.fields.push_back(f);
}

// An orthographic camera looking at the block's centre c along `dir` with `up`, its image `pixels` wide and `span`
// world units high: with an odd pixel count the centre row and column pass through c, and a pixel is span / pixels.
Camera ortho_view(const glm::dvec3& c, const glm::dvec3& dir, const glm::dvec3& up, double span)
{
    Camera cam;
    cam.orthographic = true;
    cam.target = c;
    cam.eye = c - 4.0 * dir;
    cam.up = up;
    cam.ortho_height = span;
    return cam;
}

struct View {
    const char* name;
    glm::dvec3 dir, up;
};

void check_exact_algorithms(const test::Scene& s, const Camera& cam, int size)
{
    const RayIntegrator ri(s.mesh, s.topo, s.field, s.tf);
    ReferenceStats rs;
    const Image ref = render_reference(ri, cam, size, size, rs);
    REQUIRE(test::image_errors(ref, Image(size, size), 0.0).max_abs > 0.1);  // the block is in view

    const HavsFrame h =
        HavsRenderer(s.mesh, s.topo, s.field, s.tf, test::havs_every_switch_exact()).render(cam, size, size);
    const test::ImageErrors eh = test::image_errors(h.image, ref, kExactMax);
    INFO("HAVS: RMSE " << eh.rmse << ", max " << eh.max_abs << ", pixels over " << kExactMax << ": " << eh.over);
    CHECK(eh.max_abs <= kExactMax);

    const VicpFrame v =
        VicpRenderer(s.mesh, s.topo, s.field, s.tf, test::vicp_every_switch_exact()).render(cam, size, size);
    const test::ImageErrors ev = test::image_errors(v.image, ref, kExactMax);
    INFO("VICP: RMSE " << ev.rmse << ", max " << ev.max_abs << ", pixels over " << kExactMax << ": " << ev.over);
    CHECK(ev.max_abs <= kExactMax);
}

}  // namespace

TEST_CASE("every exact algorithm equals the reference where pixel centres lie on faces, edges and vertices")
{
    // A 2 x 2 x 2 block seen along each axis from its centre (1, 1, 1), 65 x 65 pixels at 16 a unit: every plane x, y
    // or z = 0, 1 or 2 holds a row or column of pixel centres (the outer ones rays in the boundary faces' planes),
    // the six-split's diagonal planes hold the pixels of their cubes' diagonals, and the rays along the interior edges
    // pass through vertices. Window positions are exact at 16 pixels a unit, so every algorithm sees the ties exactly.
    // A cell field shows which cell takes each such ray.
    const View views[] = {
        {"along +x", {1, 0, 0}, {0, 0, 1}}, {"along -y", {0, -1, 0}, {0, 0, 1}}, {"along +z", {0, 0, 1}, {0, 1, 0}}};
    for (const bool five : {false, true})
        for (const bool cell_field : {false, true}) {
            TetMesh m = cube_block(2, five);
            if (cell_field) with_cell_field(m);
            const test::Scene scene = test::make_scene(std::move(m), cell_field ? 1 : 0);
            for (const View& v : views) {
                DYNAMIC_SECTION((five ? "five" : "six") << "-split cubes, " << (cell_field ? "cell" : "point")
                                                        << " field, " << v.name)
                {
                    check_exact_algorithms(scene, ortho_view({1, 1, 1}, v.dir, v.up, 65.0 / 16.0), 65);
                }
            }
        }
}

TEST_CASE("every exact algorithm equals the reference on a block turned 45 degrees, pixel centres on its planes")
{
    // The same blocks turned by 45 degrees about one axis, 65 x 65 pixels over 2.3 units: the centre row and column lie
    // in the planes through the centre (a face between cubes, and the five- and six-split's diagonal faces that the
    // turn puts edge-on), the centre pixel on the interior edge through the centre vertex. The outer faces lie
    // outside the image or between pixel centres. A point field (a tie's side cannot change the image; with window
    // positions rounded at this angle, which side a cell field's tie falls on is each algorithm's rounding).
    const double s = 1.0 / std::sqrt(2.0);
    const View views[] = {{"45 degrees about z", {s, s, 0}, {0, 0, 1}}, {"45 degrees about x", {0, s, s}, {1, 0, 0}}};
    for (const bool five : {false, true}) {
        const test::Scene scene = test::make_scene(cube_block(2, five), 0);
        for (const View& v : views) {
            DYNAMIC_SECTION((five ? "five" : "six") << "-split cubes, " << v.name)
            {
                check_exact_algorithms(scene, ortho_view({1, 1, 1}, v.dir, v.up, 2.3), 65);
            }
        }
    }
}
