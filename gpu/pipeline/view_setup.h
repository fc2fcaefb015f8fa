// The view of a frame, for the vertex stage and the CPU stages of HAVS and VICP: the view, projection and
// model-view-projection matrices, built in double from the camera (docs/spec.md §2) and rounded to float once, for
// points relative to an origin (HAVS and VICP pass the eye); the near and far planes (kNearPlane, kNearMargin); and, in
// double, the window coordinates, 1 / w and eye-space positions the fragment stages' constants are built from. Input:
// camera, size, bounds, origin. Output: ViewSetup. Twins: none (CPU stage). Its float mvp is the uniform of
// shaders/clip_position.vert (havs_mvp, vicp_mvp), whose product gpu/pipeline/clip_position.h emulates. Derivation:
// docs/rasterizer.md, "The vertex stage".
#pragma once

#include <array>

#include <glm/vec3.hpp>

#include "reference/camera.h"
#include "reference/mesh.h"

namespace uvr::gpu {

// Column-major 4x4, as GLSL's mat4: m[c][r] is column c, row r.
using Mat4f = std::array<std::array<float, 4>, 4>;

// The vertex program that turns a vertex-buffer position into clip coordinates (gpu/pipeline/clip_position.h): uvr's
// GLSL rows on the matrix built in double, or the paper's ARB program (DP4 rows on the driver's float product).
enum class VertexProgram { uvr, published };

struct ViewSetup {
    Mat4f view;        // world -> eye (rigid: distances are world units); the eye looks down -z
    Mat4f projection;  // eye -> clip (OpenGL conventions, depth in [-1, 1])
    Mat4f mvp;         // projection * view, multiplied in double before rounding
    // The paper's vertex program (HAVS, --interpolation gpu) reads state.matrix.mvp: the product the GL driver makes of
    // the float projection and model-view it was given (driver_matrix_product, gpu/pipeline/clip_position.h).
    Mat4f driver_mvp;
    VertexProgram program = VertexProgram::uvr;  // which program computes the positions (vertex_position)
    std::array<std::array<double, 4>, 4> mvp_d;  // the same in double (the fragment stage's exact geometry)
    bool near_cuts = false;  // the near plane lies in front of part of the bounds: the clip stage cuts there
};

// The near distance when the eye is inside or close to the bounds, as a fraction of the bounds' diagonal. HAVS
// integrates the ray from there on, so a camera inside the mesh misses the first 1e-6 of the diagonal (an opacity of at
// most the extinction times that); VICP integrates from the eye, but a cell wholly nearer than this is not drawn. Not
// smaller, so that the near plane stays far above the double rounding of the clip coordinates of points a diagonal
// away.
inline constexpr double kNearPlane = 1e-6;

// How far inside the GPU's near plane the clip stage clips, in normalized depth (z / w = -1 + kNearMargin): some 500
// times the float rounding of z / w there. Under perspective the GPU's plane lies at the near distance and the clip
// stage's at that times (1 + kNearMargin / 2); orthographic, where a normalized depth is a fixed fraction of the
// depth range, the GPU's plane is moved back instead, so that the clip stage's lies at the near distance.
inline constexpr double kNearMargin = 1.0 / 4096.0;

// The far plane encloses `bounds` seen from the camera (with a margin). The near plane lies in front of the whole
// bounds (with a margin) where they allow it, else kNearPlane times the bounds' diagonal in front of the eye; what lies
// nearer is then clipped on the CPU (gpu/pipeline/clip.h) before the draw. Orthographic views too: rays start on the
// image plane, and nothing behind it may be drawn. The matrices take points relative to `origin` (a model matrix's
// translation): the vertex buffer holds p - origin in float, so that a mesh far from the world's origin (coordinates at
// 1e8, features at 1e-3) keeps its features, as a GPU application would do it. HAVS and VICP pass the eye (the clip
// stage needs rounding in proportion to w, gpu/pipeline/clip.h).
ViewSetup view_setup(const Camera& cam, int width, int height, const Bounds& bounds, const glm::dvec3& origin);

// Window coordinates (GL: origin bottom-left) and 1 / w of a point given relative to the setup's origin, in double, for
// a glViewport(0, 0, width, height): the geometry the fragment stage's barycentric weights use. The rasterizer's own
// float coordinates (viewport_transform) agree with these to their rounding.
void window_position_d(const ViewSetup& vs, const glm::dvec3& p, int width, int height, double& x, double& y,
                       double& inv_w);

// Eye-space position (view * vec4(p, 1)).xyz in double of the point at offset d = p - eye, for the CPU stage's
// per-face constants.
glm::dvec3 eye_space(const CameraFrame& frame, const glm::dvec3& d);

}  // namespace uvr::gpu
