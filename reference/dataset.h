// Loading any supported file: the one entry point the `uvr` program and the tests use.
//
// The format is chosen by the file's extension (docs/spec.md §3): .vtk, .vtu, .vti, .node/.ele, .off, PLOT3D
// (.bin/.xyz/.x/.q with --q), .nrrd/.nhdr, .mhd/.mha, .slc, .raw (with --dims/--dtype), Exodus II (.exo/.e/.ex2, and .g
// when the file is netCDF or HDF5; a .g file of other bytes is a PLOT3D grid).
#pragma once

#include <array>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "reference/mesh.h"
#include "reference/volume.h"

namespace uvr {

struct LoadOptions {
    std::string q_file;                               // PLOT3D solution (Q) file; fields come from it
    std::optional<std::array<int64_t, 3>> raw_dims;   // raw volumes: sizes, x fastest
    std::string raw_dtype = "uint8";                  // raw volumes: voxel type (parse_voxel_type names)
    bool raw_big_endian = false;
    std::string time_step = "last";                   // Exodus II: the time step's index (from 1), or "last"
    bool cell_census = false;  // PLOT3D: count the grid's collapsed and folded hexahedra (uvr info; a pass over the cells)
};

// The whole mesh's extent as a .pvtu that `uvr partition` wrote records it (docs/distributed.md): its pieces' bounds,
// longest edge of a tetrahedron that is not flat, and each field's range, joined, so that a rank reading only its
// pieces knows them without waiting for the other ranks.
struct WholeExtent {
    Bounds bounds;
    double longest_edge = 0.0;
    std::vector<std::pair<std::string, Range>> ranges;  // per field, by name
};
// The names of the FieldData arrays that record a WholeExtent in a .pvtu (write_pvtu writes them, read_pvtu reads
// them); a field's range is named kWholeRangePrefix followed by the field's name.
inline constexpr const char* kWholeBoundsArray = "uvr whole bounds";
inline constexpr const char* kWholeLongestEdgeArray = "uvr whole longest edge";
inline constexpr const char* kWholeRangePrefix = "uvr whole range: ";

// A file holds either a tetrahedral mesh or a regular grid. Warnings are things the user should hear about but that do
// not stop the load (skipped 2D cells, ignored cell data, re-oriented tetrahedra).
struct Dataset {
    std::optional<TetMesh> mesh;
    std::optional<Volume> volume;
    std::vector<std::string> warnings;
    // What a format says of itself beyond the mesh, for `uvr info` (Exodus II: its blocks, sets, variables, times), as
    // the text of a JSON object; empty when the format says nothing more.
    std::string info_json;
    // A file of pieces (.pvtu): per tetrahedron, the index of the piece it came from; empty for every other file.
    std::vector<uint32_t> piece_of_cell;
    // A .pvtu that records the whole mesh's extent: what it records (read_pvtu); empty for every other file.
    std::optional<WholeExtent> whole;
};

Dataset load_dataset(const std::string& path, const LoadOptions& options = {});

// The readers, one per format (read_*.cpp). Each throws InputError naming the file (and line, for text) on bad input,
// and returns finalized data (finalize_mesh / finalize_volume applied).
Dataset read_vtk_legacy(const std::string& path);         // UNSTRUCTURED_GRID, STRUCTURED_POINTS; ASCII and BINARY
Dataset read_vtk_xml(const std::string& path);            // .vtu UnstructuredGrid, .vti ImageData
// .pvtu PUnstructuredGrid: its pieces (.vtu, relative to its directory) joined into one mesh, in piece order, with
// Dataset::piece_of_cell; every piece must hold the same fields.
Dataset read_pvtu(const std::string& path);
// The pieces dealt to `rank` of `ranks` (contiguous, as even as the counts allow: rank r reads pieces
// [r P / ranks, (r + 1) P / ranks) of P), joined; piece_of_cell holds their indices in the whole file. Throws
// InputError naming the file when it has fewer pieces than ranks, and naming the piece that is missing or bad. The
// whole's extent comes from the file's FieldData when it records one (write_pvtu), malformed records refused.
Dataset read_pvtu(const std::string& path, std::size_t rank, std::size_t ranks);
// The whole's extent a .pvtu records, without reading its pieces; nothing when it records none.
std::optional<WholeExtent> read_pvtu_whole_extent(const std::string& path);
Dataset read_tetgen(const std::string& path);             // .node + .ele (either name given)
Dataset read_off(const std::string& path);                // tetrahedral OFF
Dataset read_plot3d(const std::string& xyz_path, const std::string& q_path, bool cell_census = false);
Dataset read_nrrd(const std::string& path);               // .nrrd and .nhdr (raw and gzip, attached and detached)
Dataset read_metaimage(const std::string& path);          // .mhd/.mha
Dataset read_slc(const std::string& path);                // SLC (magic 11111), raw and RLE slices
// Exodus II through libexodusii: element blocks of tetrahedra, hexahedra, wedges and pyramids; nodal variables as
// point fields, element variables as cell fields, at time step `time_step` (an index from 1, or "last").
Dataset read_exodus(const std::string& path, const std::string& time_step);
// Whether the file starts like an Exodus II file (netCDF classic or 64-bit, or HDF5).
bool looks_like_exodus(const std::string& path);
Dataset read_raw_volume(const std::string& path, const std::array<int64_t, 3>& dims, const std::string& dtype,
                        bool big_endian);

}  // namespace uvr
