// The ground truth for regular grids: docs/spec.md §1's emission-absorption along a ray through a volume's
// trilinear field, in double, without shading, over the box the samples span. The ray is walked cell by cell; in a
// cell the scalar is a cubic along the ray, cut at its critical points and the transfer function's breakpoints, and
// each piece's emission integral is adaptive Gauss-Kronrod quadrature. docs/reference.md, "Regular grids".
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <glm/vec4.hpp>

#include "reference/camera.h"
#include "reference/ray_integrator.h"
#include "reference/transfer_function.h"
#include "reference/volume.h"

namespace uvr {

// The quadrature to 1e-9. The emission integrals of one ray together err by at most this much per channel
// (each piece gets its share in proportion to its length); alpha is exact up to rounding.
inline constexpr double kVolumeQuadratureTolerance = 1e-10;

class VolumeIntegrator {
public:
    // The volume must outlive the integrator. Scalars are the volume's own values (the transfer function is over them).
    VolumeIntegrator(const Volume& volume, const TransferFunction& tf);

    // Premultiplied RGBA along the ray from t = 0 (the ray's origin, which may lie inside the box) on. Thread-safe.
    // stats.segments counts the cell pieces, stats.entries the rays that met the box.
    glm::dvec4 integrate(const Ray& ray, RayStats& stats) const;

    // The trilinear scalar at world point p (clamped into the box).
    double scalar_at(const glm::dvec3& p) const;

    const Bounds& bounds() const { return box_; }

private:
    const Volume& volume_;
    TransferFunction tf_;
    std::vector<double> breaks_;
    Bounds box_;
    double sample(int64_t i, int64_t j, int64_t k) const;
    // One cell's piece of the ray from t0 to t1, its emission integrals to `tol` together.
    glm::dvec4 integrate_cell(const glm::dvec3& o, const glm::dvec3& d, double t0, double t1, double tol) const;
    using Cubic = std::array<double, 4>;  // in a piece's parameter u, lowest degree first
    // 0, the cubic's critical points in (0, L), where it crosses the transfer function's breakpoints, and L, sorted.
    void split_points(const Cubic& s, double L, std::vector<double>& cuts) const;
    // The piece [ua, ub] of a cell on which s crosses no breakpoint: its emission (to `tol`) and opacity.
    glm::dvec4 integrate_piece(const Cubic& s, double ua, double ub, double tol) const;
};

}  // namespace uvr
