// The ground truth for regular grids: docs/spec.md §1's emission-absorption along a ray through a volume's
// trilinear field, in double, without shading.
//
// The field. Sample (i, j, k) sits at origin + (i, j, k) * spacing (reference/volume.h); between samples the scalar is
// trilinear, so the data's domain is the box spanned by the samples, [origin, origin + (dims - 1) * spacing], and a
// ray is integrated where it lies inside that box. (The GPU ray caster's texture also answers outside it, clamped to
// the edge; that half-voxel rim is the ray caster's, not the data's.)
//
// The walk. Inside the box the ray is cut where it crosses the grid's planes: every crossing of every axis, computed
// from the plane's own coordinate (no accumulated stepping error), merged in order. Each piece between consecutive
// crossings lies in one cell, found from its midpoint, so a ray along a grid plane takes either neighbour: the
// trilinear field is continuous there and both give the same scalar.
//
// One cell. Along the ray each local coordinate is linear in t, so the scalar s(t) is a cubic, exactly. The transfer
// function is piecewise linear in s, so the piece is split again where s(t) crosses one of its breakpoints (the cubic's
// monotone stretches between its critical points, each crossing found by bisection to the last bit). Between splits
// colour c and extinction tau are linear in s, hence cubics in t, and the optical depth T(t) = integral of tau is a
// quartic, exact. The emission integral C = integral of c tau exp(-T) dt has no closed form: adaptive Gauss-Kronrod
// (7/15 points) to an absolute tolerance that sums to kVolumeQuadratureTolerance over the whole ray. The pieces
// composite front to back (docs/spec.md §1).
#pragma once

#include <cstdint>

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
    glm::dvec4 integrate_cell(const glm::dvec3& o, const glm::dvec3& d, double t0, double t1, double tol) const;
};

}  // namespace uvr
