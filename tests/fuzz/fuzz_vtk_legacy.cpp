// libFuzzer target: VTK legacy (.vtk, ASCII and BINARY) through uvr::read_vtk_legacy.
#include "reference/dataset.h"
#include "tests/fuzz/fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size)
{
    const std::string_view in = uvr_fuzz::as_view(data, size);
    const std::string path = uvr_fuzz::write_file("input.vtk", in);
    return uvr_fuzz::expect_input_error_only([&] { uvr::read_vtk_legacy(path); });
}
