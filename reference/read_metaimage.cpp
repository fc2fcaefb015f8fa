// MetaImage volumes (ITK's MetaIO): .mhd headers with a detached data file, .mha with the data after the header.
//
// Read: NDims 3, one channel, MET_UCHAR/CHAR/SHORT/USHORT/INT/UINT/FLOAT/DOUBLE, uncompressed or zlib-compressed
// (CompressedData True), either byte order, HeaderSize (-1: the data are the file's last bytes). The header is
// "Key = Value" lines ending with ElementDataFile (LOCAL: the data follow that line). A non-identity TransformMatrix
// is refused rather than ignored, since the grid would then be rendered in the wrong place. File lists and numbered
// series (ElementDataFile = LIST, or a %d pattern) are not supported.
#include <array>
#include <cmath>
#include <cstring>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "reference/dataset.h"
#include "reference/error.h"
#include "reference/io_util.h"

namespace uvr {

namespace {

struct Header {
    std::string path;
    long line = 0;
    std::array<int64_t, 3> dims{0, 0, 0};
    std::optional<glm::dvec3> spacing, size, origin;
    std::optional<VoxelType> type;
    bool big_endian = false;
    bool compressed = false;
    int64_t compressed_size = -1;  // -1: not given
    int64_t header_size = 0;
    std::string data_file;
    std::size_t data_offset = 0;  // where LOCAL data begin

    [[noreturn]] void fail(const std::string& what) const { throw InputError(path, line, what); }

