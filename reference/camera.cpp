#include "reference/camera.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "reference/error.h"
#include "reference/io_util.h"

namespace uvr {

namespace {
constexpr double kPi = 3.14159265358979323846;
double radians(double deg) { return deg * kPi / 180.0; }
}  // namespace

CameraFrame camera_frame(const Camera& cam)
{
    CameraFrame fr;
    fr.f = glm::normalize(cam.target - cam.eye);
    fr.r = glm::normalize(glm::cross(fr.f, cam.up));
    fr.u = glm::cross(fr.r, fr.f);
    return fr;
}

Ray camera_ray(const Camera& cam, int width, int height, double i, double j)
{
    return CameraRays(cam, width, height)(i, j);
}

CameraRays::CameraRays(const Camera& cam, int width, int height)
    : cam_(cam),
      fr_(camera_frame(cam)),
      width_(width),
      height_(height),
      half_(cam.orthographic ? 0.5 * cam.ortho_height : std::tan(0.5 * radians(cam.fovy_deg)))
{
}

Ray CameraRays::operator()(double i, double j) const
{
    // The pixel centre's offsets from the image's centre, in units of half_ at the image plane: x * half * aspect with
    // x = 2 (i + 0.5) / width - 1, written as (2 i + 1 - width) * half / height so that the integer numerator is exact
    // and an offset the grid of pixel centres meets exactly (a face's plane on an axis-aligned view) is exact too.
    const double x = (2.0 * i + 1.0 - double(width_)) * half_ / double(height_);
    const double y = (double(height_) - 2.0 * j - 1.0) * half_ / double(height_);
    if (cam_.orthographic) return {cam_.eye + x * fr_.r + y * fr_.u, fr_.f, fr_.r, fr_.u, false};
    return {cam_.eye, glm::normalize(fr_.f + x * fr_.r + y * fr_.u), fr_.r, fr_.u, true};
}

PixelRect pixels_covering(const Camera& cam, int width, int height, const Bounds& b)
{
    const PixelRect whole{0, 0, width, height};
    const CameraFrame fr = camera_frame(cam);
    const double aspect = double(width) / double(height);
    // Half the image's extent at unit distance (perspective) or in world units (orthographic): camera_ray's x, y.
    const double half_h = cam.orthographic ? 0.5 * cam.ortho_height : std::tan(0.5 * radians(cam.fovy_deg));
    double lo_i = std::numeric_limits<double>::infinity(), hi_i = -lo_i, lo_j = lo_i, hi_j = -lo_i;
    for (int c = 0; c < 8; ++c) {
        const glm::dvec3 p((c & 1) ? b.hi.x : b.lo.x, (c & 2) ? b.hi.y : b.lo.y, (c & 4) ? b.hi.z : b.lo.z);
        const glm::dvec3 v = p - cam.eye;
        const double z = cam.orthographic ? 1.0 : glm::dot(v, fr.f);
        if (!(z > 0.0)) return whole;
        const double x = glm::dot(v, fr.r) / (z * half_h * aspect), y = glm::dot(v, fr.u) / (z * half_h);
        const double i = 0.5 * (x + 1.0) * width - 0.5, j = 0.5 * (1.0 - y) * height - 0.5;
        lo_i = std::min(lo_i, i), hi_i = std::max(hi_i, i), lo_j = std::min(lo_j, j), hi_j = std::max(hi_j, j);
    }
    if (!(std::isfinite(lo_i) && std::isfinite(hi_i) && std::isfinite(lo_j) && std::isfinite(hi_j))) return whole;
    const auto clamp = [](double v, int n) { return int(std::clamp(v, 0.0, double(n))); };
    return {clamp(std::floor(lo_i) - 1.0, width), clamp(std::floor(lo_j) - 1.0, height),
            clamp(std::ceil(hi_i) + 2.0, width), clamp(std::ceil(hi_j) + 2.0, height)};
}

void validate_camera(const Camera& cam, const std::string& file)
{
    auto finite = [](const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); };
    if (!finite(cam.eye) || !finite(cam.target) || !finite(cam.up))
        throw InputError(file, "camera vectors must be finite");
    const glm::dvec3 d = cam.target - cam.eye;
    if (glm::length(d) == 0.0) throw InputError(file, "camera eye and target coincide");
    // Beyond about 1e154 the length overflows and the view direction cannot be normalized (a NaN frame).
    if (!std::isfinite(glm::length(d))) throw InputError(file, "camera eye and target are too far apart");
    if (glm::length(cam.up) == 0.0) throw InputError(file, "camera up vector is zero");
    const double s = glm::length(glm::cross(glm::normalize(d), glm::normalize(cam.up)));
    if (s < 1e-9) throw InputError(file, "camera up vector is parallel to the view direction");
    if (!cam.orthographic && !(cam.fovy_deg > 0.0 && cam.fovy_deg < 180.0))
        throw InputError(file, "fovy_deg must be in (0, 180)");
    if (cam.orthographic && !(cam.ortho_height > 0.0 && std::isfinite(cam.ortho_height)))
        throw InputError(file, "ortho_height must be positive");
}

