// VTK XML files: .vtu (UnstructuredGrid, a tetrahedral mesh after tetrahedralize_cells) and .vti (ImageData, a volume).
//
// A DataArray is stored as `ascii` text, as `binary` (base64 in the element), or `appended`: at an offset into the
// AppendedData section, which is raw bytes or base64. Binary and appended arrays start with a header of UInt32 or
// UInt64 words (VTKFile header_type): the byte count, or with vtkZLibDataCompressor the block table (number of blocks,
// block size, size of the last block or 0 when it is full, then the compressed size of each block), followed by the
// zlib streams. Headers and data follow the file's byte_order.
//
// Raw appended bytes are not XML, so the file is cut at the AppendedData start tag: pugixml parses the text before it
// (closed off artificially) and the arrays are read from the bytes after the '_' marker.
#include "reference/dataset.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <optional>

#include <nlohmann/json.hpp>
#include <pugixml.hpp>

#include "reference/cells.h"
#include "reference/error.h"
#include "reference/io_util.h"

namespace uvr {

namespace {

enum class XType { i8, u8, i16, u16, i32, u32, i64, u64, f32, f64 };

struct XTypeName {
    const char* name;
    XType type;
    uint64_t size;
};

constexpr XTypeName kXTypes[] = {
    {"Int8", XType::i8, 1},   {"UInt8", XType::u8, 1},     {"Int16", XType::i16, 2},   {"UInt16", XType::u16, 2},
    {"Int32", XType::i32, 4}, {"UInt32", XType::u32, 4},   {"Int64", XType::i64, 8},   {"UInt64", XType::u64, 8},
    {"Float32", XType::f32, 4}, {"Float64", XType::f64, 8}, {"Char", XType::i8, 1},    {"UChar", XType::u8, 1},
};

// Largest expansion a zlib stream can achieve (deflate's limit is about 1032:1); a block header that claims more is
// hostile or corrupt, and is refused before its output buffer is allocated.
constexpr uint64_t kMaxInflateRatio = 1100;

uint64_t product(uint64_t a, uint64_t b) { return (a != 0 && b > UINT64_MAX / a) ? UINT64_MAX : a * b; }

std::string brief(std::string_view s)
{
    std::string r;
    for (char c : s.substr(0, 40)) r += (c >= 32 && c < 127) ? c : '?';
    if (s.size() > 40) r += "...";
    return r;
}

// Everything the arrays of one file share.
struct XmlFile {
    std::string path;
    bool big_endian = false;
    bool header64 = false;
    bool zlib = false;
    std::string_view appended;               // the bytes after '_' (raw) or the text up to </AppendedData> (base64)
    bool appended_base64 = false;
    bool has_appended = false;
    std::vector<uint64_t> appended_offsets;  // sorted, to find where a base64 array's text ends
    std::vector<std::string> warnings;

