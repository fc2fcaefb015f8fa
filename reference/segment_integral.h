// The emission-absorption integral of one ray segment (docs/spec.md §1), in closed form, in double precision.
//
// This one function is the ground truth's, the pre-integration tables' and every emulator's "exact" mode.
//
// Derivation. On a piece of length L where colour c and extinction tau are both linear in t, write the optical depth
// T(t) = integral_0^t tau. Because tau(t) exp(-T(t)) = -d/dt exp(-T(t)), integrating by parts gives
//     C = integral_0^L c tau exp(-T) dt = c0 - c1 exp(-T(L)) + (c1 - c0) J,    alpha = 1 - exp(-T(L)),
// with J = (1/L) integral_0^L exp(-T(t)) dt = integral_0^1 exp(-(A u + B u^2)) du, A = tau0 L, B = (tau1 - tau0) L / 2.
// J has the closed forms of Williams, Max & Stein (1998): completing the square,
//     B > 0:  J = sqrt(pi) / (2 sqrt(B)) * (erfcx(x0) - exp(-(A + B)) erfcx(x1)),  x0 = A / (2 sqrt B), x1 = x0 + sqrt B
//     B < 0:  J = (D(y1) - exp(-(A + B)) D(y0)) / sqrt(-B),                      y1 = A / (2 sqrt -B), y0 = y1 - sqrt -B
// (erfcx the scaled complementary error function, D Dawson's integral). Neither overflows: A + B >= 0 because
// tau >= 0 at both ends. Both cancel when |B| is small, so below kSmallQuadratic a series in B is used instead:
//     J = sum_n (-B)^n / n! * M_2n(A),   M_k(A) = integral_0^1 u^k exp(-A u) du.
#pragma once

#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "reference/transfer_function.h"

namespace uvr {

// J above, for A >= 0 and A + 2B >= 0.
double depth_average_transmittance(double A, double B);

// Premultiplied RGBA of a piece on which colour goes linearly c0 -> c1 and extinction tau0 -> tau1 over length L.
glm::dvec4 integrate_linear_piece(const glm::dvec3& c0, const glm::dvec3& c1, double tau0, double tau1, double L);

// Front-to-back composite of `front` then `back` (docs/spec.md §1).
inline glm::dvec4 composite_over(const glm::dvec4& front, const glm::dvec4& back)
{
    const double t = 1.0 - front.a;
    return {front.r + t * back.r, front.g + t * back.g, front.b + t * back.b, front.a + t * back.a};
}

// A segment integrator for one transfer function: splits each segment where the scalar crosses a node of the colour
// or extinction, integrates each piece in closed form and composites the pieces front to back.
class SegmentIntegrator {
public:
    explicit SegmentIntegrator(const TransferFunction& tf);

    // The segment of length `length` on which the scalar goes linearly from s_front to s_back. A zero-length segment
    // contributes nothing.
    glm::dvec4 integrate(double s_front, double s_back, double length) const;

    // out[i] = integrate(s_front[i], s_back[i], length[i]) for i < n, the same bits; thin pieces within one interval of
    // the transfer function (optical size below 1/8) eight at a time in AVX2 lanes where the processor has them.
    void integrate_many(std::size_t n, const double* s_front, const double* s_back, const double* length,
                        glm::dvec4* out) const;

    const TransferFunction& transfer_function() const { return tf_; }

private:
    // Between consecutive breakpoints both colour and extinction are linear in s. Interval k spans
    // [breaks_[k-1], breaks_[k]] (k = 0 and k = breaks_.size() are the constant ends); its values are
    // c(s) = c + dc * (s - lo), tau(s) = tau + dtau * (s - lo), taken from the node interval of the transfer function
    // that contains the interval, so a jump (two nodes at one s) is seen from the correct side at each end.
    struct Piece {
        double lo;
        glm::dvec3 c, dc;
        double tau, dtau;
    };
    glm::dvec4 integrate_piece(const Piece& p, double sa, double sb, double length) const;
    // The piece holding the whole segment from s_front to s_back, as integrate() finds it; null where it crosses a
    // breakpoint. `k`: the interval to try first, set to s_front's (the search's start when the segment crosses).
    const Piece* single_piece(double s_front, double s_back, std::size_t& k) const;

    TransferFunction tf_;
    std::vector<double> breaks_;
    std::vector<Piece> pieces_;  // breaks_.size() + 1
};

// Below this |B| the series in B replaces the erfcx/Dawson forms. The closed forms lose about 1e-16 / sqrt(|B|) to
// cancellation (about 3e-15 at the threshold); the series' first omitted term at the threshold is
// |B|^7 / 7! < 1e-24.
inline constexpr double kSmallQuadratic = 1e-3;

}  // namespace uvr
