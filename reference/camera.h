// The camera of docs/spec.md §2 and the ray through each pixel centre.
#pragma once

#include <string>

#include <glm/vec3.hpp>

#include "reference/mesh.h"

namespace uvr {

struct Camera {
    glm::dvec3 eye{0.0, 0.0, 1.0};
    glm::dvec3 target{0.0};
    glm::dvec3 up{0.0, 1.0, 0.0};
    double fovy_deg = 30.0;
    bool orthographic = false;
    double ortho_height = 1.0;
};

struct Ray {
    glm::dvec3 origin;
    glm::dvec3 dir;  // unit length; distances along the ray are world units from origin
    // Which way the ray moves when its pixel moves right (dx) or up (dy) in the window: the origin's way for an
    // orthographic camera, the direction's for a perspective one (`turns`); zero for a ray no pixel made. A ray in a
    // face's plane, along an edge or through a vertex is decided as the ray of the pixel moved by (e, e^2), e -> 0+
    // (docs/spec.md §7, "Rays on faces, edges and vertices").
    glm::dvec3 pixel_dx{0.0}, pixel_dy{0.0};
    bool turns = false;
};

// The orthonormal frame of docs/spec.md §2: f = normalize(target - eye), r = normalize(f x up), u = r x f.
struct CameraFrame {
    glm::dvec3 f, r, u;
};
CameraFrame camera_frame(const Camera& cam);

// Pixel (i, j): column i from the left, row j from the top, through the pixel centre.
Ray camera_ray(const Camera& cam, int width, int height, double i, double j);

// camera_ray for every pixel of one image, the frame and the lens computed once: the same rays, bit for bit.
class CameraRays {
public:
    CameraRays(const Camera& cam, int width, int height);
    Ray operator()(double i, double j) const;

private:
    Camera cam_;
    CameraFrame fr_;
    int width_, height_;
    double half_;  // half the image's height at unit distance (perspective) or in world units
};

// The pixels whose rays (camera_ray) can meet the box b: columns [x0, x1), rows [y0, y1), possibly empty. The whole
// image where a corner of the box is not in front of a perspective camera's eye (the eye beside or inside the box);
// otherwise the box of the corners' projections widened by one pixel on each side, more than any rounding of a
// projection moves it.
struct PixelRect {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};
PixelRect pixels_covering(const Camera& cam, int width, int height, const Bounds& b);

// JSON {"eye", "target", "up", "fovy_deg", "projection", "ortho_height"}. Throws InputError naming the file: missing or
// non-finite vectors, eye == target, up parallel to the view direction, fovy outside (0, 180), ortho_height <= 0.
Camera load_camera(const std::string& path);
Camera parse_camera(const std::string& json_text, const std::string& file);
void validate_camera(const Camera& cam, const std::string& file);
std::string camera_json(const Camera& cam);

// The default camera: looks at the bounds' centre from +z, far enough that the bounding sphere fits the vertical and
// horizontal field of view (30 degrees vertical), then orbited by azimuth (about +y, towards +x) and elevation (towards
// +y) in degrees; `up` is orbited with it so it never becomes parallel to the view direction.
Camera default_camera(const Bounds& bounds, double width_over_height, double azimuth_deg = 0.0,
                      double elevation_deg = 0.0);

}  // namespace uvr
