// PLOT3D grid (XYZ) and solution (Q) files.
//
// PLOT3D has no magic number and no self-describing header: the same bytes can be big- or little-endian, whole-file or
// Fortran-record framed, single- or double-precision, with or without iblank, with or without a leading grid count.
// The only reliable test is arithmetic: an interpretation is right when the sizes it implies add up to the file's size
// exactly. We therefore unwrap Fortran records first (they are recognisable by their matching length markers), then try
// each remaining interpretation, preferring big-endian (the classic NASA files) and single precision.
//
// The Q file must describe the same grid; its four reference values (Mach, alpha, Reynolds number, time) are read and
// dropped, and its five variables become point fields, Density first so that it is the default field.
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "reference/cells.h"
#include "reference/dataset.h"
#include "reference/error.h"
#include "reference/io_util.h"

namespace uvr {

namespace {

using Dims = std::array<int64_t, 3>;

struct GridLayout {
    bool big_endian = true;
    bool grid_count = false;  // the file starts with a grid count (which must be 1)
    int precision = 4;        // bytes per real
    bool iblank = false;
    Dims dims{0, 0, 0};
};

const char* const kQNames[5] = {"Density", "MomentumX", "MomentumY", "MomentumZ", "StagnationEnergy"};

std::string dims_text(const Dims& d)
{
    return std::to_string(d[0]) + "x" + std::to_string(d[1]) + "x" + std::to_string(d[2]);
}

int32_t int_at(std::string_view data, uint64_t pos, bool big_endian)
{
    int32_t v;
    std::memcpy(&v, data.data() + pos, sizeof v);
    return big_endian ? byteswap_value(v) : v;
}

// The number of points of a dims triple, or nothing when a dimension is below 1 or the count exceeds `limit` (a file
// of `limit` bytes cannot hold more points than that, so larger counts are rejected before any multiplication can
// overflow).
std::optional<uint64_t> point_count(const Dims& d, uint64_t limit)
{
    uint64_t n = 1;
    for (int64_t v : d) {
        if (v < 1 || static_cast<uint64_t>(v) > limit || n > limit / static_cast<uint64_t>(v)) return std::nullopt;
        n *= static_cast<uint64_t>(v);
    }
    return n;
}

Dims dims_at(std::string_view data, uint64_t pos, bool big_endian)
{
    return {int_at(data, pos, big_endian), int_at(data, pos + 4, big_endian), int_at(data, pos + 8, big_endian)};
}

// Fortran unformatted sequential files frame every record as [length][payload][length]. When the whole file parses as
// such a chain (in either byte order), returns the concatenated payloads, which then have the whole-file layout.
std::optional<std::string> unwrap_fortran_records(const std::string& data, bool& big_endian)
{
    for (bool be : {true, false}) {
        std::string payload;
        uint64_t pos = 0;
        int records = 0;
        while (pos + 4 <= data.size()) {
            uint32_t len = static_cast<uint32_t>(int_at(data, pos, be));
            if (len == 0 || len > data.size() - pos - 4 || data.size() - pos - 4 - len < 4) break;
            if (static_cast<uint32_t>(int_at(data, pos + 4 + len, be)) != len) break;
            payload.append(data, pos + 4, len);
            pos += 8 + uint64_t(len);
            ++records;
        }
        if (pos == data.size() && records >= 2) {
            big_endian = be;
            return payload;
        }
    }
    return std::nullopt;
}

std::string read_unwrapped(const std::string& path, bool& big_endian)
{
    std::string data = read_file_bytes(path);
    if (data.empty()) throw InputError(path, "empty file: no PLOT3D header");
    auto unwrapped = unwrap_fortran_records(data, big_endian);
    return unwrapped ? std::move(*unwrapped) : data;
}

// Finds the grid layout whose sizes add up to the file's size, or explains why none does.
GridLayout detect_grid_layout(const std::string& data, const std::string& path, bool preferred_big_endian)
{
    const uint64_t size = data.size();
    if (size < 12)
        throw InputError(path, "truncated: " + std::to_string(size) + " bytes is too short for a PLOT3D header");

    std::vector<GridLayout> matches;
    int multi_grid_count = 0;
    for (bool be : {preferred_big_endian, !preferred_big_endian}) {
        auto consider = [&](bool grid_count, uint64_t header, const Dims& dims) {
            auto n = point_count(dims, size);
            if (!n) return;
            for (int precision : {4, 8})
                for (bool iblank : {false, true}) {
                    uint64_t need = header + *n * (3 * uint64_t(precision) + (iblank ? 4 : 0));
                    if (need == size) matches.push_back({be, grid_count, precision, iblank, dims});
                }
        };
        consider(false, 12, dims_at(data, 0, be));
        int32_t grids = int_at(data, 0, be);
        if (grids == 1 && size >= 16) consider(true, 16, dims_at(data, 4, be));
        if (grids > 1 && uint64_t(grids) <= (size - 4) / 12) {
            // A multi-grid file: recognise it (so the user hears the real reason) but do not read it.
            uint64_t need = 4 + 12 * uint64_t(grids), points = 0;
            bool plausible = true;
            for (int32_t g = 0; g < grids && plausible; ++g) {
                auto n = point_count(dims_at(data, 4 + 12 * uint64_t(g), be), size);
                plausible = n && points + *n <= size;
                if (plausible) points += *n;
            }
            if (plausible && (need + 12 * points == size || need + 16 * points == size || need + 24 * points == size ||
                              need + 28 * points == size))
                multi_grid_count = grids;
        }
    }
    if (!matches.empty()) return matches.front();
    if (multi_grid_count > 0)
        throw InputError(path, "this is a multi-grid PLOT3D file (" + std::to_string(multi_grid_count) +
                                   " grids); uvr reads single-grid files only");

    // Explain with the reading most likely intended: the byte order whose header gives positive dimensions.
    auto positive = [](const Dims& d) { return d[0] > 0 && d[1] > 0 && d[2] > 0; };
    bool be = preferred_big_endian;
    Dims dims = dims_at(data, 0, be);
    if (!positive(dims) && positive(dims_at(data, 0, !be))) {
        be = !be;
        dims = dims_at(data, 0, be);
    }
    if (!positive(dims))
        throw InputError(path, "not a PLOT3D grid file: the header's dimensions " + dims_text(dims) +
                                   " are not positive in either byte order");
    long double n = static_cast<long double>(dims[0]) * dims[1] * dims[2];
    char need[160];
    std::snprintf(need, sizeof need, "%.0Lf bytes (single precision), %.0Lf (with iblank) or %.0Lf (double precision)",
                  12 + 12 * n, 12 + 16 * n, 12 + 24 * n);
    throw InputError(path, "truncated or not a PLOT3D whole-file grid: the header gives a " + dims_text(dims) +
                               " grid (" + (be ? "big" : "little") + "-endian), which needs " + need +
                               ", but the file holds " + std::to_string(size) + " bytes");
}

template <class T>
void read_reals(BinaryCursor& cur, uint64_t n, std::vector<double>& out, const char* what)
{
    std::vector<T> raw;
    cur.read_array(n, raw, what);
    out.assign(raw.begin(), raw.end());
}

void read_reals(BinaryCursor& cur, int precision, uint64_t n, std::vector<double>& out, const char* what)
{
    if (precision == 4)
        read_reals<float>(cur, n, out, what);
    else
        read_reals<double>(cur, n, out, what);
}

StructuredGrid read_grid(const std::string& path, GridLayout& layout)
{
    bool big_endian = true;
    std::string data = read_unwrapped(path, big_endian);
    layout = detect_grid_layout(data, path, big_endian);

    BinaryCursor cur(data, path, layout.big_endian);
    cur.skip(layout.grid_count ? 16 : 12, "header");
    const uint64_t n = uint64_t(layout.dims[0]) * layout.dims[1] * layout.dims[2];
    StructuredGrid grid;
    grid.source = path;
    grid.dims = layout.dims;
    grid.points.resize(n);
    std::vector<double> coord;
    const char* names[3] = {"x coordinates", "y coordinates", "z coordinates"};
    for (int axis = 0; axis < 3; ++axis) {
        read_reals(cur, layout.precision, n, coord, names[axis]);
        for (uint64_t p = 0; p < n; ++p) grid.points[p][axis] = coord[p];
    }
    if (layout.iblank) cur.read_array(n, grid.iblank, "iblank");
    return grid;
}

// Reads the Q file's header and returns the byte offset of its reference values. The header may be in either form
// (with or without grid count) and byte order, independently of the XYZ file, but must give the same dimensions.
uint64_t q_header(const std::string& data, const std::string& q_path, const std::string& xyz_path,
                  const GridLayout& grid, bool& big_endian)
{
    if (data.size() < 12)
        throw InputError(q_path,
                         "truncated: " + std::to_string(data.size()) + " bytes is too short for a PLOT3D header");
    for (bool be : {grid.big_endian, !grid.big_endian}) {
        if (dims_at(data, 0, be) == grid.dims) {
            big_endian = be;
            return 12;
        }
        if (data.size() >= 16 && int_at(data, 0, be) == 1 && dims_at(data, 4, be) == grid.dims) {
            big_endian = be;
            return 16;
        }
    }
    uint64_t at = grid.grid_count && data.size() >= 16 ? 4 : 0;
    Dims q_dims = dims_at(data, at, grid.big_endian);
    throw InputError(q_path, "the Q file's grid " + dims_text(q_dims) + " does not match the " + dims_text(grid.dims) +
                                 " grid of XYZ file " + xyz_path);
}

void read_q(const std::string& q_path, const std::string& xyz_path, const GridLayout& grid, StructuredGrid& out,
            std::vector<std::string>& warnings)
{
    bool big_endian = grid.big_endian;
    std::string data = read_unwrapped(q_path, big_endian);
    uint64_t header = q_header(data, q_path, xyz_path, grid, big_endian);

    const uint64_t n = uint64_t(grid.dims[0]) * grid.dims[1] * grid.dims[2];
    const uint64_t body = data.size() - header;
    auto need = [&](int precision) { return uint64_t(precision) * (4 + 5 * n); };
    int precision = grid.precision;
    const int other_precision = precision == 4 ? 8 : 4;
    if (body != need(precision) && body == need(other_precision)) precision = other_precision;
    if (body < need(precision))
        throw InputError(q_path, "truncated: the Q data of a " + dims_text(grid.dims) + " grid needs " +
                                     std::to_string(need(precision)) + " bytes after the header, but the file holds " +
                                     std::to_string(body));

    BinaryCursor cur(data, q_path, big_endian);
    cur.skip(header + 4 * uint64_t(precision), "reference values (Mach, alpha, Reynolds number, time)");
    for (const char* name : kQNames) {
        ScalarField field{name, {}};
        read_reals(cur, precision, n, field.values, name);
        out.point_fields.push_back(std::move(field));
    }
    std::string_view rest = cur.rest();
    // Some writers pad the file (Blunt Fin's Q file ends in 484 zero bytes); padding is harmless, anything else is not
    // understood and the user should know it was skipped.
    if (rest.find_first_not_of('\0') != std::string_view::npos)
        warnings.push_back(q_path + ": ignored " + std::to_string(rest.size()) +
                           " bytes after the five Q variables (not all zero: the file may hold more than uvr reads)");
}

}  // namespace

Dataset read_plot3d(const std::string& xyz_path, const std::string& q_path, bool cell_census)
{
    GridLayout layout;
    StructuredGrid grid = read_grid(xyz_path, layout);
    Dataset result;
    if (!q_path.empty()) read_q(q_path, xyz_path, layout, grid, result.warnings);
    nlohmann::json info = {{"format", "PLOT3D"}, {"dims", grid.dims}};
    if (cell_census) {
        const HexahedronCensus census = hexahedron_census(grid);
        info["hexahedra"] = census.hexahedra;
        info["collapsed_hexahedra"] = census.collapsed;
        info["folded_hexahedra"] = census.folded;
    }
    result.info_json = info.dump();
    result.mesh = tetrahedralize_structured(grid);
    result.mesh->source = xyz_path;
    return result;
}

}  // namespace uvr