    [[noreturn]] void fail(const std::string& what) const { throw InputError(path, what); }
};

std::string array_label(const pugi::xml_node& da)
{
    const char* name = da.attribute("Name").value();
    return *name ? std::string("DataArray '") + name + "'" : std::string("an unnamed DataArray");
}

template <class S, class T>
void convert(const char* p, uint64_t n, bool swap, T* out)
{
    for (uint64_t i = 0; i < n; ++i) {
        S v;
        std::memcpy(&v, p + i * sizeof(S), sizeof(S));
        out[i] = static_cast<T>(swap ? byteswap_value(v) : v);
    }
}

template <class T>
void convert_bytes(XType t, const char* p, uint64_t n, bool swap, T* out)
{
    switch (t) {
    case XType::i8: convert<int8_t>(p, n, swap, out); break;
    case XType::u8: convert<uint8_t>(p, n, swap, out); break;
    case XType::i16: convert<int16_t>(p, n, swap, out); break;
    case XType::u16: convert<uint16_t>(p, n, swap, out); break;
    case XType::i32: convert<int32_t>(p, n, swap, out); break;
    case XType::u32: convert<uint32_t>(p, n, swap, out); break;
    case XType::i64: convert<int64_t>(p, n, swap, out); break;
    case XType::u64: convert<uint64_t>(p, n, swap, out); break;
    case XType::f32: convert<float>(p, n, swap, out); break;
    case XType::f64: convert<double>(p, n, swap, out); break;
    }
}

const XTypeName* find_type(const pugi::xml_node& da)
{
    const std::string t = da.attribute("type").value();
    for (const XTypeName& x : kXTypes)
        if (t == x.name) return &x;
    return nullptr;
}

const XTypeName& array_type(const XmlFile& f, const pugi::xml_node& da)
{
    if (const XTypeName* x = find_type(da)) return *x;
    const std::string t = da.attribute("type").value();
    f.fail(array_label(da) + " has unknown type '" + brief(t) +
           "' (expected Int8, UInt8, Int16, UInt16, Int32, UInt32, Int64, UInt64, Float32 or Float64)");
}

uint64_t read_header_word(BinaryCursor& cur, const XmlFile& f, const char* what)
{
    return f.header64 ? cur.read<uint64_t>(what) : cur.read<uint32_t>(what);
}

// The data bytes of a binary or appended array (header parsed, blocks inflated); exactly `expected` bytes.
// `need` describes the expected contents for messages ("15 Float32 values").
std::string unpack(const XmlFile& f, std::string_view bytes, uint64_t expected, const std::string& label,
                   const std::string& need)
{
    BinaryCursor cur(bytes, f.path, f.big_endian);
    const char* what = label.c_str();
    if (!f.zlib) {
        const uint64_t n = read_header_word(cur, f, what);
        if (n != expected)
            f.fail(label + " holds " + std::to_string(n) + " bytes, but " + need + " need " + std::to_string(expected));
        cur.require(n, what);
        return std::string(cur.rest().substr(0, n));
    }
    const uint64_t blocks = read_header_word(cur, f, what), block_size = read_header_word(cur, f, what),
                   last_size = read_header_word(cur, f, what);
    const uint64_t word = f.header64 ? 8 : 4;
    cur.require(product(blocks, word), what);
    const uint64_t last = last_size ? last_size : block_size;
    const uint64_t full = product(blocks == 0 ? 0 : blocks - 1, block_size);
    const uint64_t total = blocks == 0 ? 0 : (full > UINT64_MAX - last ? UINT64_MAX : full + last);
    if (total != expected || (blocks && (last > block_size)))
        f.fail(label + ": compressed block table describes " + std::to_string(total) + " bytes, but " + need +
               " need " + std::to_string(expected));
    // Every block is checked against the bytes really present before the output is allocated.
    std::vector<uint64_t> sizes(blocks);
    uint64_t compressed = 0;
    for (uint64_t b = 0; b < blocks; ++b) {
        sizes[b] = read_header_word(cur, f, what);
        const uint64_t raw = b + 1 == blocks ? last : block_size;
        if (raw > 1024 && raw - 1024 > product(sizes[b], kMaxInflateRatio))
            f.fail(label + ": compressed block " + std::to_string(b) + " claims " + std::to_string(raw) +
                   " bytes from only " + std::to_string(sizes[b]) + " compressed bytes (corrupt header)");
        compressed = sizes[b] > UINT64_MAX - compressed ? UINT64_MAX : compressed + sizes[b];
    }
    cur.require(compressed, what);
    std::string out;
    out.reserve(expected);
    for (uint64_t b = 0; b < blocks; ++b) {
        out += inflate_bytes(cur.rest().substr(0, sizes[b]), b + 1 == blocks ? last : block_size, f.path, what);
        cur.skip(sizes[b], what);
    }
    return out;
}

std::string payload(const XmlFile& f, const pugi::xml_node& da, const std::string& format, uint64_t expected,
                    const std::string& label, const std::string& need)
{
    if (format == "binary")
        return unpack(f, decode_base64(da.child_value(), f.path, label.c_str()), expected, label, need);
    if (format != "appended")
        f.fail(label + " has unknown format '" + brief(format) + "' (expected ascii, binary or appended)");
    if (!f.has_appended) f.fail(label + " is appended, but the file has no AppendedData section");
    const char* off_text = da.attribute("offset").value();
    uint64_t off = 0;
    auto [p, ec] = std::from_chars(off_text, off_text + std::strlen(off_text), off);
    if (ec != std::errc() || *p != '\0') f.fail(label + " has an invalid offset '" + brief(off_text) + "'");
    if (off > f.appended.size())
        f.fail("truncated: " + label + " starts at appended offset " + std::to_string(off) +
               ", but AppendedData holds " + std::to_string(f.appended.size()) + " bytes");
    if (!f.appended_base64) return unpack(f, f.appended.substr(off), expected, label, need);
    auto next = std::upper_bound(f.appended_offsets.begin(), f.appended_offsets.end(), off);
    const uint64_t end =
        next == f.appended_offsets.end() ? f.appended.size() : std::min<uint64_t>(*next, f.appended.size());
    return unpack(f, decode_base64(f.appended.substr(off, end - off), f.path, label.c_str()), expected, label, need);
}

// Reads exactly `count` values of a DataArray, converted to T.
template <class T>
std::vector<T> read_array(const XmlFile& f, const pugi::xml_node& da, uint64_t count)
{
    const XTypeName& type = array_type(f, da);
    const std::string label = array_label(da);
    if (std::is_integral_v<T> && (type.type == XType::f32 || type.type == XType::f64))
        f.fail(label + " must have an integer type, found " + type.name);
    const std::string format = da.attribute("format").as_string("ascii");
    std::vector<T> out;
    if (format == "ascii") {
        std::string_view text = da.child_value();
        if (count > kMaxElements || (count > 0 && product(count, 2) - 1 > text.size()))
            f.fail("truncated: " + label + " needs " + std::to_string(count) + " values but holds only " +
                   std::to_string(text.size()) + " characters");
        out.resize(count);
        std::size_t pos = 0;
        auto next_token = [&]() -> std::string_view {
            pos = text.find_first_not_of(" \t\r\n", pos);
            if (pos == std::string_view::npos) return {};
            const std::size_t end = std::min(text.find_first_of(" \t\r\n", pos), text.size());
            std::string_view t = text.substr(pos, end - pos);
            pos = end;
            return t;
        };
        for (uint64_t i = 0; i < count; ++i) {
            std::string_view t = next_token();
            if (t.empty())
                f.fail("truncated: " + label + " holds " + std::to_string(i) + " values, expected " +
                       std::to_string(count));
            bool ok;
            if constexpr (std::is_integral_v<T>) {
                int64_t v = 0;
                auto [p, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
                ok = ec == std::errc() && p == t.data() + t.size();
                out[i] = static_cast<T>(v);
            } else {
                double v = 0.0;
                auto [p, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
                if (ec == std::errc::result_out_of_range) v = std::strtod(std::string(t).c_str(), nullptr);
                ok = p == t.data() + t.size() && (ec == std::errc() || ec == std::errc::result_out_of_range);
                out[i] = static_cast<T>(v);
            }
            if (!ok) f.fail(label + ": value " + std::to_string(i) + " is not a number: '" + brief(t) + "'");
        }
        if (!next_token().empty()) f.fail(label + " holds more than the expected " + std::to_string(count) + " values");
        return out;
    }
    const uint64_t bytes = product(count, type.size);
    if (bytes == UINT64_MAX) f.fail(label + " is too large (" + std::to_string(count) + " values)");
    const std::string data = payload(f, da, format, bytes, label, std::to_string(count) + " " + type.name + " values");
    out.resize(count);
    convert_bytes(type.type, data.data(), count, f.big_endian, out.data());
    return out;
}

uint64_t count_attribute(const XmlFile& f, const pugi::xml_node& node, const char* name)
{
    const char* text = node.attribute(name).value();
    uint64_t v = 0;
    auto [p, ec] = std::from_chars(text, text + std::strlen(text), v);
    if (!*text || ec != std::errc() || *p != '\0')
        f.fail(std::string("<") + node.name() + "> needs a non-negative integer " + name + ", found '" + brief(text) +
               "'");
    return v;
}

int components(const XmlFile& f, const pugi::xml_node& da)
{
    const int c = da.attribute("NumberOfComponents").as_int(1);
    if (c < 1) f.fail(array_label(da) + " has NumberOfComponents " + std::to_string(c));
    return c;
}

// The numbers of a text separated by white space; empty unless the whole text is numbers.
std::vector<double> numbers_of_text(const char* s)
{
    std::vector<double> v;
    char* end = nullptr;
    for (double x = std::strtod(s, &end); end != s; x = std::strtod(s, &end)) {
        v.push_back(x);
        s = end;
    }
    while (*s == ' ' || *s == '\t' || *s == '\n' || *s == '\r') ++s;
    if (*s) v.clear();
    return v;
}

// `count` numbers from an attribute such as WholeExtent or Spacing; `fallback` when the attribute is absent.
std::vector<double> number_list(const XmlFile& f, const pugi::xml_node& node, const char* name, std::size_t count,
                                std::vector<double> fallback)
{
    const pugi::xml_attribute attr = node.attribute(name);
    if (!attr) {
        if (fallback.empty()) f.fail(std::string("<") + node.name() + "> has no " + name + " attribute");
        return fallback;
    }
    const std::vector<double> v = numbers_of_text(attr.value());
    if (v.size() != count)
        f.fail(std::string("<") + node.name() + "> " + name + " must be " + std::to_string(count) +
               " numbers, found '" + brief(attr.value()) + "'");
    return v;
}

// One piece's 1-component arrays of `data` (<PointData> or <CellData>, `what` "point" or "cell"), `count` values each,
// appended to the fields of the pieces before it. A field is kept only when every piece has it.
struct PieceArrays {
    std::map<std::string, std::vector<double>> fields;
    std::vector<std::string> order;  // the first piece's order of names
};
void append_piece_arrays(XmlFile& f, const pugi::xml_node& data, uint64_t count, int pieces, const char* what,
                         PieceArrays& out)
{
    std::map<std::string, std::vector<double>> here;
    int unnamed = 0;
    for (const pugi::xml_node& da : data.children("DataArray")) {
        std::string name = da.attribute("Name").value();
        if (name.empty()) name = "array" + std::to_string(unnamed++);
        if (components(f, da) != 1 || !find_type(da)) {
            if (pieces == 0)
                f.warnings.push_back(f.path + ": " + what + " array '" + name + "' (" + da.attribute("type").value() +
                                     ", " + std::to_string(components(f, da)) + " components) ignored: uvr uses " +
                                     "1-component numeric scalars");
            continue;
        }
        if (pieces == 0) out.order.push_back(name);
        here[name] = read_array<double>(f, da, count);
    }
    for (const std::string& name : out.order) {
        auto it = here.find(name);
        if (it == here.end()) continue;
        if (pieces == 0 || out.fields.count(name))
            out.fields[name].insert(out.fields[name].end(), it->second.begin(), it->second.end());
    }
    for (auto it = out.fields.begin(); it != out.fields.end();) {
        if (!here.count(it->first)) {
            f.warnings.push_back(f.path + ": " + what + " array '" + it->first + "' is missing from a piece; ignored");
            it = out.fields.erase(it);
        } else {
            ++it;
        }
    }
}

std::vector<ScalarField> take_fields(PieceArrays& a)
{
    std::vector<ScalarField> out;
    for (const std::string& name : a.order)
        if (a.fields.count(name)) out.push_back({name, std::move(a.fields[name])});
    return out;
}

TetMesh read_unstructured(XmlFile& f, const pugi::xml_node& grid)
{
    UnstructuredCells cells;
    cells.source = f.path;
    cells.offsets.push_back(0);
    // Fields are kept only when every piece has them; each piece's values follow the previous pieces' points (cells).
    PieceArrays point_arrays, cell_arrays;
    int pieces = 0;
    for (const pugi::xml_node& piece : grid.children("Piece")) {
        const uint64_t np = count_attribute(f, piece, "NumberOfPoints");
        const uint64_t nc = count_attribute(f, piece, "NumberOfCells");
        const int64_t base = static_cast<int64_t>(cells.points.size());
        const pugi::xml_node pts = piece.child("Points").child("DataArray");
        if (!pts) f.fail("a Piece has no <Points> DataArray");
        if (components(f, pts) != 3) f.fail("the Points DataArray must have 3 components");
        const std::vector<double> xyz = read_array<double>(f, pts, product(np, 3));
        for (uint64_t i = 0; i < np; ++i) cells.points.push_back({xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]});

        const pugi::xml_node cell_node = piece.child("Cells");
        auto cell_array = [&](const char* name) {
            const pugi::xml_node da = cell_node.find_child_by_attribute("DataArray", "Name", name);
            if (!da) f.fail(std::string("missing required array '") + name + "' in <Cells>");
            return da;
        };
        const std::vector<int64_t> offsets = read_array<int64_t>(f, cell_array("offsets"), nc);
        const std::vector<int64_t> types = read_array<int64_t>(f, cell_array("types"), nc);
        int64_t prev = 0;
        for (uint64_t c = 0; c < nc; ++c) {
            if (offsets[c] < prev)
                f.fail("cell offsets must be non-negative and non-decreasing, but cell " + std::to_string(c) +
                       " ends at " + std::to_string(offsets[c]));
            prev = offsets[c];
        }
        const std::vector<int64_t> conn = read_array<int64_t>(f, cell_array("connectivity"), uint64_t(prev));
        const int64_t conn_base = cells.offsets.back();
        for (uint64_t c = 0; c < nc; ++c) {
            if (types[c] < 0 || types[c] > INT32_MAX)
                f.fail("cell " + std::to_string(c) + " has an invalid cell type " + std::to_string(types[c]));
            cells.types.push_back(static_cast<int32_t>(types[c]));
            cells.offsets.push_back(conn_base + offsets[c]);
        }
        // Shifting by the piece's first point keeps a negative index negative, so tetrahedralize_cells reports it.
        for (int64_t i : conn) cells.connectivity.push_back(i < 0 ? i : i + base);

        append_piece_arrays(f, piece.child("PointData"), np, pieces, "point", point_arrays);
        append_piece_arrays(f, piece.child("CellData"), nc, pieces, "cell", cell_arrays);
        ++pieces;
    }
    if (pieces == 0) f.fail("the UnstructuredGrid has no Piece");
    cells.point_fields = take_fields(point_arrays);
    cells.cell_fields = take_fields(cell_arrays);
    return tetrahedralize_cells(cells, f.warnings);
}

Volume read_image(XmlFile& f, const pugi::xml_node& image)
{
    Volume v;
    v.source = f.path;
    const std::vector<double> ext = number_list(f, image, "WholeExtent", 6, {});
    const std::vector<double> origin = number_list(f, image, "Origin", 3, {0, 0, 0});
    const std::vector<double> spacing = number_list(f, image, "Spacing", 3, {1, 1, 1});
    const std::vector<double> dir = number_list(f, image, "Direction", 9, {1, 0, 0, 0, 1, 0, 0, 0, 1});
    if (dir != std::vector<double>{1, 0, 0, 0, 1, 0, 0, 0, 1})
        f.warnings.push_back(f.path + ": the image's Direction is ignored (uvr volumes are axis-aligned)");
    for (int a = 0; a < 3; ++a) {
        const double lo = ext[2 * a], hi = ext[2 * a + 1];
        if (!std::isfinite(lo) || !std::isfinite(hi) || lo != std::floor(lo) || hi != std::floor(hi) || hi < lo ||
            hi - lo >= double(kMaxElements))
            f.fail("WholeExtent must hold integer ranges lo <= hi, found '" +
                   brief(image.attribute("WholeExtent").value()) + "'");
        v.dims[a] = static_cast<int64_t>(hi - lo) + 1;
        v.spacing[a] = spacing[a];
        // VTK places point i of the extent at Origin + i * Spacing, so a non-zero extent start shifts the first sample.
        v.origin[a] = origin[a] + lo * spacing[a];
    }
    const pugi::xml_node piece = image.child("Piece");
    if (!piece) f.fail("the ImageData has no Piece");
    if (piece.next_sibling("Piece")) f.fail("ImageData with several pieces is not supported");
    if (piece.attribute("Extent") && number_list(f, piece, "Extent", 6, {}) != ext)
        f.fail("the Piece's Extent differs from the WholeExtent (partial images are not supported)");
    const pugi::xml_node pd = piece.child("PointData");
    pugi::xml_node chosen;
    if (const char* active = pd.attribute("Scalars").value(); *active)
        chosen = pd.find_child_by_attribute("DataArray", "Name", active);
    for (pugi::xml_node da = pd.child("DataArray"); da && !chosen; da = da.next_sibling("DataArray"))
        if (components(f, da) == 1) chosen = da;
    if (!chosen) f.fail("missing required array: the ImageData has no 1-component PointData array");
    if (components(f, chosen) != 1) f.fail(array_label(chosen) + " must have 1 component");
    switch (array_type(f, chosen).type) {
    case XType::i8: v.type = VoxelType::i8; break;
    case XType::u8: v.type = VoxelType::u8; break;
    case XType::i16: v.type = VoxelType::i16; break;
    case XType::u16: v.type = VoxelType::u16; break;
    case XType::i32: v.type = VoxelType::i32; break;
    case XType::u32: v.type = VoxelType::u32; break;
    case XType::f32: v.type = VoxelType::f32; break;
    case XType::f64: v.type = VoxelType::f64; break;
    default: f.fail(array_label(chosen) + ": 64-bit integer volumes are not supported");
    }
    v.name = chosen.attribute("Name").value();
    const uint64_t n = product(product(uint64_t(v.dims[0]), uint64_t(v.dims[1])), uint64_t(v.dims[2]));
    v.values = read_array<float>(f, chosen, n);
    if (piece.child("CellData").child("DataArray"))
        f.warnings.push_back(f.path + ": CellData ignored (a regular grid's scalars are point data)");
    finalize_volume(v);
    return v;
}

// Line and column of a byte offset, for XML parse errors.
std::string position_of(std::string_view text, std::size_t offset)
{
    offset = std::min(offset, text.size());
    const long line = 1 + static_cast<long>(std::count(text.begin(), text.begin() + long(offset), '\n'));
    const std::size_t nl = text.rfind('\n', offset == 0 ? 0 : offset - 1);
    const std::size_t col = offset - (nl == std::string_view::npos || offset == 0 ? 0 : nl + 1) + 1;
    return "line " + std::to_string(line) + ", column " + std::to_string(col);
}

// The XML part of the file: all of it, or with an AppendedData section (raw bytes are no XML) everything up to that
// tag, closed; the section's data are left in f.appended.
std::string xml_part(XmlFile& f, const std::string& data)
{
    std::string xml_text = data;
    const std::size_t tag = data.find("<AppendedData");
    if (tag != std::string::npos) {
        const std::size_t gt = data.find('>', tag);
        if (gt == std::string::npos) f.fail("truncated: the file ends inside the AppendedData tag");
        const bool empty_element = data[gt - 1] == '/';
        xml_text = data.substr(0, gt + 1) + (empty_element ? "" : "</AppendedData>") + "</VTKFile>";
        f.has_appended = !empty_element;
        if (f.has_appended) {
            const std::size_t mark = data.find_first_not_of(" \t\r\n", gt + 1);
            if (mark == std::string::npos) f.fail("truncated: the AppendedData section holds no data");
            if (data[mark] != '_') f.fail("the AppendedData section must start with '_'");
            f.appended = std::string_view(data).substr(mark + 1);
        }
    }
    return xml_text;
}

// Parses the XML part into `doc`; a parse error names its place, or the truncation that caused it.
void parse_xml(XmlFile& f, const std::string& xml_text, pugi::xml_document& doc)
{
    const pugi::xml_parse_result parsed = doc.load_buffer(xml_text.data(), xml_text.size(), pugi::parse_default,
                                                          pugi::encoding_utf8);
    if (!parsed) {
        const std::string where = position_of(xml_text, std::size_t(parsed.offset));
        // A file cut short no longer ends with its root's closing tag; say so rather than report the symptom.
        const std::size_t last = xml_text.find_last_not_of(" \t\r\n");
        if (last == std::string::npos || last < 9 || xml_text.compare(last - 9, 10, "</VTKFile>") != 0)
            f.fail("truncated: the file ends before </VTKFile> (the XML breaks at " + where + ": " +
                   parsed.description() + ")");
        f.fail("XML does not parse at " + where + ": " + parsed.description());
    }
}

// The root's attributes on how the arrays are stored: byte_order, header_type, compressor.
void read_storage_attributes(XmlFile& f, const pugi::xml_node& root)
{
    const std::string order = root.attribute("byte_order").as_string("LittleEndian");
    if (order != "LittleEndian" && order != "BigEndian")
        f.fail("byte_order must be LittleEndian or BigEndian, found '" + brief(order) + "'");
    f.big_endian = order == "BigEndian";
    const std::string header = root.attribute("header_type").as_string("UInt32");
    if (header != "UInt32" && header != "UInt64")
        f.fail("header_type must be UInt32 or UInt64, found '" + brief(header) + "'");
    f.header64 = header == "UInt64";
    const std::string compressor = root.attribute("compressor").value();
    if (!compressor.empty() && compressor != "vtkZLibDataCompressor")
        f.fail("unsupported compressor '" + brief(compressor) + "' (uvr reads vtkZLibDataCompressor only)");
    f.zlib = !compressor.empty();
}

// The AppendedData section's encoding and the offsets of the arrays stored in it, sorted.
void read_appended_layout(XmlFile& f, const pugi::xml_document& doc, const pugi::xml_node& root)
{
    const std::string encoding = root.child("AppendedData").attribute("encoding").as_string("raw");
    if (encoding != "raw" && encoding != "base64")
        f.fail("AppendedData encoding must be raw or base64, found '" + brief(encoding) + "'");
    f.appended_base64 = encoding == "base64";
    if (f.appended_base64) f.appended = f.appended.substr(0, f.appended.find("</AppendedData>"));
    for (const pugi::xpath_node& n : doc.select_nodes("//DataArray[@format='appended']"))
        f.appended_offsets.push_back(n.node().attribute("offset").as_ullong());
    std::sort(f.appended_offsets.begin(), f.appended_offsets.end());
}

}  // namespace

Dataset read_vtk_xml(const std::string& path)
{
    const std::string data = read_file_bytes(path);
    if (data.empty()) throw InputError(path, "empty file (not a VTK XML file)");
    XmlFile f;
    f.path = path;

    const std::string xml_text = xml_part(f, data);
    pugi::xml_document doc;
    parse_xml(f, xml_text, doc);
    const pugi::xml_node root = doc.document_element();
    if (std::string(root.name()) != "VTKFile")
        f.fail("not a VTK XML file: the root element is <" + brief(root.name()) + ">, expected <VTKFile>");
    read_storage_attributes(f, root);
    if (f.has_appended) read_appended_layout(f, doc, root);

    const std::string type = root.attribute("type").value();
    Dataset out;
    if (type == "UnstructuredGrid") {
        const pugi::xml_node grid = root.child("UnstructuredGrid");
        if (!grid) f.fail("missing <UnstructuredGrid> element");
        out.mesh = read_unstructured(f, grid);
    } else if (type == "ImageData") {
        const pugi::xml_node image = root.child("ImageData");
        if (!image) f.fail("missing <ImageData> element");
        out.volume = read_image(f, image);
    } else {
        f.fail("unsupported VTK XML file type '" + brief(type) +
               "' (uvr reads UnstructuredGrid .vtu and ImageData .vti)");
    }
    out.warnings = std::move(f.warnings);
    return out;
}

namespace {

// The `count` finite numbers of an ASCII DataArray of a .pvtu's FieldData.
std::vector<double> field_data_numbers(const XmlFile& f, const pugi::xml_node& da, std::size_t count)
{
    if (std::string(da.attribute("format").value()) != "ascii")
        f.fail("FieldData's " + array_label(da) + " must be format=\"ascii\"");
    const std::vector<double> v = numbers_of_text(da.child_value());
    if (v.size() != count || !std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); }))
        f.fail("FieldData's " + array_label(da) + " must be " + std::to_string(count) + " finite numbers, found '" +
               brief(da.child_value()) + "'");
    return v;
}

