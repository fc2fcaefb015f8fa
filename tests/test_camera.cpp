// Camera files and pixel rays (docs/spec.md §2).
#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "reference/camera.h"
#include "test_support.h"

using namespace uvr;
using uvr::test::require_input_error;

namespace {
// Rays are built from a handful of double operations on values of order 1: a few ulps.
constexpr double kRayTolerance = 1e-14;
}  // namespace

TEST_CASE("perspective rays pass through pixel centres as docs/spec.md §2 defines them")
{
    Camera cam;
    cam.eye = {0, 0, 5};
    cam.target = {0, 0, 0};
    cam.up = {0, 1, 0};
    cam.fovy_deg = 90.0;
    // 2x2 image, tan(45 deg) = 1: the top-left pixel centre is at ndc (-0.5, 0.5).
    const Ray r = camera_ray(cam, 2, 2, 0, 0);
    const glm::dvec3 expected = glm::normalize(glm::dvec3(-0.5, 0.5, -1.0));
    CHECK(glm::length(r.dir - expected) < kRayTolerance);
    CHECK(r.origin == cam.eye);
    SECTION("the aspect ratio widens x")
    {
        const Ray w = camera_ray(cam, 4, 2, 3, 1);  // ndc x = 0.75, y = -0.5, times aspect 2 on x
        CHECK(glm::length(w.dir - glm::normalize(glm::dvec3(1.5, -0.5, -1.0))) < kRayTolerance);
    }
}

TEST_CASE("orthographic rays are parallel and start on the image plane through the eye")
{
    const Camera cam = parse_camera(
        R"({"eye": [0,0,5], "target": [0,0,0], "up": [0,1,0], "projection": "orthographic", "ortho_height": 4})",
        "cam.json");
    const Ray r = camera_ray(cam, 4, 4, 0, 3);  // ndc (-0.75, -0.75) * half-height 2
    CHECK(glm::length(r.dir - glm::dvec3(0, 0, -1)) < kRayTolerance);
    CHECK(glm::length(r.origin - glm::dvec3(-1.5, -1.5, 5)) < kRayTolerance);
}

TEST_CASE("the default camera frames the whole box and orbits with --view")
{
    Bounds b{{-1, -2, -3}, {3, 2, 1}};
    const Camera front = default_camera(b, 1.0);
    CHECK(front.target == b.center());
    CHECK(front.eye.x == Approx(b.center().x));
    CHECK(front.eye.z > b.hi.z);
    // Every corner of the box is inside the view cone.
    const CameraFrame fr = camera_frame(front);
    const double half = std::tan(0.5 * front.fovy_deg * 3.14159265358979323846 / 180.0);
    for (int c = 0; c < 8; ++c) {
        const glm::dvec3 p((c & 1) ? b.hi.x : b.lo.x, (c & 2) ? b.hi.y : b.lo.y, (c & 4) ? b.hi.z : b.lo.z);
        const glm::dvec3 d = p - front.eye;
        const double z = glm::dot(d, fr.f);
        INFO("corner " << c);
        CHECK(std::fabs(glm::dot(d, fr.r)) / z < half);
        CHECK(std::fabs(glm::dot(d, fr.u)) / z < half);
    }
    const Camera side = default_camera(b, 1.0, 90.0, 0.0);
    CHECK(side.eye.x > b.hi.x);
    const Camera top = default_camera(b, 1.0, 0.0, 90.0);  // straight down: up must stay valid
    CHECK_NOTHROW(validate_camera(top, "view"));
    CHECK(top.eye.y > b.hi.y);
}

TEST_CASE("malformed cameras are errors naming the file")
{
    SECTION("eye equals target")
    {
        require_input_error([] { parse_camera(R"({"eye": [1,1,1], "target": [1,1,1]})", "cam.json"); },
                            {"cam.json", "coincide"});
    }
    SECTION("up parallel to the view direction")
    {
        require_input_error([] { parse_camera(R"({"eye": [0,0,1], "target": [0,0,0], "up": [0,0,1]})", "cam.json"); },
                            {"cam.json", "parallel"});
    }
    SECTION("missing target")
    {
        require_input_error([] { parse_camera(R"({"eye": [0,0,1]})", "cam.json"); }, {"cam.json", "\"target\""});
    }
    SECTION("bad field of view")
    {
        require_input_error(
            [] { parse_camera(R"({"eye": [0,0,1], "target": [0,0,0], "fovy_deg": 180})", "cam.json"); },
            {"cam.json", "fovy_deg"});
    }
    SECTION("orthographic without a height")
    {
        require_input_error(
            [] { parse_camera(R"({"eye": [0,0,1], "target": [0,0,0], "projection": "orthographic"})", "cam.json"); },
            {"cam.json", "ortho_height"});
    }
}

TEST_CASE("the pixels covering a box hold every pixel whose ray meets it")
{
    const Bounds box{{-1.0, -0.5, -2.0}, {1.5, 0.5, 0.0}};
    constexpr int kW = 48, kH = 32;
    // The slab test of the ray through pixel (i, j) against the box.
    auto meets = [&](const Camera& cam, int i, int j) {
        const Ray r = camera_ray(cam, kW, kH, i, j);
        double t0 = 0.0, t1 = 1e300;
        for (int a = 0; a < 3; ++a) {
            const double lo = (box.lo[a] - r.origin[a]) / r.dir[a], hi = (box.hi[a] - r.origin[a]) / r.dir[a];
            t0 = std::max(t0, std::min(lo, hi));
            t1 = std::min(t1, std::max(lo, hi));
        }
        return t0 <= t1;
    };
    Camera outside;
    outside.eye = {4.0, 3.0, 6.0};
    outside.target = {-1.5, 2.0, 0.0};  // the box off the image's centre: low and right of it
    outside.fovy_deg = 60.0;
    Camera ortho = outside;
    ortho.orthographic = true;
    ortho.ortho_height = 8.0;
    Camera inside = outside;
    inside.eye = {0.0, 0.0, -1.0};
    const struct {
        Camera cam;
        bool whole;  // from inside the box every ray meets it: the rectangle is the image
    } cases[] = {{outside, false}, {ortho, false}, {inside, true}};
    for (const auto& [cam, expect_whole] : cases) {
        const PixelRect r = pixels_covering(cam, kW, kH, box);
        int hits = 0;
        for (int j = 0; j < kH; ++j)
            for (int i = 0; i < kW; ++i)
                if (meets(cam, i, j)) {
                    ++hits;
                    INFO("pixel " << i << ", " << j);
                    CHECK((i >= r.x0 && i < r.x1 && j >= r.y0 && j < r.y1));
                }
        CHECK(hits > 0);
        CHECK((r.x0 == 0 && r.y0 == 0 && r.x1 == kW && r.y1 == kH) == expect_whole);
    }
}
