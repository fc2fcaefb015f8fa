// The regular-grid readers: NRRD, MetaImage, SLC and raw, on the shared data sets, hand-made files and broken files.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>

#include <zlib.h>

#include "reference/dataset.h"
#include "test_support.h"

using namespace uvr;
using uvr::test::data_path;
using uvr::test::file_contents;
using uvr::test::file_prefix;
using uvr::test::require_input_error;
using uvr::test::TempDir;

namespace {

// windowBits 31 asks zlib for a gzip wrapper (RFC 1952), 15 for a zlib one (RFC 1950).
std::string deflate_bytes(const std::string& in, int window_bits)
{
    z_stream zs{};
    REQUIRE(deflateInit2(&zs, Z_DEFAULT_COMPRESSION, Z_DEFLATED, window_bits, 8, Z_DEFAULT_STRATEGY) == Z_OK);
    std::string out(deflateBound(&zs, in.size()) + 32, '\0');
    zs.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(in.data()));
    zs.avail_in = static_cast<uInt>(in.size());
    zs.next_out = reinterpret_cast<Bytef*>(out.data());
    zs.avail_out = static_cast<uInt>(out.size());
    REQUIRE(deflate(&zs, Z_FINISH) == Z_STREAM_END);
    out.resize(zs.total_out);
    deflateEnd(&zs);
    return out;
}

template <class T>
std::string bytes_of(const std::vector<T>& values, bool big_endian)
{
    std::string out;
    for (T v : values) {
        char b[sizeof(T)];
        std::memcpy(b, &v, sizeof(T));
        if (big_endian) std::reverse(b, b + sizeof(T));
        out.append(b, sizeof(T));
    }
    return out;
}

// 0, 1, 2, ... as the sample values of a small grid, so that order and position errors show.
template <class T>
std::vector<T> ramp(std::size_t n, T scale = T(1))
{
    std::vector<T> v(n);
    for (std::size_t i = 0; i < n; ++i) v[i] = static_cast<T>(T(i) * scale);
    return v;
}

void check_ramp(const Volume& v, double scale = 1.0)
{
    for (std::size_t i = 0; i < v.values.size(); ++i) {
        INFO("sample " << i);
        REQUIRE(v.values[i] == static_cast<float>(double(i) * scale));
    }
}

// Copies the 93 headsq slices and their header into `tmp`, the slice `broken` cut to `keep` bytes.
std::string copy_headsq(const TempDir& tmp, int broken, std::size_t keep)
{
    for (int i = 1; i <= 93; ++i) {
        const std::string name = "quarter." + std::to_string(i);
        const std::string src = data_path("vtk-data/headsq/" + name);
        tmp.write(name, i == broken ? file_prefix(src, keep) : file_contents(src));
    }
    return tmp.write("quarter.nhdr", file_contents(data_path("vtk-data/headsq/quarter.nhdr")));
}

}  // namespace