Camera parse_camera(const std::string& text, const std::string& file)
{
    nlohmann::json j;
    try {
        j = nlohmann::json::parse(text);
    } catch (const nlohmann::json::parse_error& e) {
        const long line = 1 + static_cast<long>(std::count(text.begin(),
                                                            text.begin() + static_cast<long>(std::min<std::size_t>(
                                                                               e.byte ? e.byte - 1 : 0, text.size())),
                                                            '\n'));
        throw InputError(file, line, std::string("invalid JSON: ") + e.what());
    } catch (const nlohmann::json::exception& e) {  // out_of_range 406: a number too large for a double (1e400)
        throw InputError(file, std::string("invalid JSON: ") + e.what());
    }
    if (!j.is_object()) throw InputError(file, "a camera must be a JSON object");
    auto vec = [&](const char* key, bool required, glm::dvec3 fallback) {
        if (!j.contains(key)) {
            if (required) throw InputError(file, std::string("camera needs \"") + key + "\": [x, y, z]");
            return fallback;
        }
        const auto& v = j[key];
        if (!v.is_array() || v.size() != 3 || !v[0].is_number() || !v[1].is_number() || !v[2].is_number())
            throw InputError(file, std::string("\"") + key + "\" must be [x, y, z], found " + v.dump());
        return glm::dvec3(v[0].get<double>(), v[1].get<double>(), v[2].get<double>());
    };
    auto num = [&](const char* key, double fallback) {
        if (!j.contains(key)) return fallback;
        if (!j[key].is_number()) throw InputError(file, std::string("\"") + key + "\" must be a number");
        return j[key].get<double>();
    };
    Camera cam;
    cam.eye = vec("eye", true, {});
    cam.target = vec("target", true, {});
    cam.up = vec("up", false, {0.0, 1.0, 0.0});
    cam.fovy_deg = num("fovy_deg", 30.0);
    if (j.contains("projection")) {
        const auto& p = j["projection"];
        if (p == "orthographic")
            cam.orthographic = true;
        else if (p != "perspective")
            throw InputError(file, "\"projection\" must be \"perspective\" or \"orthographic\", found " + p.dump());
    }
    if (cam.orthographic && !j.contains("ortho_height"))
        throw InputError(file, "an orthographic camera needs \"ortho_height\"");
    cam.ortho_height = num("ortho_height", 1.0);
    validate_camera(cam, file);
    return cam;
}

Camera load_camera(const std::string& path) { return parse_camera(read_file_bytes(path), path); }

std::string camera_json(const Camera& cam)
{
    nlohmann::json j;
    j["eye"] = {cam.eye.x, cam.eye.y, cam.eye.z};
    j["target"] = {cam.target.x, cam.target.y, cam.target.z};
    j["up"] = {cam.up.x, cam.up.y, cam.up.z};
    j["fovy_deg"] = cam.fovy_deg;
    j["projection"] = cam.orthographic ? "orthographic" : "perspective";
    if (cam.orthographic) j["ortho_height"] = cam.ortho_height;
    return j.dump(1);
}

Camera default_camera(const Bounds& bounds, double aspect, double azimuth_deg, double elevation_deg)
{
    Camera cam;
    cam.target = bounds.center();
    const double radius = std::max(0.5 * glm::length(bounds.extent()), 1e-12);
    const double half_v = 0.5 * radians(cam.fovy_deg);
    const double half_h = std::atan(std::tan(half_v) * aspect);
    const double dist = radius / std::sin(std::min(half_v, half_h));
    const double az = radians(azimuth_deg), el = radians(elevation_deg);
    const glm::dvec3 back(std::cos(el) * std::sin(az), std::sin(el), std::cos(el) * std::cos(az));
    cam.eye = cam.target + dist * back;
    cam.up = glm::dvec3(-std::sin(el) * std::sin(az), std::cos(el), -std::sin(el) * std::cos(az));
    return cam;
}

}  // namespace uvr
