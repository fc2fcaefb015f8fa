// SLC volumes (VolVis's format, as read by VTK's vtkSLCReader).
//
// Layout: a text header "11111  nx ny nz bits  sx sy sz  unit_type data_origin data_modification  compression",
// then "icon_width icon_height X" immediately followed by three icon planes (red, green, blue) of width*height bytes,
// then the nz slices of nx*ny 8-bit samples, x fastest. Uncompressed slices (compression 0) follow one another as raw
// bytes; run-length encoded ones (compression 1) are each "size X" immediately followed by `size` bytes of runs: a
// control byte whose low 7 bits are a count, high bit set for that many literal bytes, clear for one byte repeated that
// many times; a zero count ends the slice. Only 8-bit samples exist in practice and only they are accepted.
#include <cctype>
#include <string>
#include <string_view>

#include "reference/dataset.h"
#include "reference/error.h"
#include "reference/io_util.h"

namespace uvr {

namespace {

// Skips whitespace from `pos` and expects the 'X' that ends a size field; returns the offset just past it.
std::size_t expect_x(const std::string& path, std::string_view data, std::size_t pos, const std::string& what)
{
    while (pos < data.size() && std::isspace(static_cast<unsigned char>(data[pos]))) ++pos;
    if (pos >= data.size()) throw InputError(path, "truncated: the file ends before the 'X' after " + what);
    if (data[pos] != 'X')
        throw InputError(path, "expected 'X' after " + what + " at byte offset " + std::to_string(pos) + ", found '" +
                                   std::string(1, data[pos]) + "'");
    return pos + 1;
}

// Reads the decimal "size" that precedes a compressed slice.
uint64_t slice_size(const std::string& path, std::string_view data, std::size_t& pos, int64_t slice)
{
    const std::string what = "the size of slice " + std::to_string(slice);
    while (pos < data.size() && std::isspace(static_cast<unsigned char>(data[pos]))) ++pos;
    if (pos >= data.size()) throw InputError(path, "truncated: the file ends before " + what);
    uint64_t v = 0;
    std::size_t start = pos;
    while (pos < data.size() && std::isdigit(static_cast<unsigned char>(data[pos])) && v <= data.size())
        v = v * 10 + uint64_t(data[pos++] - '0');
    if (pos == start)
        throw InputError(path, "expected " + what + " (a number) at byte offset " + std::to_string(start));
    pos = expect_x(path, data, pos, what);
    return v;
}

// Decodes one run-length encoded slice into out[at .. at + plane).
void decode_rle(const std::string& path, std::string_view in, int64_t slice, std::vector<float>& out, std::size_t at,
                std::size_t plane)
{
    std::size_t i = 0, produced = 0;
    auto overflow = [&] {
        throw InputError(path, "corrupt RLE data in slice " + std::to_string(slice) + ": it decodes to more than the " +
                                   std::to_string(plane) + " samples of a slice");
    };
    while (i < in.size()) {
        const unsigned char control = static_cast<unsigned char>(in[i++]);
        const std::size_t count = control & 0x7f;
        if (count == 0) break;
        if (produced + count > plane) overflow();
        if (control & 0x80) {
            if (count > in.size() - i)
                throw InputError(path, "truncated RLE data in slice " + std::to_string(slice) +
                                           ": a literal run reaches past the slice's bytes");
            for (std::size_t k = 0; k < count; ++k) out[at + produced++] = static_cast<unsigned char>(in[i++]);
        } else {
            if (i >= in.size())
                throw InputError(path, "truncated RLE data in slice " + std::to_string(slice) +
                                           ": a repeat run has no value byte");
            const float value = static_cast<unsigned char>(in[i++]);
            for (std::size_t k = 0; k < count; ++k) out[at + produced++] = value;
        }
    }
    if (produced != plane)
        throw InputError(path, "corrupt RLE data in slice " + std::to_string(slice) + ": it decodes to " +
                                   std::to_string(produced) + " samples, a slice has " + std::to_string(plane));
}

}  // namespace

Dataset read_slc(const std::string& path)
{
    const std::string data = read_file_bytes(path);
    TextScanner sc(data, path, false);
    if (sc.at_end()) throw InputError(path, "empty file: expected the SLC magic number 11111");
    std::string_view magic = sc.token("magic number");
    if (magic != "11111")
        sc.fail("not an SLC file: expected the magic number 11111, found '" + std::string(magic.substr(0, 20)) + "'");

    Volume v;
    v.source = path;
    v.type = VoxelType::u8;
    for (int a = 0; a < 3; ++a) {
        v.dims[a] = sc.integer("dimension");
        if (v.dims[a] < 1) sc.fail("dimensions must be at least 1, found " + std::to_string(v.dims[a]));
    }
    const int64_t bits = sc.integer("bits per voxel");
    if (bits != 8) sc.fail(std::to_string(bits) + " bits per voxel: uvr reads 8-bit SLC files only");
    for (int a = 0; a < 3; ++a) v.spacing[a] = sc.real("spacing");
    sc.integer("unit type");
    sc.integer("data origin");
    sc.integer("data modification");
    const int64_t compression = sc.integer("compression");
    if (compression != 0 && compression != 1)
        sc.fail("unknown compression " + std::to_string(compression) + " (0: none, 1: run-length encoding)");
    const int64_t icon_w = sc.integer("icon width"), icon_h = sc.integer("icon height");
    if (icon_w < 0 || icon_h < 0) sc.fail("negative icon size");

    // Every dimension and the icon are bounded by the file's size before they are multiplied or allocated.
    const uint64_t size = data.size();
    if (uint64_t(icon_w) > size || uint64_t(icon_h) > size || uint64_t(icon_w) * uint64_t(icon_h) > size)
        sc.fail("truncated: the icon of " + std::to_string(icon_w) + "x" + std::to_string(icon_h) +
                " is larger than the file");
    // A compressed slice takes at least a few bytes ("0 X" and a terminator) and can expand at most 127 times.
    const uint64_t limit = compression ? size * 127 : size;
    if (uint64_t(v.dims[0]) > limit || uint64_t(v.dims[2]) > size ||
        uint64_t(v.dims[1]) > limit / uint64_t(v.dims[0]) / uint64_t(v.dims[2]))
        sc.fail("truncated: the header describes " + std::to_string(v.dims[0]) + "x" + std::to_string(v.dims[1]) +
                "x" + std::to_string(v.dims[2]) + " samples, more than the file's " + std::to_string(size) +
                " bytes can hold");

    std::size_t pos = expect_x(path, data, sc.offset(), "the icon size");
    const uint64_t icon_bytes = 3 * uint64_t(icon_w) * uint64_t(icon_h);
    if (icon_bytes > size - pos)
        throw InputError(path, "truncated: the three icon planes need " + std::to_string(icon_bytes) +
                                   " bytes, but only " + std::to_string(size - pos) + " remain");
    pos += icon_bytes;

    const std::size_t plane = std::size_t(v.dims[0]) * std::size_t(v.dims[1]);
    v.values.resize(plane * std::size_t(v.dims[2]));
    std::string_view bytes(data);
    for (int64_t z = 0; z < v.dims[2]; ++z) {
        const std::size_t at = plane * std::size_t(z);
        if (compression == 0) {
            if (plane > size - pos)
                throw InputError(path, "truncated: slice " + std::to_string(z) + " needs " + std::to_string(plane) +
                                           " bytes, but only " + std::to_string(size - pos) + " remain");
            for (std::size_t k = 0; k < plane; ++k) v.values[at + k] = static_cast<unsigned char>(data[pos + k]);
            pos += plane;
        } else {
            const uint64_t n = slice_size(path, bytes, pos, z);
            if (n > size - pos)
                throw InputError(path, "truncated: slice " + std::to_string(z) + " needs " + std::to_string(n) +
                                           " compressed bytes, but only " + std::to_string(size - pos) + " remain");
            decode_rle(path, bytes.substr(pos, n), z, v.values, at, plane);
            pos += n;
        }
    }
    finalize_volume(v);
    Dataset result;
    result.volume = std::move(v);
    return result;
}

}  // namespace uvr