// The whole mesh's extent that write_pvtu records in FieldData; nothing when the file records none. A record without
// its longest edge is refused here, one without the range of a field the pieces hold by read_pvtu.
std::optional<WholeExtent> read_whole_extent(const XmlFile& f, const pugi::xml_node& grid)
{
    const pugi::xml_node data = grid.child("FieldData");
    const pugi::xml_node bounds = data.find_child_by_attribute("DataArray", "Name", kWholeBoundsArray);
    if (!bounds) return std::nullopt;
    WholeExtent w;
    const std::vector<double> b = field_data_numbers(f, bounds, 6);
    w.bounds.lo = glm::dvec3(b[0], b[1], b[2]);
    w.bounds.hi = glm::dvec3(b[3], b[4], b[5]);
    const pugi::xml_node longest = data.find_child_by_attribute("DataArray", "Name", kWholeLongestEdgeArray);
    if (!longest)
        f.fail(std::string("FieldData records '") + kWholeBoundsArray + "' without '" + kWholeLongestEdgeArray + "'");
    w.longest_edge = field_data_numbers(f, longest, 1)[0];
    const std::string prefix = kWholeRangePrefix;
    for (const pugi::xml_node& da : data.children("DataArray")) {
        const std::string name = da.attribute("Name").value();
        if (name.rfind(prefix, 0) != 0) continue;
        const std::vector<double> r = field_data_numbers(f, da, 2);
        w.ranges.push_back({name.substr(prefix.size()), Range{r[0], r[1]}});
    }
    return w;
}

