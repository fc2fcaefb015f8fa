// Exodus II files (.exo, .e, .ex2, and .g when netCDF or HDF5) through the SEACAS C library (Debian's libexodusii
// 6.02) over netCDF.
//
// Element blocks of tetrahedra, hexahedra, wedges and pyramids (higher-order ones by their corner nodes) become one
// UnstructuredCells, split by tetrahedralize_cells(); blocks of 0D/1D/2D elements are skipped with a warning and an
// unknown element type is refused. Nodal variables become point fields and element variables cell fields, at one time
// step ("last" or an index from 1). Node and side sets are listed in Dataset::info_json and otherwise skipped.
//
// The library is made quiet (ex_opts(0)) and each failing call becomes an InputError naming the file and what could
// not be read. Before the library sees the file it is checked here, because libexodusii 6.02 trusts it: a file cut
// short reads as zeros (netCDF fills the missing bytes), and some calls read a whole netCDF variable or attribute into
// a buffer sized from a dimension, so a damaged file whose variable is longer than its dimension says would overflow.
#include "reference/dataset.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <mutex>

#include <exodusII.h>
#include <netcdf.h>
#include <nlohmann/json.hpp>

#include "reference/cells.h"
#include "reference/error.h"
#include "reference/io_util.h"

namespace uvr {

namespace {

// libexodusii keeps global state (the last error, per-file caches of block ids and statuses) and netCDF is not
// thread-safe, so one file is read at a time.
std::mutex& library_mutex()
{
    static std::mutex m;
    return m;
}

std::string brief(std::string_view s)
{
    std::string r;
    for (char c : s.substr(0, 40)) r += (c >= 32 && c < 127) ? c : '?';
    if (s.size() > 40) r += "...";
    return r;
}

// Text from the file (names, the title) as valid UTF-8 without control characters, each offending byte replaced by
// '?': it goes into messages and into Dataset::info_json, and JSON refuses invalid UTF-8.
std::string clean_text(std::string_view s)
{
    std::string out;
    for (std::size_t i = 0; i < s.size();) {
        const auto byte = [&](std::size_t k) { return i + k < s.size() ? uint8_t(s[i + k]) : 0u; };
        const unsigned c = byte(0), c1 = byte(1);
        const std::size_t n = c < 0x80 ? 1 : c >= 0xc2 && c < 0xe0 ? 2 : c >= 0xe0 && c < 0xf0 ? 3
                            : c >= 0xf0 && c < 0xf5 ? 4 : 0;
        bool ok = n > 0 && i + n <= s.size() && !(n == 1 && (c < 32 || c == 127));
        for (std::size_t k = 1; ok && k < n; ++k) ok = (byte(k) >> 6) == 2;
        // Overlong forms, UTF-16 surrogates and code points above U+10FFFF.
        ok = ok && !(c == 0xe0 && c1 < 0xa0) && !(c == 0xed && c1 >= 0xa0) && !(c == 0xf0 && c1 < 0x90) &&
             !(c == 0xf4 && c1 >= 0x90);
        out.append(ok ? s.substr(i, n) : "?");
        i += ok ? n : 1;
    }
    return out;
}

uint64_t product(uint64_t a, uint64_t b) { return (a != 0 && b > UINT64_MAX / a) ? UINT64_MAX : a * b; }
uint64_t sum(uint64_t a, uint64_t b) { return b > UINT64_MAX - a ? UINT64_MAX : a + b; }

// ---- the container: netCDF classic (CDF-1, CDF-2 "64-bit offset", CDF-5 "64-bit data") or HDF5 (netCDF-4) ----

enum class Container { unknown, classic, hdf5 };

Container container_of(const std::string& path)
{
    std::ifstream in(path, std::ios::binary);
    char magic[8] = {};
    in.read(magic, sizeof magic);
    if (in.gcount() >= 4 && std::memcmp(magic, "CDF", 3) == 0 && (magic[3] == 1 || magic[3] == 2 || magic[3] == 5))
        return Container::classic;
    if (in.gcount() == 8 && std::memcmp(magic, "\x89HDF\r\n\x1a\n", 8) == 0) return Container::hdf5;
    return Container::unknown;
}

// Reads the big-endian header of a netCDF classic file front to back, never past the end of the file.
class ClassicHeader {
public:
    ClassicHeader(const std::string& path, uint64_t size) : in_(path, std::ios::binary), path_(path), size_(size)
    {
        if (!in_) throw InputError(path, "cannot open the file");
    }
    uint64_t word(int bytes, const char* what)
    {
        take(uint64_t(bytes), what);
        unsigned char b[8] = {};
        in_.read(reinterpret_cast<char*>(b), bytes);
        if (!in_) throw InputError(path_, std::string("cannot read the netCDF header (") + what + ")");
        uint64_t v = 0;
        for (int i = 0; i < bytes; ++i) v = v << 8 | b[i];
        return v;
    }
    // Skips `n` bytes and the padding that rounds them up to a multiple of 4.
    void skip(uint64_t n, const char* what)
    {
        n = sum(n, (4 - n % 4) % 4);
        take(n, what);
        in_.seekg(static_cast<std::streamoff>(n), std::ios::cur);
    }
    [[noreturn]] void invalid(const std::string& what) const
    {
        throw InputError(path_, "not a valid netCDF file: its header has " + what);
    }

private:
    void take(uint64_t n, const char* what)
    {
        if (n > size_ - pos_)
            throw InputError(path_, std::string("truncated: the file ends inside its netCDF header (in ") + what + ")");
        pos_ += n;
    }
    std::ifstream in_;
    std::string path_;
    uint64_t size_, pos_ = 0;
};

// Sizes of the netCDF external types NC_BYTE (1) .. NC_UINT64 (11); types 7 to 11 exist in CDF-5 only.
constexpr uint64_t kNcTypeSize[] = {0, 1, 1, 2, 4, 4, 8, 1, 2, 4, 8, 8};
// Header tags of the dimension, variable and attribute lists (0 with a count of 0 marks an absent list).
constexpr uint64_t kNcDimensionTag = 10, kNcVariableTag = 11, kNcAttributeTag = 12;

uint64_t list_length(ClassicHeader& h, int count_bytes, uint64_t tag, const char* what)
{
    const uint64_t t = h.word(4, what), n = h.word(count_bytes, what);
    if (t != tag && !(t == 0 && n == 0)) h.invalid(std::string("a bad tag before its ") + what);
    return n;
}

uint64_t type_size(ClassicHeader& h, int version, const char* what)
{
    const uint64_t t = h.word(4, what);
    if (t == 0 || t > (version == 5 ? 11u : 6u)) h.invalid(std::string("an unknown type for ") + what);
    return kNcTypeSize[t];
}

void skip_attributes(ClassicHeader& h, int version, int count_bytes)
{
    const uint64_t n = list_length(h, count_bytes, kNcAttributeTag, "attributes");
    for (uint64_t i = 0; i < n; ++i) {
        h.skip(h.word(count_bytes, "an attribute name"), "an attribute name");
        const uint64_t size = type_size(h, version, "an attribute");
        h.skip(product(h.word(count_bytes, "an attribute"), size), "an attribute's values");
    }
}

// Where the data a classic file's header describes ends: the furthest end of a variable (record variables take one
// slice per record, the records following each other). A file shorter than that was cut short.
uint64_t classic_data_end(const std::string& path, uint64_t size)
{
    ClassicHeader h(path, size);
    const int version = int(h.word(4, "the signature") & 0xff);
    const int count_bytes = version == 5 ? 8 : 4, offset_bytes = version == 1 ? 4 : 8;
    const uint64_t numrecs = h.word(count_bytes, "the record count");
    const bool streaming = numrecs == (version == 5 ? UINT64_MAX : 0xffffffffu);  // records counted from the size
    std::vector<uint64_t> dims;
    const uint64_t ndims = list_length(h, count_bytes, kNcDimensionTag, "dimensions");
    for (uint64_t i = 0; i < ndims; ++i) {
        h.skip(h.word(count_bytes, "a dimension name"), "a dimension name");
        dims.push_back(h.word(count_bytes, "a dimension length"));  // 0: the record (unlimited) dimension
    }
    skip_attributes(h, version, count_bytes);
    struct Extent { uint64_t begin, bytes; bool record; };  // bytes: of the whole variable, or of one record's slice
    std::vector<Extent> vars;
    uint64_t record_bytes = 0;
    const uint64_t nvars = list_length(h, count_bytes, kNcVariableTag, "variables");
    for (uint64_t i = 0; i < nvars; ++i) {
        h.skip(h.word(count_bytes, "a variable name"), "a variable name");
        const uint64_t rank = h.word(count_bytes, "a variable's rank");
        uint64_t values = 1;
        bool record = false;
        for (uint64_t d = 0; d < rank; ++d) {
            const uint64_t id = h.word(count_bytes, "a variable's dimensions");
            if (id >= dims.size()) h.invalid("a variable with an unknown dimension");
            if (d == 0 && dims[id] == 0) record = true; else values = product(values, dims[id]);
        }
        skip_attributes(h, version, count_bytes);
        const uint64_t bytes = product(values, type_size(h, version, "a variable"));
        h.word(count_bytes, "a variable's size");
        vars.push_back({h.word(offset_bytes, "a variable's offset"), bytes, record});
        if (record) record_bytes = sum(record_bytes, sum(bytes, (4 - bytes % 4) % 4));
    }
    // netCDF does not pad the records of a file with a single record variable.
    if (std::count_if(vars.begin(), vars.end(), [](const Extent& v) { return v.record; }) == 1)
        for (const Extent& v : vars) if (v.record) record_bytes = v.bytes;
    uint64_t end = 0;
    for (const Extent& v : vars) {
        if (v.record && (streaming || numrecs == 0)) continue;
        const uint64_t slices = v.record ? product(numrecs - 1, record_bytes) : 0;
        end = std::max(end, sum(v.begin, sum(slices, v.bytes)));
    }
    return end;
}

// The global attributes that libexodusii reads into a single number without checking how many values they hold.
constexpr const char* kSingleValueAttributes[] = {"api_version", "api version", "version", "file_size",
                                                  "floating_point_word_size", "floating point word size",
                                                  "maximum_name_length", "int64_status"};

// Checks what the library would trust: the signature, that a classic file holds all its data, that netCDF can open
// it (the library, when netCDF cannot, prints its own guess on stderr whatever ex_opts says) and the attributes above.
void check_container(const std::string& path)
{
    std::error_code ec;
    const uint64_t size = std::filesystem::file_size(path, ec);
    if (ec) throw InputError(path, "cannot open the file (" + ec.message() + ")");
    const Container c = container_of(path);
    if (c == Container::unknown)
        throw InputError(path, size == 0 ? "empty file (not an Exodus II file)"
                                         : "not an Exodus II file: it starts with neither the netCDF signature (CDF) "
                                           "nor the HDF5 one");
    if (c == Container::classic) {
        const uint64_t end = classic_data_end(path, size);
        if (end > size)
            throw InputError(path, "truncated: its netCDF header describes " + std::to_string(end) +
                                       " bytes, but the file holds " + std::to_string(size));
    }
    int ncid = -1;
    if (const int status = nc_open(path.c_str(), NC_NOWRITE, &ncid); status != NC_NOERR)
        throw InputError(path, std::string("netCDF cannot open the file (") + nc_strerror(status) +
                                   "): not an Exodus II file, or a damaged or truncated one");
    std::string bad;
    for (const char* name : kSingleValueAttributes) {
        std::size_t len = 1;
        if (nc_inq_attlen(ncid, NC_GLOBAL, name, &len) == NC_NOERR && len != 1 && bad.empty()) bad = name;
    }
    nc_close(ncid);
    if (!bad.empty()) throw InputError(path, "the global attribute '" + bad + "' must hold one value (a damaged file)");
}

// ---- the Exodus II file ----

// The longest name (block, set, variable) read; netCDF's own limit on names.
constexpr int kMaxNameLength = NC_MAX_NAME;

struct ExoFile {
    std::string path;
    int id = -1;  // the library's id, which is also the netCDF id of the open file
    std::vector<std::string> warnings;

