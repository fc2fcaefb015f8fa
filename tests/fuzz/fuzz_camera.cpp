// libFuzzer target: camera JSON through uvr::parse_camera (the text load_camera reads from its file). A camera that
// parsed (and so passed validate_camera) must give a finite orthonormal frame and finite rays.
#include <cmath>
#include <string>

#include "reference/camera.h"
#include "tests/fuzz/fuzz_common.h"

namespace {
bool finite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size)
{
    const std::string text(uvr_fuzz::as_view(data, size));
    return uvr_fuzz::expect_input_error_only([&] {
        const uvr::Camera cam = uvr::parse_camera(text, "input.json");
        const uvr::CameraFrame fr = uvr::camera_frame(cam);
        uvr_fuzz::require(finite(fr.f) && finite(fr.r) && finite(fr.u), "an accepted camera has a finite frame");
        for (double ij : {0.0, 7.5, 15.0}) {
            const uvr::Ray ray = uvr::camera_ray(cam, 16, 9, ij, ij * 0.5);
            uvr_fuzz::require(finite(ray.origin) && finite(ray.dir), "an accepted camera gives finite rays");
        }
        (void)uvr::camera_json(cam);
    });
}