TEST_CASE("NRRD reader loads detached series and attached raw, gzip and ascii data")
{
    TempDir tmp("nrrd");
    SECTION("headsq: 93 numbered little-endian int16 slices")
    {
        Dataset d = read_nrrd(data_path("vtk-data/headsq/quarter.nhdr"));
        REQUIRE(d.volume);
        const Volume& v = *d.volume;
        CHECK(v.dims == std::array<int64_t, 3>{64, 64, 93});
        CHECK(v.type == VoxelType::i16);
        CHECK(v.spacing.x == 3.2);
        CHECK(v.spacing.y == 3.2);
        CHECK(v.spacing.z == 1.5);
        CHECK(v.origin == glm::dvec3(0.0));
        const Range r = volume_range(v);
        CHECK(r.lo == 0.0);
        CHECK(r.hi == 3926.0);
        INFO("sample (32, 32, 50) comes from quarter.51");
        CHECK(v.values[32 + 64 * (32 + 64 * 50)] == 872.0f);
    }
    SECTION("attached raw big-endian ushort with space directions, origin and a byte skip")
    {
        const std::string header = "NRRD0005\n# a comment\ntype: unsigned short\ndimension: 3\nsizes: 3 2 2\n"
                                   "endian: big\nencoding: raw\nspace dimension: 3\n"
                                   "space directions: (0.5,0,0) (0,2,0) (0,0,4)\nspace origin: (1,2,3)\n"
                                   "kinds: domain domain domain\nbyte skip: 2\nkey:=value\n\n";
        const std::string path = tmp.write("a.nrrd", header + "##" + bytes_of(ramp<uint16_t>(12, 1000), true));
        Dataset d = read_nrrd(path);
        REQUIRE(d.volume);
        CHECK(d.volume->type == VoxelType::u16);
        CHECK(d.volume->spacing == glm::dvec3(0.5, 2, 4));
        CHECK(d.volume->origin == glm::dvec3(1, 2, 3));
        check_ramp(*d.volume, 1000.0);
    }
    SECTION("attached gzip little-endian float")
    {
        const std::string header = "NRRD0004\ntype: float\ndimension: 3\nsizes: 4 3 2\nspacings: 1 1 2\n"
                                   "endian: little\nencoding: gzip\n\n";
        const std::string path =
            tmp.write("g.nrrd", header + deflate_bytes(bytes_of(ramp<float>(24, 0.25f), false), 31));
        Dataset d = read_nrrd(path);
        REQUIRE(d.volume);
        CHECK(d.volume->type == VoxelType::f32);
        CHECK(d.volume->spacing == glm::dvec3(1, 1, 2));
        check_ramp(*d.volume, 0.25);
    }
    SECTION("attached ascii after a skipped line")
    {
        const std::string path = tmp.write("t.nrrd", "NRRD0001\ntype: int\ndimension: 3\nsizes: 2 2 2\n"
                                                     "encoding: ascii\nline skip: 1\n\nignored line\n"
                                                     "0 1 2 3\n4 5 6 7\n");
        Dataset d = read_nrrd(path);
        REQUIRE(d.volume);
        CHECK(d.volume->type == VoxelType::i32);
        check_ramp(*d.volume);
    }
    SECTION("detached LIST of two files")
    {
        const std::string data = bytes_of(ramp<uint8_t>(18), false);
        tmp.write("part0.raw", data.substr(0, 9));
        tmp.write("part1.raw", data.substr(9));
        const std::string path = tmp.write("l.nhdr", "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 3 3 2\n"
                                                     "encoding: raw\ndata file: LIST\npart0.raw\npart1.raw\n");
        Dataset d = read_nrrd(path);
        REQUIRE(d.volume);
        check_ramp(*d.volume);
    }
    SECTION("a detached file named before its byte skip")
    {
        tmp.write("one.raw", "0123456789" + bytes_of(ramp<uint8_t>(8), false));
        const std::string path = tmp.write("o.nhdr", "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 2 2\n"
                                                     "encoding: raw\ndata file: one.raw\nbyte skip: 10\n");
        Dataset d = read_nrrd(path);
        REQUIRE(d.volume);
        check_ramp(*d.volume);
    }
    SECTION("detached %03d series with a step, each file's data at its end (byte skip -1)")
    {
        const std::string data = bytes_of(ramp<int16_t>(12), false);
        for (int s = 0; s < 3; ++s)
            tmp.write("slice00" + std::to_string(2 * s) + ".raw", "junk" + data.substr(8 * s, 8));
        const std::string path = tmp.write("s.nhdr", "NRRD0004\ntype: short\ndimension: 3\nsizes: 2 2 3\n"
                                                     "endian: little\nencoding: raw\nbyte skip: -1\n"
                                                     "data file: slice%03d.raw 0 4 2 2\n");
        Dataset d = read_nrrd(path);
        REQUIRE(d.volume);
        check_ramp(*d.volume);
    }
}

