#include "bench/verify.h"

#include <cmath>

#include "reference/error.h"

namespace uvr::cli {

OrderStudy observed_order(const std::vector<double>& h, const std::vector<double>& errors, double expected,
                          const std::string& what, std::size_t min_levels)
{
    if (h.size() != errors.size())
        throw InputError(
            what, "has " + std::to_string(errors.size()) + " levels for " + std::to_string(h.size()) + " values of h");
    if (h.size() < min_levels)
        throw InputError(what,
                         "needs at least " + std::to_string(min_levels) + " levels, found " + std::to_string(h.size()));
    for (std::size_t i = 0; i < h.size(); ++i) {
        if (!(h[i] > 0.0) || !std::isfinite(h[i]))
            throw InputError(what, "h must be positive and finite, found " + std::to_string(h[i]));
        if (i > 0 && !(h[i] < h[i - 1]))
            throw InputError(what, "h must decrease from level to level, found " + std::to_string(h[i - 1]) + " then " +
                                       std::to_string(h[i]));
        if (!(errors[i] > 0.0) || !std::isfinite(errors[i]))
            throw InputError(what, "level " + std::to_string(i + 1) + "'s error is " + std::to_string(errors[i]) +
                                       ": an order needs positive, finite errors (an exact level has no order)");
    }
    OrderStudy s{h, errors, {}, 0.0, expected, false};
    double mx = 0.0, my = 0.0;
    for (std::size_t i = 0; i < h.size(); ++i) {
        mx += std::log(h[i]);
        my += std::log(errors[i]);
        if (i + 1 < h.size()) s.orders.push_back(std::log(errors[i] / errors[i + 1]) / std::log(h[i] / h[i + 1]));
    }
    mx /= double(h.size());
    my /= double(h.size());
    double sxy = 0.0, sxx = 0.0;
    for (std::size_t i = 0; i < h.size(); ++i) {
        const double dx = std::log(h[i]) - mx;
        sxy += dx * (std::log(errors[i]) - my);
        sxx += dx * dx;
    }
    s.fitted = sxy / sxx;
    s.pass = s.fitted >= expected - kOrderTolerance;
    return s;
}

std::vector<double> halving(double coarsest, int levels)
{
    std::vector<double> h;
    for (int i = 0; i < levels; ++i) h.push_back(std::ldexp(coarsest, -i));
    return h;
}

}  // namespace uvr::cli
