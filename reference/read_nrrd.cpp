// NRRD volumes (.nrrd with attached data, .nhdr with detached data), versions NRRD0001 to NRRD0005.
//
// Read: 3D scalar grids of the integer types up to 32 bits, float and double; encodings raw, gzip and ascii; spacings
// or axis-aligned space directions, space origin; line skip and byte skip (-1: the data are the file's last bytes);
// one data file, a numbered series ("data file: quarter.%d 1 93 1 [subdim]") or an explicit list ("data file: LIST",
// names on the following lines). Each data file of a series holds an equal share of the samples, in order.
// Non-axis-aligned space directions are refused: the ray caster's grids are axis-aligned, and silently dropping a
// rotation would render the data in the wrong place.
#include <array>
#include <cctype>
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

std::optional<VoxelType> nrrd_type(const std::string& name)
{
    struct Alias {
        const char* name;
        VoxelType type;
    };
    static const Alias aliases[] = {
        {"signed char", VoxelType::i8},      {"int8", VoxelType::i8},
        {"int8_t", VoxelType::i8},           {"uchar", VoxelType::u8},
        {"unsigned char", VoxelType::u8},    {"uint8", VoxelType::u8},
        {"uint8_t", VoxelType::u8},          {"short", VoxelType::i16},
        {"short int", VoxelType::i16},       {"signed short", VoxelType::i16},
        {"signed short int", VoxelType::i16}, {"int16", VoxelType::i16},
        {"int16_t", VoxelType::i16},         {"ushort", VoxelType::u16},
        {"unsigned short", VoxelType::u16},  {"unsigned short int", VoxelType::u16},
        {"uint16", VoxelType::u16},          {"uint16_t", VoxelType::u16},
        {"int", VoxelType::i32},             {"signed int", VoxelType::i32},
        {"int32", VoxelType::i32},           {"int32_t", VoxelType::i32},
        {"uint", VoxelType::u32},            {"unsigned int", VoxelType::u32},
        {"uint32", VoxelType::u32},          {"uint32_t", VoxelType::u32},
        {"float", VoxelType::f32},           {"double", VoxelType::f64},
    };
    for (const Alias& a : aliases)
        if (name == a.name) return a.type;
    return std::nullopt;
}

struct Header {
    std::string path;
    long line = 0;  // of the field being parsed, for messages
    std::optional<VoxelType> type;
    int dimension = 0;
    std::array<int64_t, 3> sizes{0, 0, 0};
    std::string encoding;
    std::optional<bool> big_endian;
    std::optional<glm::dvec3> spacings, directions_diagonal, origin;
    int64_t line_skip = 0, byte_skip = 0;
    std::vector<std::string> data_files;  // empty (and no series): the data are attached
    // A numbered series ("data file: quarter.%d 1 93 1"): its names are made one at a time as the files are read,
    // so a header naming 10^8 files costs nothing until the first missing one is reported.
    std::string series_pattern;
    int64_t series_first = 0, series_step = 1, series_count = 0;
    int64_t subdim = 0;                   // 0: not given
    std::string content;
    std::size_t data_offset = 0;          // of attached data
    bool blank_line_seen = false;

    [[noreturn]] void fail(const std::string& what) const { throw InputError(path, line, what); }

    int64_t integer(const std::string& s, const char* what) const
    {
        TextScanner sc(s, path, false);
        try {
            int64_t v = sc.integer(what);
            if (sc.at_end()) return v;
        } catch (const InputError&) {
        }
        fail(std::string("expected ") + what + " (an integer), found '" + s.substr(0, 40) + "'");
    }
    double real(const std::string& s, const char* what) const
    {
        TextScanner sc(s, path, false);
        try {
            double v = sc.real(what);
            if (sc.at_end()) return v;
        } catch (const InputError&) {
        }
        fail(std::string("expected ") + what + " (a number), found '" + s.substr(0, 40) + "'");
    }
    std::vector<std::string> exactly(std::string_view value, std::size_t n, const char* what) const
    {
        auto words = split_words(value);
        if (words.size() != n)
            fail(std::string(what) + ": expected " + std::to_string(n) + " values, found " +
                 std::to_string(words.size()));
        return words;
    }
    // "(x,y,z)" vectors, or "none" for an axis without one.
    std::vector<std::optional<glm::dvec3>> vectors(std::string_view value, const char* what) const
    {
        std::vector<std::optional<glm::dvec3>> result;
        for (const std::string& w : split_words(value)) {
            if (w == "none") {
                result.emplace_back();
                continue;
            }
            std::string inner = w.size() >= 2 ? w.substr(1, w.size() - 2) : std::string();
            for (char& c : inner) c = c == ',' ? ' ' : c;
            auto parts = split_words(inner);
            if (w.front() != '(' || w.back() != ')' || parts.size() != 3)
                fail(std::string(what) + ": expected a vector like (1,0,0), found '" + w.substr(0, 40) + "'");
            result.push_back(glm::dvec3(real(parts[0], what), real(parts[1], what), real(parts[2], what)));
        }
        return result;
    }
};