std::string field_list(const TetMesh& mesh)
{
    std::string out;
    for (const ScalarField& f : mesh.fields)
        out += (out.empty() ? "" : ", ") + f.name + (f.association == FieldAssociation::cell ? " (cell)" : " (point)");
    return out.empty() ? "none" : out;
}

// Appends `piece` to `mesh`: its points after mesh's, its tetrahedra renumbered, its fields' values after mesh's.
// Appends `piece` (piece `index` of the file) to `mesh`; `first`: the first piece joined.
void join_piece(XmlFile& f, TetMesh& mesh, const TetMesh& piece, std::size_t index, const std::string& piece_path,
                bool first)
{
    if (!first && field_list(piece) != field_list(mesh))
        f.fail("piece " + std::to_string(index) + " (" + piece_path + ") holds the fields " + field_list(piece) +
               ", the first piece " + field_list(mesh) + ": every piece must hold the same fields");
    if (mesh.points.size() + piece.points.size() > UINT32_MAX)
        f.fail("the pieces hold more than 2^32 - 1 points together");
    const uint32_t base = uint32_t(mesh.points.size());
    mesh.points.insert(mesh.points.end(), piece.points.begin(), piece.points.end());
    for (const Tet& t : piece.tets) mesh.tets.push_back({t[0] + base, t[1] + base, t[2] + base, t[3] + base});
    if (first) mesh.fields = std::vector<ScalarField>(piece.fields.size());
    for (std::size_t i = 0; i < piece.fields.size(); ++i) {
        ScalarField& to = mesh.fields[i];
        to.name = piece.fields[i].name;
        to.association = piece.fields[i].association;
        to.values.insert(to.values.end(), piece.fields[i].values.begin(), piece.fields[i].values.end());
    }
}

}  // namespace

