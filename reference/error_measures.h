// docs/spec.md §4's error measures of an image against the reference image of the same camera, and the error heat map.
#pragma once

#include <string>
#include <vector>

#include "reference/image.h"

namespace uvr {

// Over all W x H pixels and the four premultiplied channels.
struct ErrorMeasures {
    double rmse = 0.0;
    double max_abs = 0.0;
    double psnr = 0.0;              // 20 log10(1 / rmse); +inf for identical images (JSON: null)
    double visible_fraction = 0.0;  // pixels whose largest channel error exceeds 1/255
    // Not docs/spec.md §4's, beside them for renderers that drop fragments: of the pixels the reference covers (alpha
    // above 1/255, a visible coverage), the fraction where the image is empty (every compared channel exactly 0).
    double covered_left_empty = 0.0;
};

// Throws InputError when the sizes differ. `channels` 3 compares colour only: the image's RGB against the
// reference's premultiplied RGB, which is its colour over black (an outside image without alpha, uvr compare --image).
ErrorMeasures measure_errors(ImageView image, ImageView reference, int channels = 4);

// The largest channel error of each pixel (over `channels`, as above), row 0 at the top.
std::vector<float> pixel_errors(ImageView image, ImageView reference, int channels = 4);

// The heat-map scale: errors are shown on a logarithmic axis from kHeatMin (1e-6, below which float32 images of
// values near 1 cannot differ meaningfully) to kHeatMax (1, the largest possible difference).
inline constexpr double kHeatMin = 1e-6;
inline constexpr double kHeatMax = 1.0;

// RGB8 heat map of per-pixel errors with the perceptual "inferno" colour scale (black = at most kHeatMin, pale
// yellow = kHeatMax); zero-error pixels are black.
std::vector<unsigned char> error_heat_map(const std::vector<float>& errors);

// The colour of a value in [0, 1] on the inferno scale, for legends.
void inferno(double t, unsigned char rgb[3]);

}  // namespace uvr