    explicit ExoFile(const std::string& p) : path(p) {}
    ExoFile(const ExoFile&) = delete;
    ExoFile& operator=(const ExoFile&) = delete;
    ~ExoFile()
    {
        if (id >= 0) ex_close(id);
    }
    [[noreturn]] void fail(const std::string& what) const { throw InputError(path, what); }
    void warn(const std::string& what) { warnings.push_back(path + ": " + what); }

    // A library call failed when its status is negative (positive ones are warnings, such as "no names stored").
    void check(int status, const std::string& what) const
    {
        if (status < 0) fail("cannot " + what + " (" + library_reason() + ")");
    }
    // Why the last library call failed: netCDF's words for a netCDF error, else the library's message.
    static std::string library_reason()
    {
        const char* msg = nullptr;
        const char* func = nullptr;
        int code = 0;
        ex_get_err(&msg, &func, &code);
        return code < 0 ? nc_strerror(code) : (msg && *msg ? msg : "the library gives no reason");
    }

    // Whether the file has the netCDF variable `var` (named as in the Exodus II file format); one that exists must
    // hold exactly `values` values, all its dimensions (the record count included) multiplied. The library reads some
    // variables whole into buffers sized from the file's dimensions, and this reader sizes its own buffers from them:
    // a count is trusted only once a variable of that size was found, which in a classic file also bounds it by the
    // file's size (check_container).
    bool has_values(const std::string& var, uint64_t values, const std::string& what) const
    {
        std::vector<uint64_t> dims;
        if (!shape(var, dims, what)) return false;
        uint64_t n = 1;
        for (uint64_t len : dims) n = product(n, len);
        if (n != values)
            fail(what + " holds " + std::to_string(n) + " values, but the file's dimensions say " +
                 std::to_string(values) + " (a damaged file)");
        return true;
    }
    // Whether the file has `var`; one that exists must have `rows` entries along its first dimension.
    bool has_rows(const std::string& var, uint64_t rows, const std::string& what) const
    {
        std::vector<uint64_t> dims;
        if (!shape(var, dims, what)) return false;
        if (dims.empty() || dims[0] != rows)
            fail(what + " are stored for " + std::to_string(dims.empty() ? 0 : dims[0]) + " entries, but the file's "
                 "dimensions say " + std::to_string(rows) + " (a damaged file)");
        return true;
    }
    bool shape(const std::string& var, std::vector<uint64_t>& dims, const std::string& what) const
    {
        int varid = -1, rank = 0;
        if (nc_inq_varid(id, var.c_str(), &varid) != NC_NOERR) return false;
        int dimids[NC_MAX_VAR_DIMS];
        if (nc_inq_varndims(id, varid, &rank) != NC_NOERR || rank > NC_MAX_VAR_DIMS ||
            nc_inq_vardimid(id, varid, dimids) != NC_NOERR)
            fail("cannot read the shape of " + what);
        for (int d = 0; d < rank; ++d) {
            std::size_t len = 0;
            if (nc_inq_dimlen(id, dimids[d], &len) != NC_NOERR) fail("cannot read the shape of " + what);
            dims.push_back(len);
        }
        return true;
    }
    void require_values(const std::string& var, uint64_t values, const std::string& what) const
    {
        if (!has_values(var, values, what)) fail("the file has no " + what + " (netCDF variable '" + var + "')");
    }
    // `count` names of blocks, sets or variables, stored in `var` ("" where the file stores none). The names of
    // variables must be stored; `count` is trusted here only when they are, or when checked already.
    std::vector<std::string> names(ex_entity_type type, int64_t count, bool variables, const char* var,
                                   const std::string& what)
    {
        if (count <= 0) return {};
        if (!has_rows(var, uint64_t(count), "the " + what)) {
            if (variables) fail("the file has no " + what + " (netCDF variable '" + var + "')");
            return std::vector<std::string>(std::size_t(count));
        }
        std::vector<std::vector<char>> storage(std::size_t(count), std::vector<char>(kMaxNameLength + 1, '\0'));
        std::vector<char*> pointers;
        for (auto& s : storage) pointers.push_back(s.data());
        check(variables ? ex_get_variable_names(id, type, int(count), pointers.data())
                        : ex_get_names(id, type, pointers.data()),
              "read the " + what);
        std::vector<std::string> out;
        for (auto& s : storage) out.push_back(clean_text(std::string_view(s.data(), strnlen(s.data(), s.size()))));
        return out;
    }
};

// ---- element blocks ----

// A family of 3D element types: "TETRA", "TETRA4", "TETRA10", ... The Exodus corner nodes come first, in an order
// whose orientation matches VTK's for tetrahedra, hexahedra and pyramids; see kWedgeToVtk for wedges.
struct SolidFamily {
    const char* name;
    int vtk_type;
    int corners;
};
constexpr SolidFamily kSolidFamilies[] = {
    {"TETRA", kVtkTetra, 4},      {"TET", kVtkTetra, 4},   {"HEXAHEDRON", kVtkHexahedron, 8},
    {"HEX", kVtkHexahedron, 8}, {"WEDGE", kVtkWedge, 6}, {"PYRAMID", kVtkPyramid, 5},
};
// Families of 0D, 1D and 2D element types (points, bars, triangles, quadrilaterals, shells, polygons): skipped.
constexpr const char* kLowerDimensionalFamilies[] = {"SPHERE", "CIRCLE",   "POINT",    "BAR",  "BEAM",  "TRUSS", "EDGE",
                                                     "TRI",    "TRIANGLE", "TRISHELL", "QUAD", "SHELL", "NSIDED"};
// Exodus numbers a wedge's bottom triangle 1, 2, 3 counter-clockwise seen from its top triangle 4, 5, 6 (its side 4
// is 1, 3, 2 and faces outward); VTK's wedge has the opposite orientation, (0, 1, 2) facing away from (3, 4, 5). The
// same six corners in VTK's order are Exodus's 1, 3, 2, 4, 6, 5.
constexpr int kWedgeToVtk[6] = {0, 2, 1, 3, 5, 4};

// Whether `type` (upper case) is `family` followed by nothing but digits (the node count).
bool in_family(const std::string& type, const char* family)
{
    const std::size_t n = std::strlen(family);
    return type.compare(0, n, family) == 0 &&
           std::all_of(type.begin() + long(std::min(n, type.size())), type.end(),
                       [](char c) { return std::isdigit(static_cast<unsigned char>(c)) != 0; });
}

struct Block {
    int64_t id = 0;
    std::string name, type;
    int64_t elements = 0, nodes_per_element = 0;
    const SolidFamily* solid = nullptr;  // null: not read (no element, or lower-dimensional)
};

// The element type name of the block at `index` (in the order of the block ids), upper case: the attribute
// "elem_type" of its connectivity variable. ex_get_block copies that attribute whole into a buffer of
// MAX_STR_LENGTH + 1 characters on its stack (libexodusii 6.02), so a longer one, which the Exodus API never writes,
// is refused here before ex_get_block is called; the library looks for it on any of these variables.
std::string element_type(const ExoFile& f, std::size_t index, int64_t id)
{
    std::string type;
    for (const char* prefix : {"connect", "edgconn", "ebconn", "facconn", "fbconn"}) {
        const std::string var = prefix + std::to_string(index + 1);
        int varid = -1;
        std::size_t len = 0;
        if (nc_inq_varid(f.id, var.c_str(), &varid) != NC_NOERR ||
            nc_inq_attlen(f.id, varid, "elem_type", &len) != NC_NOERR)
            continue;
        if (len > std::size_t(MAX_STR_LENGTH) + 1)
            f.fail("element block " + std::to_string(id) + " has an element type name of " + std::to_string(len) +
                   " characters; Exodus II allows " + std::to_string(MAX_STR_LENGTH) + " (a damaged file)");
        std::string text(len, '\0');
        if (len > 0 && nc_get_att_text(f.id, varid, "elem_type", text.data()) != NC_NOERR)
            f.fail("cannot read the element type of element block " + std::to_string(id));
        if (type.empty()) type = text.substr(0, text.find_first_of(std::string(" \0", 2)));
    }
    for (char& c : type) c = char(std::toupper(static_cast<unsigned char>(c)));
    return clean_text(type);
}

std::vector<Block> read_block_headers(ExoFile& f, int64_t count)
{
    if (count == 0) return {};
    f.require_values("eb_prop1", uint64_t(count), "element block ids");
    f.has_values("eb_status", uint64_t(count), "the element block statuses");
    std::vector<int64_t> ids(std::size_t(count), 0);
    f.check(ex_get_ids(f.id, EX_ELEM_BLOCK, ids.data()), "read the element block ids");
    const std::vector<std::string> names = f.names(EX_ELEM_BLOCK, count, false, "eb_names", "element block names");
    std::vector<Block> blocks;
    for (std::size_t i = 0; i < ids.size(); ++i) {
        Block b;
        b.id = ids[i];
        b.name = names[i];
        if (std::find(ids.begin(), ids.begin() + long(i), b.id) != ids.begin() + long(i))
            f.fail("element block id " + std::to_string(b.id) + " is used twice");
        b.type = element_type(f, i, b.id);
        int64_t edges = 0, faces = 0, attributes = 0;
        f.check(ex_get_block(f.id, EX_ELEM_BLOCK, b.id, nullptr, &b.elements, &b.nodes_per_element, &edges, &faces,
                             &attributes),
                "read element block " + std::to_string(b.id));
        if (b.elements < 0 || b.nodes_per_element < 0 || uint64_t(b.elements) > kMaxElements ||
            product(uint64_t(b.elements), uint64_t(b.nodes_per_element)) > kMaxElements)
            f.fail("element block " + std::to_string(b.id) + " has an invalid size");
        blocks.push_back(std::move(b));
    }
    return blocks;
}

// Decides what to do with each block: read it (solid), skip it with a warning, or refuse the file.
void classify_blocks(ExoFile& f, std::vector<Block>& blocks)
{
    for (Block& b : blocks) {
        if (b.elements == 0) continue;
        const std::string label = "element block " + std::to_string(b.id) + " (" + brief(b.type) + ")";
        for (const SolidFamily& s : kSolidFamilies)
            if (!b.solid && in_family(b.type, s.name)) b.solid = &s;
        if (b.solid) {
            if (b.nodes_per_element < b.solid->corners)
                f.fail(label + " has " + std::to_string(b.nodes_per_element) + " nodes per element, fewer than its " +
                       std::to_string(b.solid->corners) + " corners");
            if (b.nodes_per_element > b.solid->corners)
                f.warn(label + ": the " + std::to_string(b.nodes_per_element - b.solid->corners) +
                       " higher-order nodes of each element are ignored (uvr uses the " +
                       std::to_string(b.solid->corners) + " corner nodes)");
            continue;
        }
        const bool lower = std::any_of(std::begin(kLowerDimensionalFamilies), std::end(kLowerDimensionalFamilies),
                                       [&](const char* family) { return in_family(b.type, family); });
        if (!lower)
            f.fail("element block " + std::to_string(b.id) + " has element type '" + brief(b.type) +
                   "', which uvr does not read (3-D types: TETRA, HEX, WEDGE, PYRAMID and their higher-order forms)");
        f.warn(label + " skipped: " + std::to_string(b.elements) + " element(s) of a 0-D, 1-D or 2-D type (uvr "
               "renders 3-D elements only)");
    }
}

// Appends a solid block's elements to `cells`, corner nodes only, numbered from 0.
void read_connectivity(ExoFile& f, const Block& b, std::size_t index, int64_t nodes, UnstructuredCells& cells)
{
    const int64_t npe = b.nodes_per_element, corners = b.solid->corners;
    const std::string label = "element block " + std::to_string(b.id);
    f.require_values("connect" + std::to_string(index + 1), uint64_t(b.elements * npe), "connectivity of " + label);
    std::vector<int64_t> conn(std::size_t(b.elements * npe), 0);
    f.check(ex_get_conn(f.id, EX_ELEM_BLOCK, b.id, conn.data(), nullptr, nullptr),
            "read the connectivity of " + label);
    for (int64_t e = 0; e < b.elements; ++e) {
        for (int64_t k = 0; k < corners; ++k) {
            const int64_t corner = b.solid->vtk_type == kVtkWedge ? kWedgeToVtk[k] : k;
            const int64_t node = conn[std::size_t(e * npe + corner)];
            if (node < 1 || node > nodes)
                f.fail(label + ", element " + std::to_string(e + 1) + " uses node " + std::to_string(node) +
                       ", but node numbers run from 1 to " + std::to_string(nodes));
            cells.connectivity.push_back(node - 1);
        }
        cells.types.push_back(b.solid->vtk_type);
        cells.offsets.push_back(int64_t(cells.connectivity.size()));
    }
}

// ---- time steps and variables ----

// The chosen time step, from 1; 0 when the file has no time step (then no variable is read: a warning says so where
// the file defines some).
int choose_time_step(ExoFile& f, const std::string& wanted, int64_t steps, bool has_variables)
{
    if (wanted == "last") {
        if (steps == 0 && has_variables)
            f.warn("the file defines variables but holds no time step: the mesh is read without fields");
        return int(steps);
    }
    int64_t index = 0;
    const char* end = wanted.data() + wanted.size();
    const auto [p, ec] = std::from_chars(wanted.data(), end, index);
    if (wanted.empty() || ec != std::errc() || p != end)
        f.fail("time step '" + brief(wanted) + "' is neither 'last' nor a number");
    if (index < 1 || index > steps)
        f.fail("time step " + wanted + " is out of range: " +
               (steps == 0 ? std::string("the file has no time step")
                           : "the file has time steps 1 to " + std::to_string(steps)));
    return int(index);
}

std::vector<ScalarField> read_nodal_fields(ExoFile& f, const std::vector<std::string>& names, int step,
                                           int64_t nodes)
{
    std::vector<ScalarField> fields;
    for (std::size_t v = 0; v < names.size(); ++v) {
        ScalarField field{names[v], std::vector<double>(std::size_t(nodes), 0.0), FieldAssociation::point};
        f.check(ex_get_var(f.id, step, EX_NODAL, int(v + 1), 1, nodes, field.values.data()),
                "read nodal variable '" + names[v] + "' at time step " + std::to_string(step));
        fields.push_back(std::move(field));
    }
    return fields;
}

// One value per element of the solid blocks, in block order. An element variable that the truth table leaves out of
// one of those blocks is dropped with a warning.
std::vector<ScalarField> read_element_fields(ExoFile& f, const std::vector<std::string>& names, int step,
                                             const std::vector<Block>& blocks)
{
    const int nvars = int(names.size()), nblocks = int(blocks.size());
    std::vector<int> truth(std::size_t(nvars) * std::size_t(nblocks), 1);
    if (nvars > 0 && nblocks > 0) {
        f.has_values("elem_var_tab", truth.size(), "the element variable truth table");
        f.check(ex_get_truth_table(f.id, EX_ELEM_BLOCK, nblocks, nvars, truth.data()),
                "read the element variable truth table");
    }
    std::vector<ScalarField> fields;
    for (int v = 0; v < nvars; ++v) {
        ScalarField field{names[std::size_t(v)], {}, FieldAssociation::cell};
        bool defined = true;
        for (int b = 0; b < nblocks && defined; ++b) {
            const Block& block = blocks[std::size_t(b)];
            if (!block.solid) continue;
            if (!truth[std::size_t(b) * std::size_t(nvars) + std::size_t(v)]) {
                f.warn("element variable '" + field.name + "' is not defined on element block " +
                       std::to_string(block.id) + "; it is dropped");
                defined = false;
                continue;
            }
            std::vector<double> values(std::size_t(block.elements), 0.0);
            f.check(ex_get_var(f.id, step, EX_ELEM_BLOCK, v + 1, block.id, block.elements, values.data()),
                    "read element variable '" + field.name + "' on element block " + std::to_string(block.id) +
                        " at time step " + std::to_string(step));
            field.values.insert(field.values.end(), values.begin(), values.end());
        }
        if (defined) fields.push_back(std::move(field));
    }
    return fields;
}

// Variable names (stored in `var`), with "nodal_var_N" / "elem_var_N" (from 1) for those the file leaves unnamed.
std::vector<std::string> variable_names(ExoFile& f, ex_entity_type type, const char* var, const char* unnamed,
                                        const char* what)
{
    int count = 0;
    f.check(ex_get_variable_param(f.id, type, &count), std::string("read the number of ") + what);
    if (count < 0) f.fail(std::string("invalid number of ") + what);
    std::vector<std::string> names = f.names(type, count, true, var, std::string("names of the ") + what);
    for (std::size_t i = 0; i < names.size(); ++i)
        if (names[i].empty()) names[i] = unnamed + std::to_string(i + 1);
    return names;
}

// Node or side sets: listed by name (or id when unnamed) and skipped with one warning.
nlohmann::json describe_sets(ExoFile& f, ex_entity_type type, int64_t count, const char* prefix, const char* what)
{
    nlohmann::json list = nlohmann::json::array();
    if (count <= 0) return list;
    f.require_values(std::string(prefix) + "_prop1", uint64_t(count), std::string(what) + " ids");
    std::vector<int64_t> ids(std::size_t(count), 0);
    f.check(ex_get_ids(f.id, type, ids.data()), std::string("read the ") + what + " ids");
    const std::vector<std::string> names =
        f.names(type, count, false, (std::string(prefix) + "_names").c_str(), std::string(what) + " names");
    for (std::size_t i = 0; i < ids.size(); ++i)
        list.push_back(names[i].empty() ? nlohmann::json(ids[i]) : nlohmann::json(names[i]));
    f.warn(std::to_string(count) + " " + what + (count == 1 ? "" : "s") +
           " skipped: uvr reads element blocks and variables");
    return list;
}

std::vector<glm::dvec3> read_points(ExoFile& f, int64_t nodes)
{
    if (nodes == 0) return {};
    // One array of all coordinates (the classic layout), or one per axis.
    if (!f.has_values("coord", uint64_t(nodes) * 3, "the coordinates"))
        for (const char* var : {"coordx", "coordy", "coordz"})
            f.require_values(var, uint64_t(nodes), "coordinates");
    std::vector<double> x(std::size_t(nodes), 0.0), y(x), z(x);
    f.check(ex_get_coord(f.id, x.data(), y.data(), z.data()), "read the coordinates");
    std::vector<glm::dvec3> points(static_cast<std::size_t>(nodes));
    for (std::size_t i = 0; i < points.size(); ++i) points[i] = {x[i], y[i], z[i]};
    return points;
}

void open_file(ExoFile& f)
{
    ex_opts(0);  // no message on stderr, no abort: every failure comes back as a status
    int cpu_word_size = sizeof(double), io_word_size = 0;
    float version = 0.0f;
    f.id = ex_open(f.path.c_str(), EX_READ, &cpu_word_size, &io_word_size, &version);
    if (f.id < 0) {
        f.id = -1;
        f.fail("not an Exodus II file, or a damaged one: the Exodus library cannot open it (" +
               ExoFile::library_reason() + ")");
    }
    f.check(ex_set_int64_status(f.id, EX_ALL_INT64_API), "switch the library to 64-bit integers");
    f.check(ex_set_max_name_length(f.id, kMaxNameLength), "set the name length");
}

}  // namespace

bool looks_like_exodus(const std::string& path) { return container_of(path) != Container::unknown; }

Dataset read_exodus(const std::string& path, const std::string& time_step)
{
    std::lock_guard<std::mutex> lock(library_mutex());
    check_container(path);
    ExoFile f(path);
    open_file(f);
    ex_init_params init{};
    f.check(ex_get_init_ext(f.id, &init), "read the file's sizes (ex_get_init)");
    init.title[MAX_LINE_LENGTH] = '\0';
    if (init.num_dim != 3) f.fail("the mesh is " + std::to_string(init.num_dim) + "-D; uvr reads 3-D meshes");
    if (init.num_nodes < 0 || uint64_t(init.num_nodes) > kMaxElements || init.num_elem_blk < 0 ||
        uint64_t(init.num_elem_blk) > kMaxElements)
        f.fail("invalid number of nodes or element blocks");
    if (init.num_elem_blk == 0)
        f.fail("the file has no element block (" + std::to_string(init.num_node_sets) + " node set(s), " +
               std::to_string(init.num_side_sets) + " side set(s)): uvr renders the 3-D elements of element blocks");

    UnstructuredCells cells;
    cells.source = path;
    cells.points = read_points(f, init.num_nodes);
    std::vector<Block> blocks = read_block_headers(f, init.num_elem_blk);
    classify_blocks(f, blocks);
    cells.offsets.push_back(0);
    for (std::size_t i = 0; i < blocks.size(); ++i)
        if (blocks[i].solid) read_connectivity(f, blocks[i], i, init.num_nodes, cells);

    const std::vector<std::string> nodal =
        variable_names(f, EX_NODAL, "name_nod_var", "nodal_var_", "nodal variables");
    const std::vector<std::string> element =
        variable_names(f, EX_ELEM_BLOCK, "name_elem_var", "elem_var_", "element variables");
    const int64_t steps = ex_inquire_int(f.id, EX_INQ_TIME);
    if (steps < 0 || steps > INT32_MAX) f.fail("invalid number of time steps");
    const int step = choose_time_step(f, time_step, steps, !nodal.empty() || !element.empty());
    if (steps > 0) f.require_values("time_whole", uint64_t(steps), "time values");
    std::vector<double> times(std::size_t(steps), 0.0);
    if (steps > 0) f.check(ex_get_all_times(f.id, times.data()), "read the time values");
    if (step > 0) {
        cells.point_fields = read_nodal_fields(f, nodal, step, init.num_nodes);
        cells.cell_fields = read_element_fields(f, element, step, blocks);
    }

    Dataset out;
    nlohmann::json info;
    info["format"] = "Exodus II";
    info["title"] = clean_text(init.title);
    info["blocks"] = nlohmann::json::array();
    for (const Block& b : blocks)
        info["blocks"].push_back({{"id", b.id}, {"name", b.name}, {"type", b.type}, {"elements", b.elements},
                                  {"nodes_per_element", b.nodes_per_element}});
    info["node_sets"] = describe_sets(f, EX_NODE_SET, init.num_node_sets, "ns", "node set");
    info["side_sets"] = describe_sets(f, EX_SIDE_SET, init.num_side_sets, "ss", "side set");
    info["nodal_variables"] = nodal;
    info["element_variables"] = element;
    info["times"] = times;
    info["time_step"] = step > 0 ? nlohmann::json(step) : nlohmann::json(nullptr);
    out.info_json = info.dump();
    out.mesh = tetrahedralize_cells(cells, f.warnings);
    out.warnings = std::move(f.warnings);
    return out;
}

}  // namespace uvr