TEST_CASE("MetaImage reader loads detached and local, raw and compressed images")
{
    TempDir tmp("mhd");
    SECTION("HeadMRVolume.mhd: 48x62x42 uchar, spacing 4")
    {
        Dataset d = read_metaimage(data_path("vtk-data/HeadMRVolume.mhd"));
        REQUIRE(d.volume);
        const Volume& v = *d.volume;
        CHECK(v.dims == std::array<int64_t, 3>{48, 62, 42});
        CHECK(v.type == VoxelType::u8);
        CHECK(v.spacing == glm::dvec3(4.0));
        CHECK(v.origin == glm::dvec3(0.0));
        const Range r = volume_range(v);
        CHECK(r.lo == 0.0);
        CHECK(r.hi == 255.0);
    }
    SECTION(".mha with local zlib-compressed big-endian shorts and an offset")
    {
        const std::string header = "ObjectType = Image\nNDims = 3\nDimSize = 3 2 2\nElementSpacing = 1 2 3\n"
                                   "Offset = -1 0 1\nTransformMatrix = 1 0 0 0 1 0 0 0 1\nElementType = MET_SHORT\n"
                                   "BinaryDataByteOrderMSB = True\nCompressedData = True\nElementDataFile = LOCAL\n";
        const std::string path =
            tmp.write("c.mha", header + deflate_bytes(bytes_of(ramp<int16_t>(12, -3), true), 15));
        Dataset d = read_metaimage(path);
        REQUIRE(d.volume);
        CHECK(d.volume->type == VoxelType::i16);
        CHECK(d.volume->spacing == glm::dvec3(1, 2, 3));
        CHECK(d.volume->origin == glm::dvec3(-1, 0, 1));
        check_ramp(*d.volume, -3.0);
    }
    SECTION(".mhd with ElementSize only and the data at the end of the file (HeaderSize -1)")
    {
        tmp.write("d.raw", "some header" + bytes_of(ramp<double>(8, 0.5), false));
        const std::string path = tmp.write("d.mhd", "NDims = 3\nDimSize = 2 2 2\nElementSize = 2 2 2\n"
                                                    "ElementType = MET_DOUBLE\nHeaderSize = -1\n"
                                                    "ElementDataFile = d.raw\n");
        Dataset d = read_metaimage(path);
        REQUIRE(d.volume);
        CHECK(d.volume->spacing == glm::dvec3(2.0));
        check_ramp(*d.volume, 0.5);
    }
}

TEST_CASE("SLC reader loads run-length encoded and raw slices")
{
    TempDir tmp("slc");
    SECTION("neghip.slc: 66x66x66, 8 bits, RLE")
    {
        Dataset d = read_slc(data_path("vtk-data/neghip.slc"));
        REQUIRE(d.volume);
        const Volume& v = *d.volume;
        CHECK(v.dims == std::array<int64_t, 3>{66, 66, 66});
        CHECK(v.type == VoxelType::u8);
        CHECK(v.spacing == glm::dvec3(1.0));
        const Range r = volume_range(v);
        INFO("range " << r.lo << " .. " << r.hi);
        CHECK(r.hi > 0.0);
        CHECK(r.hi > r.lo);
        CHECK(r.hi <= 255.0);
    }
    SECTION("uncompressed slices after a 2x2 icon")
    {
        const std::string path = tmp.write("u.slc", "11111\n3 2 2 8\n1 1 0.5\n1 6 0 0\n2 2 X" +
                                                         std::string(12, 'i') + bytes_of(ramp<uint8_t>(12), false));
        Dataset d = read_slc(path);
        REQUIRE(d.volume);
        CHECK(d.volume->spacing == glm::dvec3(1, 1, 0.5));
        check_ramp(*d.volume);
    }
    SECTION("RLE slices with repeat and literal runs")
    {
        // Slice 0 is one literal run of 0..5; slice 1 a literal run of 6, 7 and a repeat run of four 9s.
        const std::string s0 = std::string("\x86") + bytes_of(ramp<uint8_t>(6), false) + '\0';
        const std::string s1 = std::string("\x82\x06\x07\x04\x09") + '\0';
        const std::string path = tmp.write("r.slc", "11111\n3 2 2 8\n1 1 1\n1 6 0 1\n0 0 X" +
                                                         std::to_string(s0.size()) + " X" + s0 +
                                                         std::to_string(s1.size()) + " X" + s1);
        Dataset d = read_slc(path);
        REQUIRE(d.volume);
        const std::vector<float> expected = {0, 1, 2, 3, 4, 5, 6, 7, 9, 9, 9, 9};
        CHECK(d.volume->values == expected);
    }
}