    std::vector<double> reals(const std::string& value, std::size_t n, const char* key) const
    {
        TextScanner sc(value, path, false);
        std::vector<double> r;
        try {
            while (!sc.at_end()) r.push_back(sc.real(key));
        } catch (const InputError&) {
            fail(std::string(key) + ": expected numbers, found '" + value.substr(0, 60) + "'");
        }
        if (r.size() != n)
            fail(std::string(key) + ": expected " + std::to_string(n) + " values, found " + std::to_string(r.size()));
        return r;
    }
    int64_t integer(const std::string& value, const char* key) const
    {
        std::vector<double> r = reals(value, 1, key);
        if (r[0] != std::floor(r[0]) || std::abs(r[0]) > 1e15)
            fail(std::string(key) + ": expected an integer, found '" + value + "'");
        return static_cast<int64_t>(r[0]);
    }
    bool boolean(const std::string& value, const char* key) const
    {
        std::string v = lowercase(value);
        if (v == "true" || v == "1") return true;
        if (v == "false" || v == "0") return false;
        fail(std::string(key) + ": expected True or False, found '" + value + "'");
    }
};

std::optional<VoxelType> met_type(const std::string& name)
{
    static const std::pair<const char*, VoxelType> types[] = {
        {"MET_UCHAR", VoxelType::u8},   {"MET_CHAR", VoxelType::i8},   {"MET_USHORT", VoxelType::u16},
        {"MET_SHORT", VoxelType::i16},  {"MET_UINT", VoxelType::u32},  {"MET_INT", VoxelType::i32},
        {"MET_FLOAT", VoxelType::f32},  {"MET_DOUBLE", VoxelType::f64},
    };
    for (const auto& [n, t] : types)
        if (name == n) return t;
    return std::nullopt;
}

Header parse_header(const std::string& path, std::string_view text)
{
    Header h;
    h.path = path;
    std::size_t pos = 0;
    if (text.empty()) throw InputError(path, "empty file: expected a MetaImage header");
    while (pos < text.size()) {
        std::size_t nl = text.find('\n', pos);
        std::string_view l = text.substr(pos, nl == std::string_view::npos ? nl : nl - pos);
        pos = nl == std::string_view::npos ? text.size() : nl + 1;
        ++h.line;
        if (!l.empty() && l.back() == '\r') l.remove_suffix(1);
        if (l.find_first_not_of(" \t") == std::string_view::npos) continue;
        std::size_t eq = l.find('=');
        if (eq == std::string_view::npos)
            h.fail("expected 'Key = Value', found '" + std::string(l.substr(0, 60)) + "'");
        auto key_words = split_words(l.substr(0, eq));
        if (key_words.size() != 1) h.fail("expected 'Key = Value', found '" + std::string(l.substr(0, 60)) + "'");
        const std::string key = lowercase(key_words[0]);
        std::string value;
        for (const std::string& w : split_words(l.substr(eq + 1))) value += (value.empty() ? "" : " ") + w;

        if (key == "ndims") {
            if (h.integer(value, "NDims") != 3) h.fail("NDims is " + value + ": uvr reads 3D volumes only");
        } else if (key == "dimsize") {
            auto d = h.reals(value, 3, "DimSize");
            for (int a = 0; a < 3; ++a) {
                if (!(d[a] >= 1) || d[a] != std::floor(d[a]) || d[a] > 1e15)
                    h.fail("DimSize must hold three integers of at least 1, found '" + value + "'");
                h.dims[a] = static_cast<int64_t>(d[a]);
            }
        } else if (key == "elementspacing" || key == "elementsize" || key == "offset" || key == "origin" ||
                   key == "position") {
            auto r = h.reals(value, 3, key_words[0].c_str());
            glm::dvec3 v(r[0], r[1], r[2]);
            (key == "elementspacing" ? h.spacing : key == "elementsize" ? h.size : h.origin) = v;
        } else if (key == "elementtype") {
            h.type = met_type(value);
            if (!h.type) h.fail("unsupported ElementType '" + value + "' (uvr reads MET_UCHAR, MET_CHAR, MET_SHORT, "
                                "MET_USHORT, MET_INT, MET_UINT, MET_FLOAT, MET_DOUBLE)");
        } else if (key == "elementbyteordermsb" || key == "binarydatabyteordermsb") {
            h.big_endian = h.boolean(value, key_words[0].c_str());
        } else if (key == "compresseddata") {
            h.compressed = h.boolean(value, "CompressedData");
        } else if (key == "compresseddatasize") {
            h.compressed_size = h.integer(value, "CompressedDataSize");
            if (h.compressed_size < 0) h.fail("CompressedDataSize must not be negative");
        } else if (key == "headersize") {
            h.header_size = h.integer(value, "HeaderSize");
            if (h.header_size < -1) h.fail("HeaderSize must be -1 or more");
        } else if (key == "binarydata") {
            if (!h.boolean(value, "BinaryData")) h.fail("ASCII data (BinaryData = False) are not supported");
        } else if (key == "elementnumberofchannels") {
            if (h.integer(value, "ElementNumberOfChannels") != 1)
                h.fail("ElementNumberOfChannels is " + value + ": uvr reads scalar volumes only");
        } else if (key == "transformmatrix" || key == "rotation" || key == "orientation") {
            if (h.reals(value, 9, key_words[0].c_str()) != std::vector<double>{1, 0, 0, 0, 1, 0, 0, 0, 1})
                h.fail(key_words[0] + " is not the identity: uvr renders axis-aligned grids only");
        } else if (key == "elementdatafile") {
            if (value.empty()) h.fail("ElementDataFile names no file");
            if (value.rfind("LIST", 0) == 0 || value.find('%') != std::string::npos)
                h.fail("file lists and numbered series (ElementDataFile = " + value + ") are not supported");
            h.data_file = value;
            h.data_offset = pos;
            break;  // ElementDataFile ends the header; LOCAL data follow
        }
        // Other keys (ObjectType, AnatomicalOrientation, CenterOfRotation, Comment, ...) do not affect the samples.
    }
    if (h.data_file.empty()) h.fail("the header ends without ElementDataFile");
    h.line = 0;
    if (h.dims[0] == 0) h.fail("the header has no DimSize");
    if (!h.type) h.fail("the header has no ElementType");
    return h;
}

}  // namespace

Dataset read_metaimage(const std::string& path)
{
    const std::string text = read_file_bytes(path);
    const Header h = parse_header(path, text);

    const bool local = lowercase(h.data_file) == "local";
    const std::string data_path = local ? path
                                  : h.data_file.front() == '/' ? h.data_file
                                                               : directory_of(path) + h.data_file;
    std::string owned = local ? std::string() : read_file_bytes(data_path);
    std::string_view data = local ? std::string_view(text).substr(h.data_offset) : std::string_view(owned);

    const std::size_t elem = voxel_type_size(*h.type);
    uint64_t samples = 1;
    for (int64_t d : h.dims) {
        if (uint64_t(d) > kMaxElements / samples)
            throw InputError(path, "DimSize describes more samples than uvr can hold");
        samples *= uint64_t(d);
    }
    const uint64_t need = samples * elem;

    std::string inflated;
    if (h.compressed) {
        if (h.header_size == -1) throw InputError(path, "HeaderSize = -1 cannot be used with compressed data");
        if (uint64_t(h.header_size) > data.size())
            throw InputError(data_path, "truncated: HeaderSize " + std::to_string(h.header_size) +
                                            " is larger than the data file");
        data.remove_prefix(h.header_size);
        if (h.compressed_size >= 0) data = data.substr(0, h.compressed_size);
        // Deflate cannot expand data by more than about 1032:1; larger claims are refused before allocating.
        if (need / 1032 > data.size() + 64)
            throw InputError(data_path, "truncated: " + std::to_string(data.size()) +
                                            " compressed bytes cannot hold the " + std::to_string(need) +
                                            " bytes DimSize and ElementType describe");
        inflated = inflate_bytes(data, need, data_path, "the compressed image data");
        data = inflated;
    } else {
        const uint64_t skip = h.header_size == -1 ? (data.size() >= need ? data.size() - need : 0) : h.header_size;
        if (skip > data.size() || data.size() - skip < need)
            throw InputError(data_path, "truncated: a " + std::to_string(h.dims[0]) + "x" + std::to_string(h.dims[1]) +
                                            "x" + std::to_string(h.dims[2]) + " " + voxel_type_name(*h.type) +
                                            " image needs " + std::to_string(need) + " bytes, but the data hold " +
                                            std::to_string(data.size() - std::min<uint64_t>(skip, data.size())) +
                                            (skip ? " after skipping " + std::to_string(skip) : std::string()));
        data = data.substr(skip, need);
    }

    Volume v;
    v.source = path;
    v.dims = h.dims;
    v.type = *h.type;
    v.spacing = h.spacing ? *h.spacing : h.size ? *h.size : glm::dvec3(1.0);
    v.origin = h.origin ? *h.origin : glm::dvec3(0.0);
    v.values.resize(data.size() / voxel_type_size(v.type));
    decode_voxels(data, v.type, h.big_endian, v.values.data());
    finalize_volume(v);
    Dataset result;
    result.volume = std::move(v);
    return result;
}

}  // namespace uvr
