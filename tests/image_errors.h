// docs/spec.md §4's error measures recomputed for the tests, independently of reference/error_measures.cpp (the code
// under test in test_compare), in double over float32 RGBA.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

#include "reference/image.h"

namespace uvr::test {

struct ImageErrors {
    double rmse = 0.0;              // over every channel of every pixel
    double max_abs = 0.0;           // the largest channel error
    double visible_fraction = 0.0;  // pixels whose largest channel error exceeds 1/255
    std::size_t over = 0;           // pixels whose largest channel error exceeds the caller's threshold
};

inline ImageErrors image_errors(const Image& img, const Image& ref,
                                double threshold = std::numeric_limits<double>::infinity())
{
    ImageErrors e;
    double sum = 0.0;
    std::size_t visible = 0;
    const std::size_t pixels = img.rgba.size() / 4;
    for (std::size_t p = 0; p < pixels; ++p) {
        double pw = 0.0;
        for (int c = 0; c < 4; ++c) {
            const double d = std::fabs(double(img.rgba[4 * p + c]) - double(ref.rgba[4 * p + c]));
            sum += d * d;
            pw = std::max(pw, d);
        }
        e.max_abs = std::max(e.max_abs, pw);
        visible += pw > 1.0 / 255.0 ? 1 : 0;
        e.over += pw > threshold ? 1 : 0;
    }
    e.rmse = std::sqrt(sum / double(img.rgba.size()));
    e.visible_fraction = double(visible) / double(pixels);
    return e;
}

// Whether every channel of every pixel is a finite number.
inline bool all_finite(const Image& img)
{
    for (float x : img.rgba)
        if (!std::isfinite(x)) return false;
    return true;
}

}  // namespace uvr::test
