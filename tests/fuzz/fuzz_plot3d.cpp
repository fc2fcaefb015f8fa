// libFuzzer target: PLOT3D through uvr::read_plot3d. The input is the XYZ (grid) file, the separator UVRSPLIT, then the
// Q (solution) file; without a separator the grid is read alone (no Q file), as `uvr info grid.xyz` does.
#include "reference/dataset.h"
#include "tests/fuzz/fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size)
{
    bool had_separator = false;
    const auto [xyz, q] = uvr_fuzz::split(uvr_fuzz::as_view(data, size), had_separator);
    const std::string xyz_path = uvr_fuzz::write_file("input.xyz", xyz);
    const std::string q_path = had_separator ? uvr_fuzz::write_file("input.q", q) : std::string();
    return uvr_fuzz::expect_input_error_only([&] { uvr::read_plot3d(xyz_path, q_path); });
}
