// libFuzzer target: transfer-function JSON through uvr::parse_transfer_function (the text load_transfer_function reads
// from its file). A transfer function that parsed must answer every query the renderers make with finite values:
// colour in [0, 1] and extinction >= 0 at, between and beyond its nodes.
#include <cmath>
#include <string>

#include "reference/transfer_function.h"
#include "tests/fuzz/fuzz_common.h"

namespace {
void check_at(const uvr::TransferFunction& tf, double s)
{
    const double tau = tf.tau_at(s);
    uvr_fuzz::require(std::isfinite(tau) && tau >= 0.0, "tau_at(s) is finite and >= 0 for an accepted function");
    const glm::dvec3 c = tf.color_at(s);
    for (int k = 0; k < 3; ++k)
        uvr_fuzz::require(c[k] >= 0.0 && c[k] <= 1.0, "color_at(s) is in [0, 1] for an accepted function");
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size)
{
    const std::string text(uvr_fuzz::as_view(data, size));
    return uvr_fuzz::expect_input_error_only([&] {
        const uvr::TransferFunction tf = uvr::parse_transfer_function(text, "input.json");
        const std::vector<double> breaks = tf.breakpoints();
        for (std::size_t i = 0; i < breaks.size(); ++i) {
            check_at(tf, breaks[i]);
            if (i + 1 < breaks.size()) check_at(tf, 0.5 * breaks[i] + 0.5 * breaks[i + 1]);
        }
        check_at(tf, breaks.front() - 1.0);
        check_at(tf, breaks.back() + 1.0);
        (void)uvr::transfer_function_json(tf);
    });
}
