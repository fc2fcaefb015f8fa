#include "bench/scene.h"

#include <array>
#include <cstdint>
#include <cstdio>

#include <glm/geometric.hpp>

#include "reference/error.h"
#include "reference/image.h"

namespace uvr::cli {

Dataset load_input(const InputOptions& in, bool cell_census)
{
    LoadOptions lo;
    lo.cell_census = cell_census;
    lo.q_file = in.q_file;
    lo.raw_dtype = in.dtype;
    lo.raw_big_endian = in.big_endian;
    lo.time_step = in.time_step;
    if (!in.dims.empty()) {
        std::array<int64_t, 3> d{0, 0, 0};
        char c1 = 0, c2 = 0, extra = 0;
        long long x = 0, y = 0, z = 0;
        if (std::sscanf(in.dims.c_str(), "%lld%c%lld%c%lld%c", &x, &c1, &y, &c2, &z, &extra) != 5 || c1 != ',' ||
            c2 != ',' || x < 1 || y < 1 || z < 1)
            throw InputError("", "--dims must be X,Y,Z with positive integers, found '" + in.dims + "'");
        d = {x, y, z};
        lo.raw_dims = d;
    }
    Dataset d = load_dataset(in.path, lo);
    if (d.mesh && !in.field.empty()) find_field(*d.mesh, in.field);  // fail early on an unknown --field
    return d;
}

void print_warnings(const Dataset& d)
{
    for (const auto& w : d.warnings) std::fprintf(stderr, "uvr: warning: %s\n", w.c_str());
}

const TetMesh& Scene::mesh() const
{
    if (!data.mesh)
        throw InputError(data.volume->source,
                         "is a regular grid: this takes a tetrahedral mesh (on volumes, "
                         "--algo reference or raycast)");
    return *data.mesh;
}

std::string Scene::field_name() const { return data.mesh ? data.mesh->fields[field].name : data.volume->name; }

Scene setup_scene(const SceneOptions& o)
{
    int width = 0, height = 0;
    parse_size(o.size, width, height);  // a bad --size fails before the data is read
    return setup_scene(load_input(o.input), o);
}

namespace {

// The scene of `data`, with the whole's extent where `whole` is given.
Scene setup_with_extent(Dataset data, const SceneOptions& o, const SceneExtent* whole)
{
    Scene s;
    parse_size(o.size, s.width, s.height);
    s.data = std::move(data);
    print_warnings(s.data);
    Bounds b;
    Range range;
    if (s.data.mesh) {
        const TetMesh& mesh = *s.data.mesh;
        s.field = find_field(mesh, o.input.field);
        b = mesh_bounds(mesh);
        range = field_range(mesh.fields[s.field]);
    } else {
        if (!o.input.field.empty())
            throw InputError(s.data.volume->source, "is a regular grid with one scalar; --field is for meshes");
        b = volume_bounds(*s.data.volume);
        range = volume_range(*s.data.volume);
    }
    if (whole) {
        b = whole->bounds;
        range = whole->range;
        s.whole = *whole;
    }
    // The default: over a regular grid transparent around the histogram's dominant (background) value; --tf
    // preset:NAME puts one of ParaView's colour maps on the default's extinction.
    const bool preset = o.tf_path.rfind("preset:", 0) == 0;
    if (o.tf) {
        s.tf = *o.tf;
    } else if (o.tf_path.empty() || preset) {
        const double diagonal = glm::length(b.extent());
        s.tf = s.data.volume ? default_volume_transfer_function(s.data.volume->values, range, diagonal)
                             : default_transfer_function(range, diagonal);
        if (preset) s.tf = with_colour_preset(s.tf, range, o.tf_path.substr(7));
    } else {
        s.tf = load_transfer_function(o.tf_path);
    }
    const bool camera_given = !o.camera_path.empty() || o.camera;
    if (camera_given && !o.view.empty()) throw InputError("", "give either --camera or --view, not both");
    if (o.camera) {
        s.camera = *o.camera;
    } else if (!o.camera_path.empty()) {
        s.camera = load_camera(o.camera_path);
    } else {
        double az = 0.0, el = 0.0;
        char comma = 0, extra = 0;
        if (!o.view.empty() && (std::sscanf(o.view.c_str(), "%lf%c%lf%c", &az, &comma, &el, &extra) != 3 || comma != ','))
            throw InputError("", "--view must be AZIMUTH,ELEVATION in degrees, found '" + o.view + "'");
        s.camera = default_camera(b, double(s.width) / double(s.height), az, el);
    }
    if (s.data.mesh) s.topology = std::make_unique<MeshTopology>(build_topology(*s.data.mesh));
    return s;
}

}  // namespace

Scene setup_scene(Dataset data, const SceneOptions& o)
{
    return setup_with_extent(std::move(data), o, nullptr);
}

Scene setup_scene(Dataset data, const SceneOptions& o, const SceneExtent& whole)
{
    return setup_with_extent(std::move(data), o, &whole);
}

}  // namespace uvr::cli