TEST_CASE("Raw volume reader takes its size and type from the caller")
{
    TempDir tmp("raw");
    SECTION("neghip 64^3 uint8")
    {
        Dataset d = read_raw_volume(data_path("open-scivis/neghip_64x64x64_uint8.raw"), {64, 64, 64}, "uint8", false);
        REQUIRE(d.volume);
        CHECK(d.volume->dims == std::array<int64_t, 3>{64, 64, 64});
        CHECK(d.volume->type == VoxelType::u8);
        CHECK(d.volume->spacing == glm::dvec3(1.0));
        CHECK(d.volume->origin == glm::dvec3(0.0));
        const Range r = volume_range(*d.volume);
        CHECK(r.lo == 0.0);
        CHECK(r.hi == 255.0);
    }
    SECTION("big-endian int16")
    {
        const std::string path = tmp.write("v.raw", bytes_of(ramp<int16_t>(24, -7), true));
        Dataset d = read_raw_volume(path, {2, 3, 4}, "int16", true);
        REQUIRE(d.volume);
        check_ramp(*d.volume, -7.0);
    }
}

TEST_CASE("Volume readers reject broken files with the file named")
{
    TempDir tmp("vol-bad");
    const std::string ushort_header = "NRRD0004\ntype: ushort\ndimension: 3\nsizes: 2 2 2\nendian: little\n";
    SECTION("NRRD: a truncated headsq slice")
    {
        const std::string nhdr = copy_headsq(tmp, 50, 4000);
        require_input_error([&] { read_nrrd(nhdr); },
                            {tmp.file("quarter.50"), "truncated", "8192 bytes", "only 4000 remain"});
    }
    SECTION("NRRD: a missing headsq slice")
    {
        const std::string nhdr = copy_headsq(tmp, 0, 0);
        std::filesystem::remove(tmp.file("quarter.93"));
        require_input_error([&] { read_nrrd(nhdr); }, {tmp.file("quarter.93"), "cannot open"});
    }
    SECTION("NRRD: truncated attached raw data")
    {
        const std::string p = tmp.write("t.nrrd", ushort_header + "encoding: raw\n\n" + std::string(10, 'x'));
        require_input_error([&] { read_nrrd(p); }, {p, "truncated", "need 16 bytes", "holds only 10 bytes"});
    }
    SECTION("NRRD: truncated gzip data")
    {
        const std::string gz = deflate_bytes(bytes_of(ramp<uint16_t>(8), false), 31);
        const std::string p = tmp.write("t.nrrd", ushort_header + "encoding: gzip\n\n" + gz.substr(0, gz.size() / 2));
        require_input_error([&] { read_nrrd(p); }, {p, "corrupt or truncated compressed data"});
    }
    SECTION("NRRD: wrong magic")
    {
        const std::string p = tmp.write("m.nrrd", "NRRD0009\ntype: uchar\n");
        require_input_error([&] { read_nrrd(p); }, {p + ":1:", "not a NRRD file", "NRRD0009"});
    }
    SECTION("NRRD: empty file")
    {
        const std::string p = tmp.write("e.nrrd", "");
        require_input_error([&] { read_nrrd(p); }, {p, "empty file"});
    }
    SECTION("NRRD: a header claiming 8*10^9 samples fails at once")
    {
        const std::string p = tmp.write("h.nrrd", "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2000 2000 2000\n"
                                                  "encoding: raw\n\nabc");
        require_input_error([&] { read_nrrd(p); }, {p, "truncated", "8000000000 samples", "3 bytes"});
    }
    SECTION("NRRD: a header claiming 10^12 samples fails at once")
    {
        const std::string p = tmp.write("h.nrrd", "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 10000 10000 10000\n"
                                                  "encoding: raw\n\nabc");
        require_input_error([&] { read_nrrd(p); }, {p, "more samples than uvr can hold"});
    }
    SECTION("NRRD: rotated space directions")
    {
        const std::string p = tmp.write("r.nrrd", ushort_header + "space directions: (0,1,0) (1,0,0) (0,0,1)\n"
                                                                  "encoding: raw\n\n" + std::string(16, 'x'));
        require_input_error([&] { read_nrrd(p); }, {p + ":6:", "not axis-aligned"});
    }
    SECTION("NRRD: multi-byte samples without endian")
    {
        const std::string p = tmp.write("n.nrrd", "NRRD0004\ntype: short\ndimension: 3\nsizes: 1 1 1\n"
                                                  "encoding: raw\n\nxx");
        require_input_error([&] { read_nrrd(p); }, {p, "no 'endian' field"});
    }
    SECTION("NRRD: a 2D image")
    {
        const std::string p = tmp.write("2.nrrd", "NRRD0004\ntype: uchar\ndimension: 2\nsizes: 2 2\n");
        require_input_error([&] { read_nrrd(p); }, {p + ":3:", "3D volumes only"});
    }
    SECTION("NRRD: an unsupported encoding")
    {
        const std::string p = tmp.write("b.nrrd", ushort_header + "encoding: bzip2\n\nxxxx");
        require_input_error([&] { read_nrrd(p); }, {p, "unsupported encoding 'bzip2'"});
    }
    SECTION("MetaImage: a truncated HeadMRVolume.raw")
    {
        tmp.write("HeadMRVolume.raw", file_prefix(data_path("vtk-data/HeadMRVolume.raw"), 100000));
        const std::string mhd = tmp.write("HeadMRVolume.mhd", file_contents(data_path("vtk-data/HeadMRVolume.mhd")));
        require_input_error([&] { read_metaimage(mhd); },
                            {tmp.file("HeadMRVolume.raw"), "truncated", "48x62x42", "124992 bytes", "hold 100000"});
    }
    SECTION("MetaImage: empty file")
    {
        const std::string p = tmp.write("e.mhd", "");
        require_input_error([&] { read_metaimage(p); }, {p, "empty file"});
    }
    SECTION("MetaImage: a header claiming 8*10^9 samples fails at once")
    {
        const std::string p = tmp.write("h.mha", "NDims = 3\nDimSize = 2000 2000 2000\nElementType = MET_UCHAR\n"
                                                 "ElementDataFile = LOCAL\nabc");
        require_input_error([&] { read_metaimage(p); }, {p, "truncated", "8000000000 bytes", "hold 3"});
    }
    SECTION("MetaImage: not a header")
    {
        const std::string p = tmp.write("x.mhd", "NDims = 3\nthis is not a header line\n");
        require_input_error([&] { read_metaimage(p); }, {p + ":2:", "expected 'Key = Value'"});
    }
    SECTION("MetaImage: an unsupported element type")
    {
        const std::string p = tmp.write("l.mhd", "NDims = 3\nDimSize = 1 1 1\nElementType = MET_LONG_LONG\n");
        require_input_error([&] { read_metaimage(p); }, {p + ":3:", "unsupported ElementType 'MET_LONG_LONG'"});
    }
    SECTION("SLC: a truncated neghip.slc")
    {
        const std::string p = tmp.write("neghip.slc", file_prefix(data_path("vtk-data/neghip.slc"), 100000));
        require_input_error([&] { read_slc(p); }, {p, "truncated", "slice"});
    }
    SECTION("SLC: wrong magic")
    {
        const std::string p = tmp.write("m.slc", "11112\n3 2 2 8\n");
        require_input_error([&] { read_slc(p); }, {p + ":1:", "not an SLC file", "11112"});
    }
    SECTION("SLC: empty file")
    {
        const std::string p = tmp.write("e.slc", "");
        require_input_error([&] { read_slc(p); }, {p, "empty file"});
    }
    SECTION("SLC: a header claiming 10^12 samples fails at once")
    {
        const std::string p = tmp.write("h.slc", "11111\n10000 10000 10000 8\n1 1 1\n1 6 0 0\n0 0 X");
        require_input_error([&] { read_slc(p); }, {p, "truncated", "10000x10000x10000"});
    }
    SECTION("SLC: an RLE run that overruns its slice")
    {
        const std::string s0 = "\x7f\x01";
        const std::string p = tmp.write("o.slc", "11111\n2 2 1 8\n1 1 1\n1 6 0 1\n0 0 X2 X" + s0);
        require_input_error([&] { read_slc(p); }, {p, "corrupt RLE data in slice 0", "more than the 4 samples"});
    }
    SECTION("SLC: 16-bit samples")
    {
        const std::string p = tmp.write("b.slc", "11111\n2 2 1 16\n");
        require_input_error([&] { read_slc(p); }, {p + ":2:", "16 bits per voxel"});
    }
    SECTION("raw: a truncated copy of neghip")
    {
        const std::string src = data_path("open-scivis/neghip_64x64x64_uint8.raw");
        const std::string p = tmp.write("n.raw", file_prefix(src, 262000));
        require_input_error([&] { read_raw_volume(p, {64, 64, 64}, "uint8", false); },
                            {p, "truncated", "64x64x64 uint8", "exactly 262144 bytes", "holds 262000"});
    }
    SECTION("raw: a file longer than its dimensions")
    {
        const std::string p = data_path("open-scivis/neghip_64x64x64_uint8.raw");
        require_input_error([&] { read_raw_volume(p, {64, 64, 32}, "uint8", false); }, {p, "too long", "131072"});
    }
    SECTION("raw: empty file")
    {
        const std::string p = tmp.write("e.raw", "");
        require_input_error([&] { read_raw_volume(p, {1, 1, 1}, "uint8", false); }, {p, "truncated", "holds 0"});
    }
    SECTION("raw: dimensions of 10^12 samples fail at once")
    {
        const std::string p = tmp.write("h.raw", "abc");
        require_input_error([&] { read_raw_volume(p, {10000, 10000, 10000}, "uint8", false); },
                            {p, "more samples than uvr can hold"});
    }
    SECTION("raw: an unknown type")
    {
        const std::string p = tmp.write("t.raw", "abcd");
        require_input_error([&] { read_raw_volume(p, {1, 1, 1}, "complex", false); }, {p, "unknown voxel type"});
    }
}

