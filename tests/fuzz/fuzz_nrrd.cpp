// libFuzzer target: NRRD with attached data (.nrrd) through uvr::read_nrrd. Detached data files named by the
// header are looked up beside the input (and are absent unless the header names the input itself).
#include "reference/dataset.h"
#include "tests/fuzz/fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size)
{
    const std::string_view in = uvr_fuzz::as_view(data, size);
    if (uvr_fuzz::names_system_path(in)) return -1;  // a detached "data file" naming a device (fuzz_common.h)
    const std::string path = uvr_fuzz::write_file("input.nrrd", in);
    return uvr_fuzz::expect_input_error_only([&] { uvr::read_nrrd(path); });
}
