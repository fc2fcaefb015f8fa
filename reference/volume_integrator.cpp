#include "reference/volume_integrator.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <glm/common.hpp>

namespace uvr {

namespace {

// A polynomial in the piece's local parameter u, lowest degree first.
using Cubic = std::array<double, 4>;

double eval(const Cubic& p, double u) { return ((p[3] * u + p[2]) * u + p[1]) * u + p[0]; }
// The antiderivative vanishing at 0.
double eval_integral(const Cubic& p, double u)
{
    return (((p[3] / 4.0 * u + p[2] / 3.0) * u + p[1] / 2.0) * u + p[0]) * u;
}

// QUADPACK's qk15: Kronrod nodes on [0, 1] of the half interval (the last is the centre), Kronrod weights, and the
// weights of the embedded 7-point Gauss rule on the odd-indexed nodes.
constexpr double kXgk[8] = {0.991455371120812639206854697526329, 0.949107912342758524526189684047851,
                            0.864864423359769072789712788640926, 0.741531185599394439863864773280788,
                            0.586087235467691130294144845693013, 0.405845151377397166906606412076961,
                            0.207784955007898467600689403773245, 0.0};
constexpr double kWgk[8] = {0.022935322010529224963732008058970, 0.063092092629978553290700663189204,
                            0.104790010322250183839876322541518, 0.140653259715525918745189590510238,
                            0.169004726639267902826583426598550, 0.190350578064785409913256402421014,
                            0.204432940075298892414161999234649, 0.209482141084727828012999174891714};
constexpr double kWg[4] = {0.129484966168869693270611432679082, 0.279705391489276667901467771423780,
                           0.381830050505118944950369775488975, 0.417959183673469387755102040816327};

// Recursion limit of the adaptive quadrature: 2^-40 of a piece is below any length a double ray parameter resolves.
constexpr int kMaxQuadratureDepth = 40;

// Adaptive Gauss-Kronrod of a 3-vector function on [a, b] to absolute tolerance `tol` (the largest channel's
// Kronrod-Gauss difference).
template <class F>
glm::dvec3 integrate_gk(const F& f, double a, double b, double tol, int depth = 0)
{
    const double c = 0.5 * (a + b), h = 0.5 * (b - a);
    glm::dvec3 k = kWgk[7] * f(c), g = kWg[3] * f(c);
    for (int i = 0; i < 7; ++i) {
        const glm::dvec3 sum = f(c - h * kXgk[i]) + f(c + h * kXgk[i]);
        k += kWgk[i] * sum;
        if (i % 2 == 1) g += kWg[i / 2] * sum;
    }
    k *= h;
    g *= h;
    const glm::dvec3 e = glm::abs(k - g);
    if (std::max({e.x, e.y, e.z}) <= tol || depth >= kMaxQuadratureDepth) return k;
    return integrate_gk(f, a, c, 0.5 * tol, depth + 1) + integrate_gk(f, c, b, 0.5 * tol, depth + 1);
}

// A crossing is found when its bracket, or Newton's last step, is at most this many ulps of the stretch's far end:
// a few ulps, the noise of evaluating the cubic near its root, and far below any length the integral resolves.
constexpr double kCrossingUlps = 4.0;
// Newton's method converges in a handful of steps; the bisections it falls back on halve the bracket each, so 200
// steps reach the last representable midpoint of any stretch of doubles.
constexpr int kMaxCrossingSteps = 200;

// Where the cubic p reaches `value` on [a, b], on which it is monotone and changes sign against value: Newton's method
// kept inside the bracket, bisecting where a step would leave it or not halve the bracket's error.
double crossing(const Cubic& p, double value, double a, double b)
{
    const bool rising = eval(p, b) > eval(p, a);
    const double tol = kCrossingUlps * std::numeric_limits<double>::epsilon() * std::max(std::abs(a), std::abs(b));
    double u = 0.5 * (a + b), last_step = b - a;
    for (int it = 0; it < kMaxCrossingSteps && b - a > tol; ++it) {
        const double f = eval(p, u) - value;
        if (f == 0.0) return u;
        ((f < 0.0) == rising ? a : b) = u;
        const double slope = (3.0 * p[3] * u + 2.0 * p[2]) * u + p[1];
        double next = u - f / slope;
        if (!(next > a && next < b) || std::abs(next - u) > 0.5 * last_step) next = 0.5 * (a + b);
        last_step = std::abs(next - u);
        if (last_step <= tol) return next;
        u = next;
    }
    return 0.5 * (a + b);
}

// The trilinear scalar along a piece as a cubic in u, from the cell's corner values (corner bits x, y, z) and the
// local coordinates x_a(u) = x0[a] + u * dx[a]: the sum over the corners of v * prod_a (corner_a ? x_a : 1 - x_a).
Cubic trilinear_along(const double corners[8], const double x0[3], const double dx[3])
{
    Cubic s{0.0, 0.0, 0.0, 0.0};
    for (int corner = 0; corner < 8; ++corner) {
        Cubic p{corners[corner], 0.0, 0.0, 0.0};
        for (int a = 0; a < 3; ++a) {
            // Multiply by (alpha + beta u).
            const bool high = (corner >> a) & 1;
            const double alpha = high ? x0[a] : 1.0 - x0[a], beta = high ? dx[a] : -dx[a];
            for (std::size_t deg = 3; deg > 0; --deg) p[deg] = alpha * p[deg] + beta * p[deg - 1];
            p[0] *= alpha;
        }
        for (int deg = 0; deg < 4; ++deg) s[std::size_t(deg)] += p[std::size_t(deg)];
    }
    return s;
}

}  // namespace

VolumeIntegrator::VolumeIntegrator(const Volume& volume, const TransferFunction& tf)
    : volume_(volume), tf_(tf), breaks_(tf.breakpoints()), box_(volume_bounds(volume))
{
}

double VolumeIntegrator::sample(int64_t i, int64_t j, int64_t k) const
{
    const auto& d = volume_.dims;
    return double(volume_.values[std::size_t(i + d[0] * (j + d[1] * k))]);
}

double VolumeIntegrator::scalar_at(const glm::dvec3& p) const
{
    int64_t c[3];
    double f[3];
    for (int a = 0; a < 3; ++a) {
        const int64_t n = volume_.dims[std::size_t(a)];
        const double x = std::clamp((p[a] - volume_.origin[a]) / volume_.spacing[a], 0.0, double(n - 1));
        c[a] = std::min<int64_t>(int64_t(std::floor(x)), std::max<int64_t>(n - 2, 0));
        f[a] = n > 1 ? x - double(c[a]) : 0.0;
    }
    double s = 0.0;
    for (int corner = 0; corner < 8; ++corner) {
        const int64_t di = corner & 1, dj = (corner >> 1) & 1, dk = (corner >> 2) & 1;
        const double w = (di ? f[0] : 1.0 - f[0]) * (dj ? f[1] : 1.0 - f[1]) * (dk ? f[2] : 1.0 - f[2]);
        if (w != 0.0) s += w * sample(c[0] + di, c[1] + dj, c[2] + dk);
    }
    return s;
}

glm::dvec4 VolumeIntegrator::integrate_cell(const glm::dvec3& o, const glm::dvec3& d, double t0, double t1,
                                            double tol) const
{
    // The cell holding the piece's midpoint.
    const glm::dvec3 mid = o + (0.5 * (t0 + t1)) * d;
    int64_t c[3];
    for (int a = 0; a < 3; ++a) {
        const double x = (mid[a] - volume_.origin[a]) / volume_.spacing[a];
        c[a] = std::clamp<int64_t>(int64_t(std::floor(x)), 0, volume_.dims[std::size_t(a)] - 2);
    }
    // Inside its cell the trilinear scalar lies between the corners' least and greatest: a cell where extinction is
    // zero over that range adds nothing (C = 0 and alpha = 0 exactly) and is not integrated.
    double corners[8];
    for (int corner = 0; corner < 8; ++corner)
        corners[corner] = sample(c[0] + (corner & 1), c[1] + ((corner >> 1) & 1), c[2] + ((corner >> 2) & 1));
    const auto [lo, hi] = std::minmax_element(corners, corners + 8);
    if (tf_.clear_between(*lo, *hi)) return glm::dvec4(0.0);
    // The local coordinates along the piece, x_a(u) = x0[a] + u * dx[a] for u in [0, L].
    const double L = t1 - t0;
    double x0[3], dx[3];
    for (int a = 0; a < 3; ++a) {
        const double lo = volume_.origin[a] + double(c[a]) * volume_.spacing[a];
        x0[a] = (o[a] + t0 * d[a] - lo) / volume_.spacing[a];
        dx[a] = d[a] / volume_.spacing[a];
    }
    const Cubic s = trilinear_along(corners, x0, dx);
    // The split points, in a buffer each thread keeps (integrate_cell runs once per cell a ray crosses).
    thread_local std::vector<double> cuts;
    split_points(s, L, cuts);
    glm::dvec4 acc(0.0);
    for (std::size_t m = 1; m < cuts.size(); ++m) {
        const double ua = cuts[m - 1], ub = cuts[m];
        if (ub > ua) acc = composite_over(acc, integrate_piece(s, ua, ub, tol * (ub - ua) / L));
    }
    return acc;
}

void VolumeIntegrator::split_points(const Cubic& s, double L, std::vector<double>& cuts) const
{
    // The cubic's critical points inside (0, L), then where it crosses a breakpoint of the transfer function.
    cuts.assign(1, 0.0);
    const double qa = 3.0 * s[3], qb = 2.0 * s[2], qc = s[1];
    const auto critical = [&](double u) {
        if (u > 0.0 && u < L) cuts.push_back(u);
    };
    if (qa != 0.0) {
        const double disc = qb * qb - 4.0 * qa * qc;
        if (disc >= 0.0) {
            const double q = -0.5 * (qb + std::copysign(std::sqrt(disc), qb));
            if (q != 0.0) critical(qc / q);
            critical(q / qa);
        }
    } else if (qb != 0.0) {
        critical(-qc / qb);
    }
    cuts.push_back(L);
    std::sort(cuts.begin(), cuts.end());
    const std::size_t monotone = cuts.size();
    for (std::size_t m = 1; m < monotone; ++m) {
        const double a = cuts[m - 1], b = cuts[m], sa = eval(s, a), sb = eval(s, b);
        const double s_lo = std::min(sa, sb), s_hi = std::max(sa, sb);
        for (auto br = std::upper_bound(breaks_.begin(), breaks_.end(), s_lo); br != breaks_.end() && *br < s_hi; ++br)
            cuts.push_back(crossing(s, *br, a, b));
    }
    std::sort(cuts.begin(), cuts.end());
}

glm::dvec4 VolumeIntegrator::integrate_piece(const Cubic& s, double ua, double ub, double tol) const
{
    // Colour and extinction are linear in s on the transfer function's interval holding the piece; their
    // coefficients come from values at its 1/3 and 2/3 points (never on a node, where a jump sits).
    const double sm = eval(s, 0.5 * (ua + ub));
    const auto above = std::upper_bound(breaks_.begin(), breaks_.end(), sm);
    double s1 = sm, s2 = sm;
    if (above != breaks_.begin() && above != breaks_.end()) {
        const double lo = *(above - 1), hi = *above;
        s1 = lo + (hi - lo) / 3.0;
        s2 = lo + 2.0 * (hi - lo) / 3.0;
    }
    const double tau1 = tf_.tau_at(s1), dtau = s2 > s1 ? (tf_.tau_at(s2) - tau1) / (s2 - s1) : 0.0;
    const glm::dvec3 c1 = tf_.color_at(s1), dc = s2 > s1 ? (tf_.color_at(s2) - c1) / (s2 - s1) : glm::dvec3(0.0);
    // tau(u) = tau1 + dtau (s(u) - s1): a cubic; T(u) = its integral from ua, a quartic.
    Cubic tau = s;
    for (double& coef : tau) coef *= dtau;
    tau[0] += tau1 - dtau * s1;
    const double Ta = eval_integral(tau, ua);
    const double depth = std::max(0.0, eval_integral(tau, ub) - Ta);
    const auto emission = [&](double u) {
        const double su = eval(s, u);
        const double tu = std::max(0.0, eval(tau, u));
        return (c1 + dc * (su - s1)) * (tu * std::exp(-std::max(0.0, eval_integral(tau, u) - Ta)));
    };
    const glm::dvec3 C = depth > 0.0 ? integrate_gk(emission, ua, ub, tol) : glm::dvec3(0.0);
    return glm::dvec4(C, -std::expm1(-depth));
}

glm::dvec4 VolumeIntegrator::integrate(const Ray& ray, RayStats& stats) const
{
    const auto& dims = volume_.dims;
    if (dims[0] < 2 || dims[1] < 2 || dims[2] < 2) return glm::dvec4(0.0);  // no interior: the box is flat
    // The slab test against the samples' box, from t = 0 on.
    double t_in = 0.0, t_out = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 3; ++a) {
        if (ray.dir[a] == 0.0) {
            if (ray.origin[a] < box_.lo[a] || ray.origin[a] > box_.hi[a]) return glm::dvec4(0.0);
            continue;
        }
        double ta = (box_.lo[a] - ray.origin[a]) / ray.dir[a], tb = (box_.hi[a] - ray.origin[a]) / ray.dir[a];
        if (ta > tb) std::swap(ta, tb);
        t_in = std::max(t_in, ta);
        t_out = std::min(t_out, tb);
    }
    if (!(t_out > t_in)) return glm::dvec4(0.0);
    ++stats.entries;
    // Per axis, the next grid plane the ray crosses after t_in (its index, and the step through the indices).
    int64_t next[3], step[3];
    auto plane_t = [&](int a, int64_t i) {
        return (volume_.origin[a] + double(i) * volume_.spacing[a] - ray.origin[a]) / ray.dir[a];
    };
    for (int a = 0; a < 3; ++a) {
        step[a] = ray.dir[a] > 0.0 ? 1 : -1;
        if (ray.dir[a] == 0.0) {
            next[a] = -1;  // never crossed
            continue;
        }
        const double x = (ray.origin[a] + t_in * ray.dir[a] - volume_.origin[a]) / volume_.spacing[a];
        next[a] = step[a] > 0 ? int64_t(std::floor(x)) : int64_t(std::ceil(x));
        while (next[a] >= 0 && next[a] < dims[std::size_t(a)] && !(plane_t(a, next[a]) > t_in)) next[a] += step[a];
    }
    auto crossing_t = [&](int a) {
        return ray.dir[a] != 0.0 && next[a] >= 0 && next[a] < dims[std::size_t(a)]
                   ? plane_t(a, next[a])
                   : std::numeric_limits<double>::infinity();
    };
    glm::dvec4 acc(0.0);
    const double chord = t_out - t_in;
    double t = t_in;
    while (t < t_out && acc.a < kReferenceOpaque) {
        const double t_next = std::min({crossing_t(0), crossing_t(1), crossing_t(2), t_out});
        if (t_next > t) {
            acc = composite_over(acc, integrate_cell(ray.origin, ray.dir, t, t_next,
                                                     kVolumeQuadratureTolerance * (t_next - t) / chord));
            ++stats.segments;
        }
        for (int a = 0; a < 3; ++a)
            while (crossing_t(a) <= t_next) next[a] += step[a];
        t = t_next;
    }
    return acc;
}

}  // namespace uvr