std::string expand_pattern(const Header& h, const std::string& pattern, int64_t index)
{
    std::string out;
    bool used = false;
    for (std::size_t i = 0; i < pattern.size(); ++i) {
        if (pattern[i] != '%') {
            out += pattern[i];
            continue;
        }
        if (i + 1 < pattern.size() && pattern[i + 1] == '%') {
            out += '%';
            ++i;
            continue;
        }
        std::size_t j = i + 1;
        bool zero = j < pattern.size() && pattern[j] == '0';
        std::size_t width = 0;
        while (j < pattern.size() && std::isdigit(static_cast<unsigned char>(pattern[j])) && width < 100)
            width = width * 10 + std::size_t(pattern[j++] - '0');
        if (used || j >= pattern.size() || (pattern[j] != 'd' && pattern[j] != 'i' && pattern[j] != 'u'))
            h.fail("data file pattern '" + pattern + "' must hold exactly one %d (optionally %0Nd)");
        std::string digits = std::to_string(index < 0 ? -index : index);
        std::size_t len = digits.size() + (index < 0 ? 1 : 0);
        std::string pad = width > len ? std::string(width - len, zero ? '0' : ' ') : std::string();
        out += zero ? (index < 0 ? "-" : "") + pad + digits : pad + (index < 0 ? "-" : "") + digits;
        used = true;
        i = j;
    }
    if (!used) h.fail("data file pattern '" + pattern + "' holds no %d");
    return out;
}

// Returns true for the LIST form, whose names end the header.
bool parse_data_file(Header& h, const std::string& value, std::string_view text, std::size_t& pos, long& line)
{
    auto words = split_words(value);
    if (words.empty()) h.fail("'data file' names no file");
    if (words[0] == "LIST") {
        if (words.size() > 2) h.fail("'data file: LIST' takes at most a sub-dimension");
        if (words.size() == 2) h.subdim = h.integer(words[1], "data file sub-dimension");
        // The names fill the rest of the header, one per line.
        while (pos < text.size()) {
            std::size_t nl = text.find('\n', pos);
            std::string_view name = text.substr(pos, nl == std::string_view::npos ? nl : nl - pos);
            pos = nl == std::string_view::npos ? text.size() : nl + 1;
            ++line;
            if (!name.empty() && name.back() == '\r') name.remove_suffix(1);
            if (name.empty()) break;
            h.data_files.emplace_back(name);
        }
        if (h.data_files.empty()) h.fail("'data file: LIST' is followed by no file name");
        return true;
    }
    if ((words.size() == 4 || words.size() == 5) && words[0].find('%') != std::string::npos) {
        const int64_t first = h.integer(words[1], "first file number"), last = h.integer(words[2], "last file number");
        const int64_t step = h.integer(words[3], "file number step");
        if (words.size() == 5) h.subdim = h.integer(words[4], "data file sub-dimension");
        if (step == 0) h.fail("the data file step must not be 0");
        const int64_t bound = int64_t(1) << 53;
        if (first < -bound || first > bound || last < -bound || last > bound)
            h.fail("the data file numbers " + words[1] + " to " + words[2] + " are out of range");
        const long double count = std::floor((static_cast<long double>(last) - first) / step) + 1;
        const long double samples = static_cast<long double>(h.sizes[0]) * h.sizes[1] * h.sizes[2];
        if (count < 1)
            h.fail("the data file numbers " + words[1] + " to " + words[2] + " by " + words[3] + " are empty");
        if (h.dimension == 0 || count > samples)
            h.fail("the data file series names " + std::to_string(static_cast<int64_t>(std::min(count, 1e18L))) +
                   " files, more than the volume's samples (give 'sizes' before 'data file')");
        h.series_pattern = words[0];
        h.series_first = first;
        h.series_step = step;
        h.series_count = static_cast<int64_t>(count);
        expand_pattern(h, words[0], first);  // a malformed pattern is refused now, not at the first read
        return false;
    }
    h.data_files.push_back(value);
    return false;
}

