// The emission-absorption integral of an analytic scalar field inside a box, by adaptive quadrature: the exact answer
// against which a mesh that samples the field converges (uvr verify --refine mesh, docs/verification.md).
#pragma once

#include <functional>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "reference/camera.h"
#include "reference/image.h"
#include "reference/mesh.h"
#include "reference/segment_integral.h"

namespace uvr {

using AnalyticField = std::function<double(const glm::dvec3&)>;

// The ray's integral through `box`: the field is taken linear on sub-segments, each integrated in closed form
// (SegmentIntegrator), and a sub-segment is halved until one piece and its two halves differ by at most
// `tolerance` times its share of the ray's length in every channel (the halves' result is kept). The a-posteriori
// estimate bounds each channel's error by about `tolerance` when the field is smooth (the halves err a quarter as
// much as the whole: the piece's error is O(length^3)).
glm::dvec4 integrate_analytic(const AnalyticField& field, const Bounds& box, const SegmentIntegrator& segment,
                              const Ray& ray, double tolerance);

// Every pixel's ray, as render_reference shoots them.
Image render_analytic(const AnalyticField& field, const Bounds& box, const TransferFunction& tf, const Camera& camera,
                      int width, int height, double tolerance);

}  // namespace uvr
