// What every rendering command sets up the same way: the data, the field, the transfer function, the camera, the size.
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "reference/dataset.h"
#include "reference/camera.h"
#include "reference/topology.h"
#include "reference/transfer_function.h"

namespace uvr::cli {

struct InputOptions {
    std::string path;
    std::string q_file;
    std::string dims;  // "X,Y,Z" for raw volumes
    std::string dtype = "uint8";
    bool big_endian = false;
    std::string field;
    std::string time_step = "last";  // Exodus II: --time INDEX|last
};

// Loads the input; throws InputError naming the file for anything wrong (an unknown --field included). `cell_census`:
// what uvr info adds (LoadOptions::cell_census).
Dataset load_input(const InputOptions& in, bool cell_census = false);
void print_warnings(const Dataset& d);  // the data's warnings on stderr, one line each

struct SceneOptions {
    InputOptions input;
    std::string tf_path;
    std::string camera_path;
    std::string view;              // "AZ,EL" in degrees
    std::string size = "512x512";
    // Given as values rather than files (the Python module): they replace --tf and --camera.
    std::optional<TransferFunction> tf;
    std::optional<Camera> camera;
};

// The whole data's bounds, field range and longest edge, where `data` holds a part of it (a rank's pieces, a sort-last
// part): the default camera and transfer function are then the whole's, as one process reading everything sets them,
// and HAVS's and VICP's tables span the whole's range and longest edge on every part.
struct SceneExtent {
    Bounds bounds;
    Range range;
    double longest_edge = 0.0;
};

struct Scene {
    Dataset data;
    std::size_t field = 0;
    TransferFunction tf;
    Camera camera;
    int width = 0, height = 0;
    std::unique_ptr<MeshTopology> topology;  // meshes only
    std::optional<SceneExtent> whole;        // set where the mesh is a part of a larger one
    bool is_volume() const { return data.volume.has_value(); }
    // The tetrahedral mesh; throws InputError for a regular grid (what needs a mesh refuses a volume cleanly).
    const TetMesh& mesh() const;
    const Volume& volume() const { return *data.volume; }  // is_volume() only
    std::string field_name() const;
};

// Loads and validates everything; throws InputError for anything wrong (a --camera and a --view together, say).
Scene setup_scene(const SceneOptions& o);
// The same on data already loaded (o.input names only the field; its path is not read).
Scene setup_scene(Dataset data, const SceneOptions& o);
Scene setup_scene(Dataset data, const SceneOptions& o, const SceneExtent& whole);

}  // namespace uvr::cli