// The fields of the samples and the grid: type, dimension, sizes. False for any other field.
bool parse_grid_field(Header& h, const std::string& field, const std::string& value)
{
    if (field == "type") {
        std::string name;
        for (const std::string& w : split_words(lowercase(value))) name += (name.empty() ? "" : " ") + w;
        h.type = nrrd_type(name);
        if (!h.type)
            h.fail("unsupported type '" + value + "' (uvr reads 8-, 16- and 32-bit integers, float and double)");
    } else if (field == "dimension") {
        int64_t d = h.integer(value, "dimension");
        if (d != 3) h.fail("dimension " + std::to_string(d) + ": uvr reads 3D volumes only");
        h.dimension = 3;
    } else if (field == "sizes") {
        auto w = h.exactly(value, 3, "sizes");
        for (int a = 0; a < 3; ++a) {
            h.sizes[a] = h.integer(w[a], "size");
            if (h.sizes[a] < 1) h.fail("sizes must be at least 1, found " + w[a]);
        }
    } else {
        return false;
    }
    return true;
}

// The diagonal of axis-aligned, positive space directions (one vector per axis).
glm::dvec3 directions_diagonal(const Header& h, const std::string& value)
{
    auto v = h.vectors(value, "space directions");
    if (v.size() != 3 || !v[0] || !v[1] || !v[2]) h.fail("space directions: expected three vectors, one per axis");
    glm::dvec3 diag;
    for (int a = 0; a < 3; ++a) {
        for (int b = 0; b < 3; ++b)
            if (a != b && (*v[a])[b] != 0.0)
                h.fail("space directions are not axis-aligned; uvr renders axis-aligned grids only");
        if (!((*v[a])[a] > 0.0))
            h.fail("space direction of axis " + std::to_string(a) +
                   " is not positive (flipped axes are not supported)");
        diag[a] = (*v[a])[a];
    }
    return diag;
}

// The fields of the samples' positions: spacings, space directions, space origin, space dimension. False for any
// other field.
bool parse_space_field(Header& h, const std::string& field, const std::string& value)
{
    if (field == "spacings") {
        auto w = h.exactly(value, 3, "spacings");
        h.spacings = glm::dvec3(h.real(w[0], "spacing"), h.real(w[1], "spacing"), h.real(w[2], "spacing"));
    } else if (field == "space directions") {
        h.directions_diagonal = directions_diagonal(h, value);
    } else if (field == "space origin") {
        auto v = h.vectors(value, "space origin");
        if (v.size() != 1 || !v[0]) h.fail("space origin: expected one vector like (0,0,0)");
        h.origin = *v[0];
    } else if (field == "space dimension") {
        if (h.integer(value, "space dimension") != 3) h.fail("space dimension must be 3");
    } else {
        return false;
    }
    return true;
}

// The fields of how the samples are stored: encoding, endian, line skip, byte skip. False for any other field.
bool parse_storage_field(Header& h, const std::string& field, const std::string& value)
{
    if (field == "encoding") {
        h.encoding = lowercase(value);
        if (h.encoding == "gz") h.encoding = "gzip";
        if (h.encoding == "text" || h.encoding == "txt") h.encoding = "ascii";
        if (h.encoding != "raw" && h.encoding != "gzip" && h.encoding != "ascii")
            h.fail("unsupported encoding '" + value + "' (uvr reads raw, gzip and ascii)");
    } else if (field == "endian") {
        if (value != "little" && value != "big") h.fail("endian must be 'little' or 'big', found '" + value + "'");
        h.big_endian = value == "big";
    } else if (field == "line skip" || field == "lineskip") {
        h.line_skip = h.integer(value, "line skip");
        if (h.line_skip < 0) h.fail("line skip must not be negative");
    } else if (field == "byte skip" || field == "byteskip") {
        h.byte_skip = h.integer(value, "byte skip");
        if (h.byte_skip < -1) h.fail("byte skip must be -1 or more");
    } else {
        return false;
    }
    return true;
}