TEST_CASE("the built-in volume is a fuzzy torus on a 64 x 64 x 32 grid, loaded like a file")
{
    const uvr::Dataset d = uvr::load_dataset("builtin:torus-volume");
    REQUIRE(d.volume.has_value());
    const uvr::Volume& v = *d.volume;
    CHECK(v.dims == std::array<int64_t, 3>{64, 64, 32});
    const uvr::Range r = uvr::volume_range(v);
    INFO("range " << r.lo << " .. " << r.hi);
    CHECK(r.lo >= 0.0);
    CHECK(r.lo < 1e-3);  // at the box's corners, 4 tube radii from the core circle, exp(-16) and less
    // Next to the core circle exp(-(d / r)^2) is about 1: the largest sample is at least the wave's largest value on
    // the circle (x, y) = (cos t, sin t), found here by a fine walk round it, less 2 % (a sample is at most half a
    // spacing, 0.05 < r / 8, off the circle: exp(-1/64)); off the circle inside the tube the product can be a little
    // larger, never above 1.
    double wave_max = 0.0;
    for (int i = 0; i < 100000; ++i) {
        const double t = 2.0 * 3.14159265358979323846 * i / 100000.0;
        wave_max = std::max(wave_max, 0.75 + 0.25 * std::sin(3.0 * std::cos(t)) * std::cos(2.0 * std::sin(t)));
    }
    INFO("the wave's largest value on the core circle: " << wave_max);
    CHECK(r.hi >= 0.98 * wave_max);
    CHECK(r.hi <= 1.0);
    // The grid's centre lies in the torus's hole: one tube radius and more from the core circle.
    const std::size_t centre = std::size_t((16 * 64 + 32) * 64 + 32);
    CHECK(v.values[centre] < 0.01f);
}

