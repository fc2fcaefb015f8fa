// VICP's own error: the published vertex program gives each vertex the distance along its view ray to the
// face opposite it, and the rasterizer interpolates those distances across the projected face. Under perspective the
// rays through a face's pixels are not parallel, so the distance to a plane is not the interpolation of the vertices'
// distances; orthographic, it is. This test computes that model on its own (in double: the pixel's ray, the point where
// it meets the face, its barycentric weights, the exact distances) and checks that the emulated pipeline (ProjectTet's
// records, VertexProg, llvmpipe's interpolation, FragmentProg's exit) reproduces the model, and so shows the error: a
// wide-angle close-up of one tetrahedron errs by a visible fraction of its size, an orthographic view within 1e-5.
#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "gpu/pipeline/clip_position.h"
#include "gpu/pipeline/denormals.h"
#include "gpu/pipeline/rasterize.h"
#include "gpu/pipeline/view_setup.h"
#include "gpu/vicp/vicp_published_vertex.h"
#include "gpu/vicp/vicp_vertex.h"
#include "test_support.h"

using namespace uvr;
using namespace uvr::gpu;

namespace {

constexpr int kSize = 160;

// The emulated length against the model, relative to the cell's size: float32 positions, plane components and
// gradient (2^-24 relative each) through the vertex program's division and the rasterizer's interpolation. Measured
// 2.4e-6 (the close-up below) and 5.8e-7 (orthographic); 1e-5 bounds both with room, while the interpolation's own
// error, which the model predicts, reaches 4.9 cell sizes in the close-up.
constexpr double kEmulatedVsModel = 1e-5;
// The bar for orthographic views, where the distances are linear across a face: within 1e-5 of the exact.
constexpr double kOrthographicBar = 1e-5;
// The close-up must show VICP's error: at least this fraction of the cell's size somewhere.
constexpr double kVisibleError = 1e-2;

struct Outcome {
    std::size_t fragments = 0;
    std::size_t face_differs = 0;   // the emulation chose another exit face than the model
    double emu_vs_model = 0.0;      // largest |emulated length - model length| over the tetrahedron's size
    double model_vs_exact = 0.0;    // largest |model - exact| over the size
    double emu_vs_exact = 0.0;      // largest |emulated - exact| over the size
    double emu_vs_exact_sum = 0.0;  // the same, summed (for the mean)
};

// The ray through pixel (px, py)'s centre (GL rows from the bottom), written here from the camera's definition
// (docs/spec.md §2) rather than taken from uvr.
void pixel_ray(const Camera& cam, int px, int py, glm::dvec3& o, glm::dvec3& d)
{
    const glm::dvec3 f = glm::normalize(cam.target - cam.eye);
    const glm::dvec3 r = glm::normalize(glm::cross(f, cam.up));
    const glm::dvec3 u = glm::cross(r, f);
    const double nx = (px + 0.5) / kSize * 2.0 - 1.0, ny = (py + 0.5) / kSize * 2.0 - 1.0;
    if (cam.orthographic) {
        o = cam.eye + nx * 0.5 * cam.ortho_height * r + ny * 0.5 * cam.ortho_height * u;
        d = f;
        return;
    }
    const double h = std::tan(0.5 * cam.fovy_deg * M_PI / 180.0);
    o = cam.eye;
    d = glm::normalize(f + nx * h * r + ny * h * u);
}

// Distance along the unit direction d from x to the plane through a, b, c (infinite when parallel).
double plane_distance(const glm::dvec3& x, const glm::dvec3& d, const glm::dvec3& a, const glm::dvec3& b,
                      const glm::dvec3& c)
{
    const glm::dvec3 n = glm::cross(b - a, c - a);
    return glm::dot(n, a - x) / glm::dot(n, d);
}

Outcome render_one_tet(const Camera& cam, const glm::dvec3 p[4])
{
    Outcome out;
    const double size = glm::length(p[1] - p[0]);
    const Bounds bounds{glm::min(glm::min(p[0], p[1]), glm::min(p[2], p[3])),
                        glm::max(glm::max(p[0], p[1]), glm::max(p[2], p[3]))};
    const ViewSetup view = view_setup(cam, kSize, kSize, bounds, cam.eye);
    const Framebuffer fbuf{kSize, kSize, RenderTarget::fbo};
    const ViewportArithmetic arith = host_viewport_arithmetic();
    VicpPublishedView sv_view;
    sv_view.orthographic = cam.orthographic ? 1 : 0;
    sv_view.direction = glm::vec3(glm::normalize(cam.target - cam.eye));
    const double s[4] = {0.1, 0.9, 0.4, 0.6};
    const glm::dvec3 e1 = p[1] - p[0], e2 = p[2] - p[0], e3 = p[3] - p[0];
    const double det = glm::dot(e1, glm::cross(e2, e3));
    REQUIRE(det > 0.0);
    const glm::dvec3 g =
        (glm::cross(e2, e3) * (s[1] - s[0]) + glm::cross(e3, e1) * (s[2] - s[0]) + glm::cross(e1, e2) * (s[3] - s[0])) /
        det;
    const FlushDenormals as_llvmpipe_runs;
    for (const auto& face : kVicpCorner) {
        WindowCoord win[3];
        SetupVertex setup[3];
        VicpPublishedVaryings vary[3];
        int opposite[3][3];
        for (int j = 0; j < 3; ++j) {
            const int v = face[j];
            int n = 0;
            for (int k = 0; k < 4; ++k)
                if (k != v) opposite[j][n++] = k;
            VicpPublishedVertex rec;
            rec.position = glm::vec3(p[v] - cam.eye);
            rec.s = float(s[v]);
            rec.gradient = glm::vec3(g);
            rec.plane = glm::vec3(vicp_published_plane(p[v], p[opposite[j][0]], p[opposite[j][1]], p[opposite[j][2]]));
            rec.index = float(j);
            const auto clip = vertex_position(view, rec.position);
            win[j] = viewport_transform(clip.data(), fbuf);
            setup[j] = setup_vertex(clip.data(), fbuf);
            vary[j] = vicp_published_vertex_program(sv_view, rec);
        }
        const TriangleSetup ts = setup_triangle(win, fbuf);
        if (ts.empty() || ts.facing != Facing::front) continue;
        const VicpPublishedPlanes planes = vicp_published_planes(setup, vary, ts);
        rasterize_triangle(win, fbuf, [&](int px, int py) {
            const VicpPublishedExit e = vicp_published_exit(vicp_published_varyings_at(planes, px, py, arith));
            // The model: where the pixel's ray meets the face, its barycentric weights w there, the vertices' own
            // distances d_j (along each vertex's view ray to its opposite plane): entry j interpolates to w_j d_j.
            glm::dvec3 o, d;
            pixel_ray(cam, px, py, o, d);
            const glm::dvec3 a = p[face[0]], b = p[face[1]], c = p[face[2]];
            const glm::dvec3 n = glm::cross(b - a, c - a);
            const glm::dvec3 x = o + d * (glm::dot(n, a - o) / glm::dot(n, d));
            const double area = glm::dot(n, n);
            const double w[3] = {glm::dot(glm::cross(b - x, c - x), n) / area,
                                 glm::dot(glm::cross(c - x, a - x), n) / area,
                                 glm::dot(glm::cross(a - x, b - x), n) / area};
            int model_face = -1, exact_face = -1;
            double model = 0.0, exact = 0.0;
            for (int j = 0; j < 3; ++j) {
                const glm::dvec3 vj = p[face[j]];
                const glm::dvec3 rj = cam.orthographic ? d : glm::normalize(vj - cam.eye);
                const glm::dvec3 qa = p[opposite[j][0]], qb = p[opposite[j][1]], qc = p[opposite[j][2]];
                const double mj = w[j] * plane_distance(vj, rj, qa, qb, qc);
                const double xj = plane_distance(x, d, qa, qb, qc);
                if (mj > 0.0 && (model_face < 0 || mj < model)) model_face = j, model = mj;
                if (xj > 0.0 && (exact_face < 0 || xj < exact)) exact_face = j, exact = xj;
            }
            ++out.fragments;
            if (e.face != model_face) {
                ++out.face_differs;
                return;
            }
            out.emu_vs_model = std::max(out.emu_vs_model, std::abs(double(e.length) - model) / size);
            out.model_vs_exact = std::max(out.model_vs_exact, std::abs(model - exact) / size);
            out.emu_vs_exact = std::max(out.emu_vs_exact, std::abs(double(e.length) - exact) / size);
            out.emu_vs_exact_sum += std::abs(double(e.length) - exact) / size;
        });
    }
    return out;
}

std::string describe(const Outcome& o)
{
    std::ostringstream s;
    s << o.fragments << " fragments, " << o.face_differs << " with another exit face than the model; emulated - model "
      << o.emu_vs_model << ", model - exact " << o.model_vs_exact << ", emulated - exact " << o.emu_vs_exact
      << " (of the cell's size; mean " << o.emu_vs_exact_sum / double(o.fragments) << ")";
    return s.str();
}

// A regular-ish tetrahedron of edge about 1 around the origin, positively oriented.
void tetrahedron(glm::dvec3 p[4])
{
    p[0] = {-0.5, -0.3, -0.35};
    p[1] = {0.55, -0.25, -0.3};
    p[2] = {0.05, 0.6, -0.25};
    p[3] = {0.0, 0.05, 0.55};
    const double det = glm::dot(p[1] - p[0], glm::cross(p[2] - p[0], p[3] - p[0]));
    if (det < 0.0) std::swap(p[2], p[3]);
}

}  // namespace