Header parse_header(const std::string& path, std::string_view text)
{
    Header h;
    h.path = path;
    std::size_t pos = 0;
    long line = 0;
    auto next_line = [&](std::string_view& out) {
        if (pos >= text.size()) return false;
        std::size_t nl = text.find('\n', pos);
        out = text.substr(pos, nl == std::string_view::npos ? nl : nl - pos);
        pos = nl == std::string_view::npos ? text.size() : nl + 1;
        h.line = ++line;
        if (!out.empty() && out.back() == '\r') out.remove_suffix(1);
        return true;
    };
    std::string_view l;
    if (!next_line(l)) throw InputError(path, "empty file: expected a NRRD header");
    if (l.size() != 8 || l.substr(0, 7) != "NRRD000" || l[7] < '1' || l[7] > '5')
        h.fail("not a NRRD file: the first line must be NRRD0001 to NRRD0005, found '" + std::string(l.substr(0, 40)) +
               "'");
    while (next_line(l)) {
        if (l.empty()) {
            h.blank_line_seen = true;
            break;
        }
        if (l[0] == '#' || l.find(":=") != std::string_view::npos) continue;  // comments, key/value pairs
        std::size_t colon = l.find(": ");
        if (colon == std::string_view::npos)
            h.fail("expected 'field: value', found '" + std::string(l.substr(0, 60)) + "'");
        const std::string field = lowercase(l.substr(0, colon));
        std::string value(l.substr(colon + 2));
        while (!value.empty() && (value.back() == ' ' || value.back() == '\t')) value.pop_back();
        if (parse_grid_field(h, field, value) || parse_space_field(h, field, value) ||
            parse_storage_field(h, field, value))
            continue;
        if (field == "data file" || field == "datafile") {
            if (parse_data_file(h, value, text, pos, line)) break;
        } else if (field == "content") {
            h.content = value;
        }
        // Every other field (kinds, centers, units, labels, space, measurement frame, ...) has no bearing on the
        // samples' values or positions in an axis-aligned grid.
    }
    h.data_offset = pos;
    h.line = 0;
    if (!h.type) h.fail("the header has no 'type' field");
    if (h.dimension == 0) h.fail("the header has no 'dimension' field");
    if (h.sizes[0] == 0) h.fail("the header has no 'sizes' field");
    if (h.encoding.empty()) h.fail("the header has no 'encoding' field");
    return h;
}

// The stored samples of one data file (or of the attached data) after its line and byte skips: a view into `data`
// for raw encoding, into `inflated` for gzip.
std::string_view piece_bytes(const Header& h, const std::string& file, std::string_view data, uint64_t need,
                             std::string& inflated)
{
    for (int64_t l = 0; l < h.line_skip; ++l) {
        std::size_t nl = data.find('\n');
        if (nl == std::string_view::npos)
            throw InputError(file, "truncated: 'line skip: " + std::to_string(h.line_skip) +
                                       "' skips more lines than the data hold");
        data.remove_prefix(nl + 1);
    }
    if (h.encoding == "raw") {
        if (h.byte_skip == -1) {
            if (data.size() < need)
                throw InputError(file, "truncated: the data need " + std::to_string(need) + " bytes, the file holds " +
                                           std::to_string(data.size()));
            return data.substr(data.size() - need);
        }
        if (uint64_t(h.byte_skip) > data.size() || data.size() - h.byte_skip < need)
            throw InputError(file, "truncated: the data need " + std::to_string(need) + " bytes after skipping " +
                                       std::to_string(h.byte_skip) + ", but only " +
                                       std::to_string(data.size() - std::min<uint64_t>(h.byte_skip, data.size())) +
                                       " remain");
        return data.substr(h.byte_skip, need);
    }
    // gzip: byte skip counts decompressed bytes, as in teem.
    if (h.byte_skip == -1) throw InputError(h.path, "'byte skip: -1' is only allowed with raw encoding");
    const uint64_t total = need + uint64_t(h.byte_skip);
    if (total / 1032 > data.size() + 64)
        throw InputError(file, "truncated: " + std::to_string(data.size()) + " compressed bytes cannot hold the " +
                                   std::to_string(total) + " bytes the header describes");
    inflated = inflate_bytes(data, total, file, "gzip data");
    return std::string_view(inflated).substr(h.byte_skip);
}

