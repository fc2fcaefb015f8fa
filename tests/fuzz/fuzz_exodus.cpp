// libFuzzer target: Exodus II (.exo) through uvr::read_exodus, at the last time step.
//
// Inputs in HDF5 (netCDF-4) are rejected (return -1: libFuzzer keeps them out of the corpus): libhdf5 1.10 itself
// crashes on some damaged files while netCDF opens them (invalid frees in H5G__dense_iterate), before anything of
// the reader runs, so fuzzing them tests libhdf5 rather than the reader. netCDF classic inputs go through all of the
// reader's checks and then libnetcdf and libexodusii.
#include <cstring>

#include "reference/dataset.h"
#include "tests/fuzz/fuzz_common.h"

// Leaks of the libraries under the reader, not of the reader: libhdf5 allocates its global state on first use and
// never frees it, and libnetcdf 4.9 does not free what it built when it fails to open some damaged files.
extern "C" const char* __lsan_default_suppressions() { return "leak:libhdf5\nleak:libnetcdf\n"; }

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size)
{
    const std::string_view in = uvr_fuzz::as_view(data, size);
    if (in.size() >= 8 && std::memcmp(in.data(), "\x89HDF\r\n\x1a\n", 8) == 0) return -1;
    const std::string path = uvr_fuzz::write_file("input.exo", in);
    return uvr_fuzz::expect_input_error_only([&] { uvr::read_exodus(path, "last"); });
}
