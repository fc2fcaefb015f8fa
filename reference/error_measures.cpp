#include "reference/error_measures.h"

#include <algorithm>
#include <cmath>

#include "reference/error.h"

namespace uvr {

ErrorMeasures measure_errors(ImageView a, ImageView r, int channels)
{
    if (a.width != r.width || a.height != r.height)
        throw InputError("", "cannot compare a " + std::to_string(a.width) + "x" + std::to_string(a.height) +
                                 " image with a " + std::to_string(r.width) + "x" + std::to_string(r.height) +
                                 " reference");
    ErrorMeasures m;
    double sum = 0.0;
    std::size_t visible = 0, covered = 0, empty = 0;
    const std::size_t n = std::size_t(a.width) * std::size_t(a.height);
    for (std::size_t p = 0; p < n; ++p) {
        double worst = 0.0;
        bool blank = true;
        for (int c = 0; c < channels; ++c) {
            const double d = std::fabs(double(a.rgba[4 * p + c]) - double(r.rgba[4 * p + c]));
            sum += d * d;
            worst = std::max(worst, d);
            blank = blank && a.rgba[4 * p + c] == 0.0f;
        }
        m.max_abs = std::max(m.max_abs, worst);
        visible += worst > 1.0 / 255.0 ? 1 : 0;
        const bool covers = double(r.rgba[4 * p + 3]) > 1.0 / 255.0;
        covered += covers ? 1 : 0;
        empty += covers && blank ? 1 : 0;
    }
    m.covered_left_empty = covered ? double(empty) / double(covered) : 0.0;
    m.rmse = n ? std::sqrt(sum / double(std::size_t(channels) * n)) : 0.0;
    m.psnr = m.rmse > 0.0 ? 20.0 * std::log10(1.0 / m.rmse) : INFINITY;
    m.visible_fraction = n ? double(visible) / double(n) : 0.0;
    return m;
}

std::vector<float> pixel_errors(ImageView a, ImageView r, int channels)
{
    measure_errors(a, r, channels);  // size check
    std::vector<float> e(std::size_t(a.width) * std::size_t(a.height));
    for (std::size_t p = 0; p < e.size(); ++p) {
        float worst = 0.0f;
        for (int c = 0; c < channels; ++c) worst = std::max(worst, std::fabs(a.rgba[4 * p + c] - r.rgba[4 * p + c]));
        e[p] = worst;
    }
    return e;
}

void inferno(double t, unsigned char rgb[3])
{
    // Matplotlib's inferno sampled at nine points, interpolated linearly.
    static const double kStops[9][3] = {{0.001, 0.000, 0.014}, {0.088, 0.044, 0.224}, {0.258, 0.039, 0.406},
                                        {0.416, 0.090, 0.433}, {0.578, 0.148, 0.404}, {0.735, 0.216, 0.330},
                                        {0.865, 0.317, 0.226}, {0.955, 0.475, 0.094}, {0.988, 0.998, 0.645}};
    t = std::clamp(t, 0.0, 1.0) * 8.0;
    const int i = std::min(7, int(t));
    const double w = t - i;
    for (int c = 0; c < 3; ++c)
        rgb[c] = static_cast<unsigned char>(std::lround(255.0 * (kStops[i][c] + w * (kStops[i + 1][c] - kStops[i][c]))));
}

std::vector<unsigned char> error_heat_map(const std::vector<float>& errors)
{
    std::vector<unsigned char> rgb(errors.size() * 3, 0);
    const double lo = std::log10(kHeatMin), hi = std::log10(kHeatMax);
    for (std::size_t p = 0; p < errors.size(); ++p) {
        if (!(errors[p] > 0.0f)) continue;
        inferno((std::log10(std::max(double(errors[p]), kHeatMin)) - lo) / (hi - lo), &rgb[3 * p]);
    }
    return rgb;
}

}  // namespace uvr