void read_ascii_piece(const Header& h, const std::string& file, std::string_view data, uint64_t count,
                      std::vector<float>& out, std::size_t at)
{
    TextScanner sc(data, file, false);
    for (int64_t l = 0; l < h.line_skip; ++l) sc.line_rest();
    if (count > data.size() / 2 + 1)
        throw InputError(file, "truncated: the text holds too few bytes for " + std::to_string(count) + " samples");
    for (uint64_t i = 0; i < count; ++i) {
        if (sc.at_end())
            sc.fail("truncated: expected " + std::to_string(count) + " samples, found " + std::to_string(i));
        out[at + i] = static_cast<float>(sc.real("sample"));
    }
}

}  // namespace

Dataset read_nrrd(const std::string& path)
{
    const std::string text = read_file_bytes(path);
    const Header h = parse_header(path, text);
    const std::size_t elem = voxel_type_size(*h.type);
    const bool ascii = h.encoding == "ascii";
    const bool compressed = h.encoding == "gzip";
    if (elem > 1 && !h.big_endian && !ascii)
        throw InputError(path, "the header has no 'endian' field, needed for multi-byte samples");

    uint64_t samples = 1;
    for (int64_t s : h.sizes) {
        if (uint64_t(s) > kMaxElements / samples)
            throw InputError(path, "the sizes " + std::to_string(h.sizes[0]) + " " + std::to_string(h.sizes[1]) + " " +
                                       std::to_string(h.sizes[2]) + " describe more samples than uvr can hold");
        samples *= uint64_t(s);
    }
    const bool attached = h.data_files.empty() && h.series_count == 0;
    const uint64_t pieces = attached ? 1 : h.series_count ? uint64_t(h.series_count) : h.data_files.size();
    uint64_t per_piece = samples / pieces;
    if (h.subdim != 0) {
        if (h.subdim < 1 || h.subdim > 3) throw InputError(path, "data file sub-dimension must be 1 to 3");
        per_piece = 1;
        for (int a = 0; a < h.subdim; ++a) per_piece *= uint64_t(h.sizes[a]);
    }
    if (per_piece * pieces != samples)
        throw InputError(path, std::to_string(pieces) + " data files cannot hold " + std::to_string(samples) +
                                   " samples in equal parts of " + std::to_string(per_piece));
    if (attached && !h.blank_line_seen)
        throw InputError(path, "no data: the header names no 'data file' and is not followed by a blank line and "
                               "attached data");

    auto piece_path = [&](uint64_t p) {
        if (attached) return path;
        const std::string name = h.series_count
                                     ? expand_pattern(h, h.series_pattern, h.series_first + int64_t(p) * h.series_step)
                                     : h.data_files[p];
        return name.front() == '/' ? name : directory_of(path) + name;
    };
    // The first piece is read before the value array is allocated, so that sizes no file could hold are refused
    // without allocating them.
    std::string first = attached ? std::string() : read_file_bytes(piece_path(0));
    const uint64_t available = attached ? text.size() - h.data_offset : first.size();
    // Deflate expands at most about 1032:1 and an ascii sample takes at least two characters.
    const uint64_t holdable = compressed ? available * 1032 + 64 : ascii ? available / 2 + 1 : available;
    if (per_piece * (ascii ? 1 : elem) > holdable)
        throw InputError(piece_path(0), "truncated: " + std::to_string(per_piece) + " samples of " +
                                            std::to_string(elem) + " bytes need " + std::to_string(per_piece * elem) +
                                            " bytes of " + h.encoding + " data, but the file holds only " +
                                            std::to_string(available) + " bytes of data");

    Volume v;
    v.source = path;
    v.name = h.content;
    v.dims = h.sizes;
    v.type = *h.type;
    v.spacing = h.directions_diagonal ? *h.directions_diagonal : h.spacings ? *h.spacings : glm::dvec3(1.0);
    v.origin = h.origin ? *h.origin : glm::dvec3(0.0);
    v.values.resize(samples);
    for (uint64_t p = 0; p < pieces; ++p) {
        const std::string file = piece_path(p);
        std::string owned = p == 0 ? std::move(first) : read_file_bytes(file);
        std::string_view data = attached ? std::string_view(text).substr(h.data_offset) : std::string_view(owned);
        if (ascii) {
            read_ascii_piece(h, file, data, per_piece, v.values, p * per_piece);
        } else {
            std::string inflated;
            std::string_view bytes = piece_bytes(h, file, data, per_piece * elem, inflated);
            decode_voxels(bytes, v.type, h.big_endian.value_or(false), v.values.data() + p * per_piece);
        }
    }
    finalize_volume(v);
    Dataset result;
    result.volume = std::move(v);
    return result;
}

}  // namespace uvr
