// Loading any supported file: the one entry point the `uvr` program and the tests use.
//
// The format is chosen by the file's extension (SPEC §3): .vtk, .vtu, .vti, .node/.ele, .off, PLOT3D (.bin/.xyz/.x/.q
// with --q), .nrrd/.nhdr, .mhd/.mha, .slc, .raw (with --dims/--dtype).
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "reference/mesh.h"
#include "reference/volume.h"

namespace uvr {

struct LoadOptions {
    std::string q_file;                               // PLOT3D solution (Q) file; fields come from it
    std::optional<std::array<int64_t, 3>> raw_dims;   // raw volumes: sizes, x fastest
    std::string raw_dtype = "uint8";                  // raw volumes: voxel type (parse_voxel_type names)
    bool raw_big_endian = false;
};

// A file holds either a tetrahedral mesh or a regular grid. Warnings are things the user should hear about but that do
// not stop the load (skipped 2D cells, ignored cell data, re-oriented tetrahedra).
struct Dataset {
    std::optional<TetMesh> mesh;
    std::optional<Volume> volume;
    std::vector<std::string> warnings;
};

Dataset load_dataset(const std::string& path, const LoadOptions& options = {});

// The readers, one per format (read_*.cpp). Each throws InputError naming the file (and line, for text) on bad input,
// and returns finalized data (finalize_mesh / finalize_volume applied).
Dataset read_vtk_legacy(const std::string& path);         // UNSTRUCTURED_GRID, STRUCTURED_POINTS; ASCII and BINARY
Dataset read_vtk_xml(const std::string& path);            // .vtu UnstructuredGrid, .vti ImageData
Dataset read_tetgen(const std::string& path);             // .node + .ele (either name given)
Dataset read_off(const std::string& path);                // tetrahedral OFF
Dataset read_plot3d(const std::string& xyz_path, const std::string& q_path);
Dataset read_nrrd(const std::string& path);               // .nrrd and .nhdr (raw and gzip, attached and detached)
Dataset read_metaimage(const std::string& path);          // .mhd/.mha
Dataset read_slc(const std::string& path);                // SLC (magic 11111), raw and RLE slices
Dataset read_raw_volume(const std::string& path, const std::array<int64_t, 3>& dims, const std::string& dtype,
                        bool big_endian);

}  // namespace uvr
