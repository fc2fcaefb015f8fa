// libFuzzer target: raw volumes through uvr::read_raw_volume. What the command line gives (--dims, --dtype, byte order)
// comes from the input's first 13 bytes: byte 0 picks the voxel type (low 4 bits: an index into kTypes, where the
// last entry is a name the reader must refuse) and the byte order (bit 4: big-endian); bytes 1-12 are the three
// dimensions as little-endian int32 (so zero, negative and huge sizes are tried too). The rest is the file.
#include <array>
#include <cstring>

#include "reference/dataset.h"
#include "tests/fuzz/fuzz_common.h"

namespace {
const char* const kTypes[] = {"uint8",  "int8",  "uint16", "int16", "uint32", "int32", "float32", "float64",
                              "uchar",  "short", "float",  "double", "int",   "unsigned short", "int64", "bogus"};
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size)
{
    if (size < 13) return -1;
    const char* dtype = kTypes[data[0] & 0x0f];
    const bool big_endian = (data[0] & 0x10) != 0;
    std::array<int64_t, 3> dims{};
    for (int a = 0; a < 3; ++a) {
        int32_t d;
        std::memcpy(&d, data + 1 + 4 * a, sizeof d);
        dims[a] = d;
    }
    const std::string path = uvr_fuzz::write_file("input.raw", uvr_fuzz::as_view(data + 13, size - 13));
    return uvr_fuzz::expect_input_error_only([&] { uvr::read_raw_volume(path, dims, dtype, big_endian); });
}