TEST_CASE("VICP's interpolated distances err under a wide-angle close-up as the model predicts, and not orthographic")
{
    glm::dvec3 p[4];
    tetrahedron(p);
    SECTION("a wide-angle close-up")
    {
        Camera cam;
        cam.eye = {0.21, 0.54, 0.69};  // a little outside the cell, which fills much of a 120-degree view
        cam.target = {0.0, 0.0, 0.0};
        cam.up = {0.0, 1.0, 0.0};
        cam.fovy_deg = 120.0;
        const Outcome o = render_one_tet(cam, p);
        INFO(describe(o));
        REQUIRE(o.fragments > 1000);
        CHECK(o.face_differs < o.fragments / 100);  // ties at the edges between exit faces only
        CHECK(o.emu_vs_model < kEmulatedVsModel);
        CHECK(o.model_vs_exact > kVisibleError);
        CHECK(o.emu_vs_exact > kVisibleError);
    }
    SECTION("orthographic")
    {
        Camera cam;
        cam.eye = {0.35, 0.9, 1.15};
        cam.target = {0.0, 0.0, 0.0};
        cam.up = {0.0, 1.0, 0.0};
        cam.orthographic = true;
        cam.ortho_height = 2.0;
        const Outcome o = render_one_tet(cam, p);
        INFO(describe(o));
        REQUIRE(o.fragments > 1000);
        CHECK(o.face_differs < o.fragments / 100);
        CHECK(o.emu_vs_model < kEmulatedVsModel);
        CHECK(o.emu_vs_exact < kOrthographicBar);
    }
}