Dataset read_pvtu(const std::string& path)
{
    return read_pvtu(path, 0, 1);
}

namespace {

// The <PUnstructuredGrid> element of the .pvtu at f.path, parsed into `doc`.
pugi::xml_node parse_pvtu(XmlFile& f, pugi::xml_document& doc)
{
    const std::string data = read_file_bytes(f.path);
    if (data.empty()) throw InputError(f.path, "empty file (not a VTK XML file)");
    parse_xml(f, data, doc);
    const pugi::xml_node root = doc.document_element();
    if (std::string(root.name()) != "VTKFile" || std::string(root.attribute("type").value()) != "PUnstructuredGrid")
        f.fail("not a parallel unstructured grid: expected <VTKFile type=\"PUnstructuredGrid\">");
    const pugi::xml_node grid = root.child("PUnstructuredGrid");
    if (!grid) f.fail("missing <PUnstructuredGrid> element");
    return grid;
}

}  // namespace

std::optional<WholeExtent> read_pvtu_whole_extent(const std::string& path)
{
    XmlFile f;
    f.path = path;
    pugi::xml_document doc;
    return read_whole_extent(f, parse_pvtu(f, doc));
}

Dataset read_pvtu(const std::string& path, std::size_t rank, std::size_t ranks)
{
    XmlFile f;
    f.path = path;
    pugi::xml_document doc;
    const pugi::xml_node grid = parse_pvtu(f, doc);

    Dataset out;
    TetMesh mesh;
    mesh.source = path;
    nlohmann::json pieces = nlohmann::json::array();
    const std::size_t count = std::size_t(std::distance(grid.children("Piece").begin(), grid.children("Piece").end()));
    if (count == 0) f.fail("the PUnstructuredGrid has no Piece");
    if (count < ranks)
        f.fail("has " + std::to_string(count) + " pieces for " + std::to_string(ranks) +
               " ranks: run at most as many ranks as pieces (uvr partition --parts N writes N)");
    const std::size_t first = rank * count / ranks, last = (rank + 1) * count / ranks;
    std::size_t index = 0;
    for (const pugi::xml_node& piece : grid.children("Piece")) {
        if (index < first || index >= last) {
            ++index;
            continue;
        }
        const std::string source = piece.attribute("Source").value();
        if (source.empty()) f.fail("Piece " + std::to_string(index) + " has no Source attribute");
        const std::string piece_path = source.front() == '/' ? source : directory_of(path) + source;
        if (!std::filesystem::is_regular_file(piece_path))
            f.fail("piece " + std::to_string(index) + ": " + piece_path + " does not exist");
        Dataset d = read_vtk_xml(piece_path);
        if (!d.mesh) f.fail("piece " + std::to_string(index) + " (" + piece_path + ") is not an UnstructuredGrid");
        join_piece(f, mesh, *d.mesh, index, piece_path, index == first);
        out.piece_of_cell.insert(out.piece_of_cell.end(), d.mesh->tets.size(), uint32_t(index));
        pieces.push_back({{"source", source}, {"points", d.mesh->points.size()}, {"tetrahedra", d.mesh->tets.size()}});
        for (std::string& w : d.warnings) out.warnings.push_back(std::move(w));
        ++index;
    }
    out.whole = read_whole_extent(f, grid);
    if (out.whole)
        for (const ScalarField& field : mesh.fields)
            if (std::none_of(out.whole->ranges.begin(), out.whole->ranges.end(),
                             [&](const auto& r) { return r.first == field.name; }))
                f.fail("FieldData records the whole's extent but no range of field '" + field.name + "'");
    // Each piece was finalized by its reader; joining them renumbers indices only, so the invariants hold.
    out.mesh = std::move(mesh);
    nlohmann::json info = {{"format", "VTK PUnstructuredGrid"}, {"pieces", pieces}};
    if (out.whole) {
        const Bounds& b = out.whole->bounds;
        nlohmann::json ranges = nlohmann::json::object();
        for (const auto& [name, r] : out.whole->ranges) ranges[name] = {r.lo, r.hi};
        info["whole_extent"] = {{"bounds", {b.lo.x, b.lo.y, b.lo.z, b.hi.x, b.hi.y, b.hi.z}},
                                {"longest_edge", out.whole->longest_edge},
                                {"ranges", ranges}};
    }
    out.info_json = info.dump();
    return out;
}

}  // namespace uvr
