// VTK legacy files (.vtk), ASCII and BINARY, versions 1.0 to 5.1: UNSTRUCTURED_GRID (a tetrahedral mesh after
// tetrahedralize_cells) and STRUCTURED_POINTS (a volume).
//
// The format is keyword lines with data after them: in ASCII the data are whitespace-separated numbers, in BINARY they
// are big-endian bytes that start right after the newline of the keyword line (or of its LOOKUP_TABLE line) and are
// followed by a newline. Everything uvr does not use (vectors, tensors, lookup tables, cell data, field data at the
// dataset level) is still parsed far enough to be skipped exactly, because in BINARY there is no other way to find the
// next keyword.
#include "reference/dataset.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <type_traits>

#include "reference/cells.h"
#include "reference/error.h"
#include "reference/io_util.h"

namespace uvr {

namespace {

enum class Elem { bit, i8, u8, i16, u16, i32, u32, i64, u64, f32, f64, str };

struct ElemName {
    const char* name;
    Elem elem;
};

// VTK writes "long" as 8 bytes on the LP64 systems it runs on, and vtkIdType as a 4-byte int in every version.
constexpr ElemName kElemNames[] = {
    {"bit", Elem::bit},          {"char", Elem::i8},           {"signed_char", Elem::i8},
    {"unsigned_char", Elem::u8}, {"short", Elem::i16},         {"unsigned_short", Elem::u16},
    {"int", Elem::i32},          {"unsigned_int", Elem::u32},  {"vtkidtype", Elem::i32},
    {"long", Elem::i64},         {"unsigned_long", Elem::u64}, {"vtktypeint64", Elem::i64},
    {"vtktypeuint64", Elem::u64}, {"vtktypeint32", Elem::i32}, {"vtktypeuint32", Elem::u32},
    {"vtktypeint16", Elem::i16}, {"vtktypeuint16", Elem::u16}, {"vtktypeint8", Elem::i8},
    {"vtktypeuint8", Elem::u8},  {"float", Elem::f32},         {"double", Elem::f64},
    {"vtktypefloat32", Elem::f32}, {"vtktypefloat64", Elem::f64}, {"string", Elem::str},
    {"utf8_string", Elem::str},
};

uint64_t elem_size(Elem e)
{
    switch (e) {
    case Elem::i16:
    case Elem::u16: return 2;
    case Elem::i32:
    case Elem::u32:
    case Elem::f32: return 4;
    case Elem::i64:
    case Elem::u64:
    case Elem::f64: return 8;
    default: return 1;
    }
}

// a * b, or UINT64_MAX where the product overflows (then every size check fails).
uint64_t product(uint64_t a, uint64_t b) { return (a != 0 && b > UINT64_MAX / a) ? UINT64_MAX : a * b; }

// Bytes of n binary values; bits are packed eight to a byte.
uint64_t binary_bytes(Elem e, uint64_t n) { return e == Elem::bit ? n / 8 + (n % 8 != 0) : product(n, elem_size(e)); }

bool is_integer(Elem e) { return e != Elem::f32 && e != Elem::f64 && e != Elem::str; }

// Tokens from a binary file may be arbitrary bytes; messages show them readably and briefly.
std::string printable(std::string_view s)
{
    std::string r;
    for (char c : s.substr(0, 40)) r += (c >= 32 && c < 127) ? c : '?';
    if (s.size() > 40) r += "...";
    return r;
}

// VTK escapes blanks and other special characters in array names as %XX.
std::string decode_name(std::string_view s)
{
    std::string r;
    for (std::size_t i = 0; i < s.size(); ++i) {
        unsigned v = 0;
        if (s[i] == '%' && i + 2 < s.size() && std::from_chars(s.data() + i + 1, s.data() + i + 3, v, 16).ptr ==
                                                     s.data() + i + 3) {
            r += static_cast<char>(v);
            i += 2;
        } else {
            r += s[i];
        }
    }
    return r;
}

std::string_view trim(std::string_view s)
{
    const std::size_t b = s.find_first_not_of(" \t\r");
    if (b == std::string_view::npos) return {};
    return s.substr(b, s.find_last_not_of(" \t\r") + 1 - b);
}

std::string uppercase(std::string_view s)
{
    std::string r(s);
    for (auto& c : r) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    return r;
}

bool parse_int(std::string_view t, int64_t& v)
{
    if (!t.empty() && t[0] == '+') t.remove_prefix(1);
    auto [p, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    return ec == std::errc() && p == t.data() + t.size() && !t.empty();
}

bool parse_real(std::string_view t, double& v)
{
    if (!t.empty() && t[0] == '+') t.remove_prefix(1);
    auto [p, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    if (p != t.data() + t.size() || t.empty()) return false;
    if (ec == std::errc::result_out_of_range) v = std::strtod(std::string(t).c_str(), nullptr);  // inf or 0, as C does
    return ec == std::errc() || ec == std::errc::result_out_of_range;
}

// Whitespace tokens with absolute line numbers. The reader jumps over binary blocks; TextScanner::set_offset recounts
// lines from the file start, which would make a file of many small binary arrays quadratic, so this wrapper restarts a
// scanner at each jump and carries the line count forward incrementally.
class Lexer {
public:
    Lexer(std::string_view text, std::string file) : text_(text), file_(std::move(file))
    {
        sc_.emplace(text, file_, false);
    }

    const std::string& file() const { return file_; }
    std::string_view text() const { return text_; }
    bool at_end() { return sc_->at_end(); }
    std::string_view token(const char* what)
    {
        if (sc_->at_end()) fail(std::string("truncated: the file ends where ") + what + " was expected");
        std::string_view t = sc_->token(what);
        line_ = base_newlines_ + sc_->line();
        return t;
    }
    std::string_view line_rest()
    {
        line_ = base_newlines_ + sc_->line();
        return sc_->line_rest();
    }
    std::size_t offset() const { return base_ + sc_->offset(); }
    // The line of the last token or line read: the keyword line of a binary block stays the line of its errors.
    long line() const { return line_; }
    void seek(std::size_t pos)
    {
        pos = std::min(pos, text_.size());
        if (pos >= base_)
            base_newlines_ += std::count(text_.begin() + long(base_), text_.begin() + long(pos), '\n');
        else
            base_newlines_ -= std::count(text_.begin() + long(pos), text_.begin() + long(base_), '\n');
        base_ = pos;
        sc_.emplace(text_.substr(pos), file_, false);
    }
    // A position to come back to after looking at the next word.
    struct Mark {
        std::size_t offset;
        long line;
    };
    Mark mark() const { return {offset(), line_}; }
    void restore(const Mark& m)
    {
        seek(m.offset);
        line_ = m.line;
    }
    [[noreturn]] void fail(const std::string& what) const { throw InputError(file_, line(), what); }

private:
    std::string_view text_;
    std::string file_;
    std::optional<TextScanner> sc_;
    std::size_t base_ = 0;
    long base_newlines_ = 0;  // newlines in text_[0, base_)
    long line_ = 1;
};

template <class S, class T>
void convert_be(const char* p, uint64_t n, T* out)
{
    for (uint64_t i = 0; i < n; ++i) {
        S v;
        std::memcpy(&v, p + i * sizeof(S), sizeof(S));
        out[i] = static_cast<T>(byteswap_value(v));
    }
}

template <class T>
void convert_binary(Elem e, const char* p, uint64_t n, T* out)
{
    switch (e) {
    case Elem::bit:
        for (uint64_t i = 0; i < n; ++i)
            out[i] = static_cast<T>((static_cast<unsigned char>(p[i / 8]) >> (7 - i % 8)) & 1);
        break;
    case Elem::i8: convert_be<int8_t>(p, n, out); break;
    case Elem::u8: convert_be<uint8_t>(p, n, out); break;
    case Elem::i16: convert_be<int16_t>(p, n, out); break;
    case Elem::u16: convert_be<uint16_t>(p, n, out); break;
    case Elem::i32: convert_be<int32_t>(p, n, out); break;
    case Elem::u32: convert_be<uint32_t>(p, n, out); break;
    case Elem::i64: convert_be<int64_t>(p, n, out); break;
    case Elem::u64: convert_be<uint64_t>(p, n, out); break;
    case Elem::f32: convert_be<float>(p, n, out); break;
    case Elem::f64: convert_be<double>(p, n, out); break;
    case Elem::str: break;  // never numeric; callers reject it first
    }
}

std::optional<VoxelType> voxel_type(Elem e)
{
    switch (e) {
    case Elem::i8: return VoxelType::i8;
    case Elem::u8: return VoxelType::u8;
    case Elem::i16: return VoxelType::i16;
    case Elem::u16: return VoxelType::u16;
    case Elem::i32: return VoxelType::i32;
    case Elem::u32: return VoxelType::u32;
    case Elem::f32: return VoxelType::f32;
    case Elem::f64: return VoxelType::f64;
    default: return std::nullopt;
    }
}

class LegacyReader {
public:
    LegacyReader(std::string_view text, const std::string& file) : lex_(text, file) {}
    Dataset read();

private:
    enum class Section { none, point, cell };

    Elem elem(const char* what);
    uint64_t count(const char* what);
    double real(const char* what);
    void end_header_line() { lex_.line_rest(); }
    template <class T>
    void read_values(Elem e, uint64_t n, const char* what, std::vector<T>& out);
    void skip_values(Elem e, uint64_t n, const char* what);
    void check_room(Elem e, uint64_t n, const char* what);

    void read_unstructured_keyword(const std::string& kw);
    void read_structured_points_keyword(const std::string& kw);
    bool read_attribute(const std::string& kw);
    void read_field_block();
    // Whether the current section's 1-component arrays become fields: point data, and a mesh's cell data.
    bool stores_scalars() const { return section_ == Section::point || (section_ == Section::cell && !volume_mode_); }
    void skip_metadata();
    [[noreturn]] void unknown_keyword(const std::string& kw, const char* where);
    void store_scalar(const std::string& name, Elem e, uint64_t n);
    void read_cells();

    Lexer lex_;
    bool binary_ = false;
    bool volume_mode_ = false;
    Section section_ = Section::none;
    uint64_t section_tuples_ = 0;
    bool have_points_ = false, have_cells_ = false, have_types_ = false, have_dims_ = false;
    UnstructuredCells cells_;
    Volume volume_;
    bool have_volume_values_ = false;
    bool cell_data_warned_ = false;
    Dataset out_;
};

Elem LegacyReader::elem(const char* what)
{
    const std::string name = lowercase(lex_.token(what));
    for (const ElemName& n : kElemNames)
        if (name == n.name) return n.elem;
    lex_.fail("unknown data type '" + printable(name) +
              "' (expected float, double, int, unsigned_char, short, ... as VTK writes them)");
}

uint64_t LegacyReader::count(const char* what)
{
    std::string_view t = lex_.token(what);
    int64_t v = 0;
    if (!parse_int(t, v)) lex_.fail(std::string("expected ") + what + " (an integer), found '" + printable(t) + "'");
    if (v < 0) lex_.fail(std::string(what) + " is negative (" + std::to_string(v) + ")");
    return static_cast<uint64_t>(v);
}

double LegacyReader::real(const char* what)
{
    std::string_view t = lex_.token(what);
    double v = 0.0;
    if (!parse_real(t, v)) lex_.fail(std::string("expected ") + what + " (a number), found '" + printable(t) + "'");
    return v;
}

// Fails before anything is allocated when the rest of the file cannot hold n values: n values of a binary type need
// their byte size, n ASCII numbers need at least one character and one separator each.
void LegacyReader::check_room(Elem e, uint64_t n, const char* what)
{
    const uint64_t left = lex_.text().size() - std::min(lex_.offset(), lex_.text().size());
    const uint64_t need = binary_ ? binary_bytes(e, n) : (n == 0 ? 0 : product(n, 2) - 1);
    if (need > left || n > kMaxElements)
        lex_.fail("truncated: " + std::string(what) + " needs " + std::to_string(n) + " values (" +
                  (need == UINT64_MAX ? std::string("too many") : std::to_string(need)) + " bytes" +
                  (binary_ ? "" : " at least") + "), but only " + std::to_string(left) + " bytes remain");
}

template <class T>
void LegacyReader::read_values(Elem e, uint64_t n, const char* what, std::vector<T>& out)
{
    if (e == Elem::str) lex_.fail(std::string(what) + " cannot be a string array");
    if (std::is_integral_v<T> && !is_integer(e)) lex_.fail(std::string(what) + " must have an integer data type");
    check_room(e, n, what);
    out.resize(n);
    if (binary_) {
        convert_binary(e, lex_.text().data() + lex_.offset(), n, out.data());
        lex_.seek(lex_.offset() + binary_bytes(e, n));
        return;
    }
    for (uint64_t i = 0; i < n; ++i) {
        if (lex_.at_end())
            lex_.fail("truncated: expected " + std::to_string(n) + " " + what + ", the file ends after " +
                      std::to_string(i));
        std::string_view t = lex_.token(what);
        bool ok;
        if constexpr (std::is_integral_v<T>) {
            int64_t v = 0;
            ok = parse_int(t, v);
            out[i] = static_cast<T>(v);
        } else {
            double v = 0.0;
            ok = parse_real(t, v);
            out[i] = static_cast<T>(v);
        }
        if (!ok && lex_.offset() >= lex_.text().size())
            lex_.fail("truncated: the file ends inside value " + std::to_string(i) + " of " + std::to_string(n) + " " +
                      what + " ('" + printable(t) + "')");
        if (!ok)
            lex_.fail("expected " + std::to_string(n) + " " + what + ", found '" + printable(t) + "' after " +
                      std::to_string(i));
    }
}

void LegacyReader::skip_values(Elem e, uint64_t n, const char* what)
{
    if (e == Elem::str) {
        // ASCII strings are one per line; binary ones carry a length prefix whose top two bits give its width.
        for (uint64_t i = 0; i < n; ++i) {
            if (lex_.offset() >= lex_.text().size())
                lex_.fail("truncated: expected " + std::to_string(n) + " strings in " + what +
                          ", the file ends after " + std::to_string(i));
            if (!binary_) {
                lex_.line_rest();
                continue;
            }
            BinaryCursor cur(lex_.text(), lex_.file(), true);
            cur.seek(lex_.offset());
            const unsigned kind = static_cast<unsigned char>(cur.rest()[0]) >> 6;
            uint64_t len = 0;
            if (kind == 3) len = cur.read<uint8_t>(what) & 0x3Fu;
            else if (kind == 2) len = cur.read<uint16_t>(what) & 0x3FFFu;
            else if (kind == 1) len = cur.read<uint32_t>(what) & 0x3FFFFFFFu;
            else len = cur.read<uint64_t>(what);
            cur.skip(len, what);
            lex_.seek(cur.position());
        }
        return;
    }
    check_room(e, n, what);
    if (binary_) {
        lex_.seek(lex_.offset() + binary_bytes(e, n));
        return;
    }
    for (uint64_t i = 0; i < n; ++i) {
        if (lex_.at_end())
            lex_.fail("truncated: expected " + std::to_string(n) + " " + what + ", the file ends after " +
                      std::to_string(i));
        lex_.token(what);
    }
}

Dataset LegacyReader::read()
{
    const std::string_view first = lex_.line_rest();
    if (first.rfind("# vtk DataFile Version", 0) != 0)
        lex_.fail("not a VTK legacy file: first line must start with '# vtk DataFile Version'");
    lex_.line_rest();  // the title
    // VTK reads the format as a word, so blank lines before it (ironProt.vtk has one) are allowed.
    const std::string format = lex_.at_end() ? std::string() : lowercase(lex_.token("ASCII or BINARY"));
    if (format != "ascii" && format != "binary")
        lex_.fail("the line after the title must be ASCII or BINARY, found '" + printable(format) + "'");
    binary_ = format == "binary";

    const std::string dataset = lowercase(lex_.token("DATASET"));
    if (dataset != "dataset") lex_.fail("expected 'DATASET', found '" + printable(dataset) + "'");
    const std::string type = lowercase(lex_.token("dataset type"));
    end_header_line();
    cells_.source = volume_.source = lex_.file();
    if (type == "unstructured_grid") {
        while (!lex_.at_end()) read_unstructured_keyword(lowercase(lex_.token("keyword")));
        if (!have_points_) throw InputError(lex_.file(), "no POINTS section");
        if (!have_cells_) throw InputError(lex_.file(), "no CELLS section");
        if (!have_types_) throw InputError(lex_.file(), "no CELL_TYPES section");
        if (cells_.types.size() + 1 != cells_.offsets.size())
            throw InputError(lex_.file(), "CELL_TYPES lists " + std::to_string(cells_.types.size()) +
                                              " cells but CELLS holds " + std::to_string(cells_.offsets.size() - 1));
        out_.mesh = tetrahedralize_cells(cells_, out_.warnings);
    } else if (type == "structured_points") {
        volume_mode_ = true;
        while (!lex_.at_end()) read_structured_points_keyword(lowercase(lex_.token("keyword")));
        if (!have_dims_) throw InputError(lex_.file(), "no DIMENSIONS line");
        if (!have_volume_values_)
            throw InputError(lex_.file(), "no point scalars for the volume (a 1-component SCALARS or FIELD array in "
                                          "POINT_DATA)");
        finalize_volume(volume_);
        out_.volume = std::move(volume_);
    } else {
        lex_.fail("unsupported dataset type " + printable(type) + " (uvr reads UNSTRUCTURED_GRID and "
                  "STRUCTURED_POINTS)");
    }
    return std::move(out_);
}

void LegacyReader::read_unstructured_keyword(const std::string& kw)
{
    if (kw == "points") {
        const uint64_t n = count("point count");
        const Elem e = elem("point data type");
        end_header_line();
        std::vector<double> xyz;
        read_values(e, product(n, 3), "point coordinates", xyz);
        cells_.points.resize(n);
        for (uint64_t i = 0; i < n; ++i) cells_.points[i] = {xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]};
        have_points_ = true;
    } else if (kw == "cells") {
        read_cells();
    } else if (kw == "cell_types") {
        const uint64_t n = count("cell count");
        end_header_line();
        std::vector<int64_t> types;
        read_values(Elem::i32, n, "cell types", types);
        if (have_cells_ && n + 1 != cells_.offsets.size())
            lex_.fail("CELL_TYPES lists " + std::to_string(n) + " cells but CELLS holds " +
                      std::to_string(cells_.offsets.size() - 1));
        cells_.types.resize(n);
        for (uint64_t i = 0; i < n; ++i) {
            if (types[i] < INT32_MIN || types[i] > INT32_MAX)
                lex_.fail("cell " + std::to_string(i) + " has an invalid cell type " + std::to_string(types[i]));
            cells_.types[i] = static_cast<int32_t>(types[i]);
        }
        have_types_ = true;
    } else if (kw == "point_data") {
        const uint64_t n = count("point count");
        if (!have_points_) lex_.fail("POINT_DATA comes before POINTS");
        if (n != cells_.points.size())
            lex_.fail("POINT_DATA has " + std::to_string(n) + " values but POINTS has " +
                      std::to_string(cells_.points.size()));
        section_ = Section::point;
        section_tuples_ = n;
    } else if (!read_attribute(kw)) {
        unknown_keyword(kw, "an UNSTRUCTURED_GRID");
    }
}

// Old form: "CELLS n size" and n count-prefixed lists of int. Version 5 form: "CELLS nOffsets nConnectivity" followed
// by an OFFSETS and a CONNECTIVITY array of any integer type.
void LegacyReader::read_cells()
{
    const uint64_t a = count("cell count"), b = count("cell list size");
    end_header_line();
    const Lexer::Mark after_header = lex_.mark();
    const bool new_form = !lex_.at_end() && lowercase(lex_.token("OFFSETS")) == "offsets";
    cells_.offsets.clear();
    cells_.connectivity.clear();
    if (new_form) {
        const Elem oe = elem("offsets data type");
        end_header_line();
        read_values(oe, a, "cell offsets", cells_.offsets);
        if (lowercase(lex_.token("CONNECTIVITY")) != "connectivity")
            lex_.fail("expected CONNECTIVITY after the OFFSETS array");
        const Elem ce = elem("connectivity data type");
        end_header_line();
        read_values(ce, b, "cell connectivity", cells_.connectivity);
        if (a == 0) cells_.offsets.push_back(0);
        if (cells_.offsets.front() != 0 || static_cast<uint64_t>(cells_.offsets.back()) != b)
            lex_.fail("cell OFFSETS must start at 0 and end at the CONNECTIVITY size " + std::to_string(b));
        for (std::size_t c = 0; c + 1 < cells_.offsets.size(); ++c)
            if (cells_.offsets[c + 1] < cells_.offsets[c])
                lex_.fail("cell OFFSETS decrease at cell " + std::to_string(c));
    } else {
        lex_.restore(after_header);
        std::vector<int64_t> lists;
        read_values(Elem::i32, b, "cell list entries", lists);
        if (a > b) lex_.fail("CELLS claims " + std::to_string(a) + " cells in only " + std::to_string(b) + " entries");
        cells_.offsets.reserve(a + 1);
        cells_.offsets.push_back(0);
        cells_.connectivity.reserve(b - std::min(a, b));
        uint64_t pos = 0;
        for (uint64_t c = 0; c < a; ++c) {
            if (pos >= b)
                lex_.fail("CELLS lists end after " + std::to_string(c) + " cells, but the header says " +
                          std::to_string(a));
            const int64_t k = lists[pos++];
            if (k < 0 || static_cast<uint64_t>(k) > b - pos)
                lex_.fail("cell " + std::to_string(c) + " claims " + std::to_string(k) + " points, but only " +
                          std::to_string(b - pos) + " entries remain in CELLS");
            cells_.connectivity.insert(cells_.connectivity.end(), lists.begin() + long(pos),
                                       lists.begin() + long(pos + uint64_t(k)));
            pos += uint64_t(k);
            cells_.offsets.push_back(static_cast<int64_t>(cells_.connectivity.size()));
        }
        if (pos != b)
            lex_.fail("CELLS size mismatch: the header says " + std::to_string(b) + " entries, the " +
                      std::to_string(a) + " cells use " + std::to_string(pos));
    }
    if (have_types_ && cells_.types.size() + 1 != cells_.offsets.size())
        lex_.fail("CELLS holds " + std::to_string(cells_.offsets.size() - 1) + " cells but CELL_TYPES lists " +
                  std::to_string(cells_.types.size()));
    have_cells_ = true;
}

void LegacyReader::read_structured_points_keyword(const std::string& kw)
{
    if (kw == "dimensions") {
        for (int a = 0; a < 3; ++a) {
            const uint64_t d = count("dimension");
            if (d < 1 || d > kMaxElements)
                lex_.fail("DIMENSIONS must be between 1 and 2^34, found " + std::to_string(d));
            volume_.dims[a] = static_cast<int64_t>(d);
        }
        have_dims_ = true;
    } else if (kw == "origin") {
        for (int a = 0; a < 3; ++a) volume_.origin[a] = real("origin");
    } else if (kw == "spacing" || kw == "aspect_ratio") {
        for (int a = 0; a < 3; ++a) volume_.spacing[a] = real("spacing");
    } else if (kw == "point_data") {
        const uint64_t n = count("point count");
        if (!have_dims_) lex_.fail("POINT_DATA comes before DIMENSIONS");
        const uint64_t expected = product(product(uint64_t(volume_.dims[0]), uint64_t(volume_.dims[1])),
                                          uint64_t(volume_.dims[2]));
        if (n != expected)
            lex_.fail("POINT_DATA has " + std::to_string(n) + " values but DIMENSIONS give " +
                      std::to_string(expected) + " points");
        section_ = Section::point;
        section_tuples_ = n;
    } else if (!read_attribute(kw)) {
        unknown_keyword(kw, "STRUCTURED_POINTS");
    }
}

// The keywords that may appear in any dataset: attribute arrays, FIELD blocks, CELL_DATA, METADATA. Returns false for
// anything else.
bool LegacyReader::read_attribute(const std::string& kw)
{
    if (kw == "cell_data") {
        section_tuples_ = count("cell count");
        section_ = Section::cell;
        return true;
    }
    if (section_ == Section::cell && volume_mode_ && kw != "metadata" && !cell_data_warned_) {
        out_.warnings.push_back(lex_.file() + ": CELL_DATA ignored (a regular grid's scalars are point data)");
        cell_data_warned_ = true;
    }
    if (kw == "field") {
        read_field_block();
        return true;
    }
    if (kw == "metadata") {
        skip_metadata();
        return true;
    }
    static const char* const kAttributes[] = {"scalars",  "color_scalars", "lookup_table", "vectors",
                                              "normals",  "tensors",       "tensors6",     "texture_coordinates",
                                              "global_ids", "pedigree_ids"};
    if (std::find(std::begin(kAttributes), std::end(kAttributes), kw) == std::end(kAttributes)) return false;
    const std::string upper = uppercase(kw);
    if (section_ == Section::none && kw != "lookup_table")
        lex_.fail(upper + " outside POINT_DATA or CELL_DATA");
    const uint64_t n = section_tuples_;
    const std::string name = decode_name(lex_.token("array name"));
    if (kw == "scalars") {
        const Elem e = elem("data type");
        const std::string_view rest = trim(lex_.line_rest());
        int64_t comps = 1;
        if (!rest.empty() && (!parse_int(rest, comps) || comps < 1))
            lex_.fail("SCALARS '" + name + "': expected a component count, found '" + printable(rest) + "'");
        // LOOKUP_TABLE is required by VTK but often left out by other writers; the data start after it if present.
        const Lexer::Mark data_start = lex_.mark();
        if (!lex_.at_end() && lowercase(lex_.token("LOOKUP_TABLE")) == "lookup_table") {
            lex_.token("lookup table name");
            end_header_line();
        } else {
            lex_.restore(data_start);
        }
        if (stores_scalars() && comps == 1 && e != Elem::str) {
            store_scalar(name, e, n);
        } else {
            if (stores_scalars())
                out_.warnings.push_back(lex_.file() + ": SCALARS '" + name + "' with " + std::to_string(comps) +
                                        " components ignored (uvr uses 1-component scalars)");
            skip_values(e, product(n, uint64_t(comps)), "SCALARS values");
        }
    } else if (kw == "color_scalars") {
        const uint64_t comps = count("component count");
        end_header_line();
        skip_values(binary_ ? Elem::u8 : Elem::f32, product(n, comps), "COLOR_SCALARS values");
    } else if (kw == "lookup_table") {
        const uint64_t size = count("lookup table size");
        end_header_line();
        skip_values(binary_ ? Elem::u8 : Elem::f32, product(size, 4), "LOOKUP_TABLE entries");
    } else {
        uint64_t comps = 1;
        if (kw == "vectors" || kw == "normals") comps = 3;
        else if (kw == "tensors") comps = 9;
        else if (kw == "tensors6") comps = 6;
        else if (kw == "texture_coordinates") comps = count("texture dimension");
        const Elem e = elem("data type");
        end_header_line();
        skip_values(e, product(n, comps), (upper + " values").c_str());
    }
    return true;
}

// FIELD name numArrays, then per array "name numComponents numTuples type" and its values (or NULL_ARRAY). In point
// data (and a mesh's cell data), 1-component arrays with one value per point (cell) become scalar fields; everything
// else is skipped.
void LegacyReader::read_field_block()
{
    const bool point_data = stores_scalars();
    lex_.token("field name");
    const uint64_t arrays = count("number of field arrays");
    end_header_line();
    for (uint64_t i = 0; i < arrays; ++i) {
        const std::string name = decode_name(lex_.token("field array name"));
        if (name == "NULL_ARRAY") continue;
        const uint64_t comps = count("component count"), tuples = count("tuple count");
        const Elem e = elem("field array data type");
        end_header_line();
        if (point_data && comps == 1 && tuples == section_tuples_ && e != Elem::str) {
            store_scalar(name, e, tuples);
        } else {
            if (point_data)
                out_.warnings.push_back(lex_.file() + ": field array '" + name + "' (" + std::to_string(comps) +
                                        " components, " + std::to_string(tuples) + " tuples) ignored");
            skip_values(e, product(comps, tuples), "field array values");
        }
        const Lexer::Mark next = lex_.mark();
        if (!lex_.at_end() && lowercase(lex_.token("keyword")) == "metadata")
            skip_metadata();
        else
            lex_.restore(next);
    }
}

void LegacyReader::unknown_keyword(const std::string& kw, const char* where)
{
    if (lex_.offset() >= lex_.text().size())
        lex_.fail("truncated: the file ends inside '" + printable(kw) + "'");
    double number = 0.0;
    if (parse_real(kw, number))
        lex_.fail("found the number '" + printable(kw) + "' where a keyword was expected (a count in an earlier "
                  "header is smaller than the data that follow it)");
    lex_.fail("unknown keyword '" + printable(kw) + "' in " + where);
}

// METADATA is followed by text lines (COMPONENT_NAMES, INFORMATION) up to a blank line.
void LegacyReader::skip_metadata()
{
    lex_.line_rest();
    while (lex_.offset() < lex_.text().size()) {
        const std::string_view l = lex_.line_rest();
        if (l.find_first_not_of(" \t\r") == std::string_view::npos) break;
    }
}

void LegacyReader::store_scalar(const std::string& name, Elem e, uint64_t n)
{
    if (!volume_mode_) {
        ScalarField f;
        f.name = name;
        const bool cell = section_ == Section::cell;
        read_values(e, n, cell ? "cell scalars" : "point scalars", f.values);
        (cell ? cells_.cell_fields : cells_.point_fields).push_back(std::move(f));
        return;
    }
    if (have_volume_values_) {
        out_.warnings.push_back(lex_.file() + ": point array '" + name + "' ignored (the volume is '" + volume_.name +
                                "')");
        skip_values(e, n, "point scalars");
        return;
    }
    const std::optional<VoxelType> vt = voxel_type(e);
    if (!vt) lex_.fail("volume scalars '" + name + "' have a data type uvr volumes do not support (64-bit or bit)");
    volume_.type = *vt;
    volume_.name = name;
    read_values(e, n, "volume values", volume_.values);
    have_volume_values_ = true;
}

}  // namespace

Dataset read_vtk_legacy(const std::string& path)
{
    const std::string data = read_file_bytes(path);
    if (data.empty()) throw InputError(path, "empty file (not a VTK legacy file)");
    return LegacyReader(data, path).read();
}

}  // namespace uvr
