// The Python module `uvr` (docs/python.md): scenes from files or NumPy arrays, any algorithm's image on any backend,
// the reference and docs/spec.md §4's measures, as NumPy arrays and dicts. A thin layer over bench/: the same registry,
// scene set-up and measures the `uvr` program uses, so a render here computes the program's bits.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "bench/algorithms.h"
#include "bench/budget.h"
#include "bench/verify.h"
#include "bench/scene.h"
#include "reference/camera.h"
#include "reference/error.h"
#include "reference/error_measures.h"
#include "reference/transfer_function.h"

namespace py = pybind11;

namespace {

using uvr::InputError;
using uvr::cli::AlgoOptions;

// A mesh or volume made from arrays (uvr.mesh, uvr.volume), not yet a scene.
struct Data {
    uvr::Dataset dataset;
};

// A scene: data, field, transfer function, camera and size, set up as the program's scene options set it up.
struct PyScene {
    std::unique_ptr<uvr::cli::Scene> scene;
    std::optional<uvr::cli::SceneOptions> options;  // a scene made from a file or builtin:NAME: how to make it again
};

std::string json_text(const py::handle& value)
{
    return py::module_::import("json").attr("dumps")(value).cast<std::string>();
}

py::object json_value(const std::string& text) { return py::module_::import("json").attr("loads")(text); }

// The image's floats handed to NumPy without a copy: the array owns the vector through a capsule.
py::array_t<float> image_array(uvr::Image&& image)
{
    auto* owner = new std::vector<float>(std::move(image.rgba));
    py::capsule release(owner, [](void* p) { delete static_cast<std::vector<float>*>(p); });
    const py::ssize_t w = image.width, h = image.height, f = sizeof(float);
    return py::array_t<float>({h, w, py::ssize_t(4)}, {w * 4 * f, 4 * f, f}, owner->data(), release);
}

// An H x W x 4 (or x 3: colour only) float32 array seen as an image. A C-contiguous float32 array is used where it
// lies; anything else is converted once (NumPy's own rules), which is the only copy.
struct ArrayImage {
    py::array_t<float, py::array::c_style | py::array::forcecast> array;
    uvr::Image widened;  // an H x W x 3 array, given alpha 1 (colour only)
    uvr::ImageView view;
    int channels = 4;
};

ArrayImage array_image(const py::handle& value, const char* what)
{
    ArrayImage a;
    a.array = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(value);
    if (!a.array) throw InputError("", std::string(what) + " is not an array of numbers");
    if (a.array.ndim() != 3 || (a.array.shape(2) != 4 && a.array.shape(2) != 3) || a.array.shape(0) < 1 ||
        a.array.shape(1) < 1)
        throw InputError("", std::string(what) + " must be an H x W x 4 (or H x W x 3) array, found shape " +
                                 py::str(py::getattr(a.array, "shape")).cast<std::string>());
    const int h = int(a.array.shape(0)), w = int(a.array.shape(1));
    if (a.array.shape(2) == 4) {
        a.view = uvr::ImageView(w, h, a.array.data());
        return a;
    }
    a.channels = 3;
    a.widened = uvr::Image(w, h);
    const float* src = a.array.data();
    for (std::size_t p = 0; p < std::size_t(w) * std::size_t(h); ++p) {
        for (int c = 0; c < 3; ++c) a.widened.rgba[4 * p + c] = src[3 * p + c];
        a.widened.rgba[4 * p + 3] = 1.0f;
    }
    a.view = uvr::ImageView(a.widened);
    return a;
}

// uvr's messages name the program's options (--table-size, --algos); a Python caller passes keywords (table_size)
// and the algorithm as render()'s second argument (algo).
std::string python_names(const std::string& message)
{
    std::string out;
    for (std::size_t i = 0; i < message.size();) {
        const bool option = message.compare(i, 2, "--") == 0 && i + 2 < message.size() &&
                            std::islower(static_cast<unsigned char>(message[i + 2])) &&
                            (i == 0 || !std::isalnum(static_cast<unsigned char>(message[i - 1])));
        if (!option) {
            out += message[i++];
            continue;
        }
        std::size_t j = i + 2;
        std::string name;
        for (; j < message.size() && (std::isalnum(static_cast<unsigned char>(message[j])) || message[j] == '-'); ++j)
            name += message[j] == '-' ? '_' : message[j];
        out += name == "algos" ? "algo" : name;
        i = j;
    }
    return out;
}

// Keyword options of render() and budget(): one per row of the algorithm options' table (bench/algo_options.h), its
// name with '_' for '-' (--table-size: table_size). A value is handed to the row's parser as the program's text would
// be: a number as Python writes it (repr: the same double back), a bool as true/false.
std::string option_text(const uvr::cli::AlgoOption& row, const py::handle& v)
{
    if (row.flag) {
        if (!py::isinstance<py::bool_>(v)) throw py::cast_error();
        return v.cast<bool>() != row.python_inverted ? "true" : "false";
    }
    if (py::isinstance<py::bool_>(v)) throw py::cast_error();  // True is not a number of anything
    if (py::isinstance<py::str>(v)) return v.cast<std::string>();
    if (py::isinstance<py::int_>(v) || py::isinstance<py::float_>(v)) return py::repr(v).cast<std::string>();
    throw py::cast_error();
}

AlgoOptions algo_options(const py::kwargs& kwargs)
{
    const auto& table = uvr::cli::algo_option_table();
    AlgoOptions o;
    for (const auto& item : kwargs) {
        const std::string key = item.first.cast<std::string>();
        const auto row = std::find_if(table.begin(), table.end(), [&](const uvr::cli::AlgoOption& r) {
            return uvr::cli::python_keyword(r) == key;
        });
        if (row == table.end()) {
            std::string known;
            for (const auto& r : table) known += (known.empty() ? "" : ", ") + uvr::cli::python_keyword(r);
            throw InputError("", "unknown option '" + key + "' (" + known + ")");
        }
        std::string text;
        try {
            text = option_text(*row, item.second);
        } catch (const py::cast_error&) {
            throw InputError("", "option '" + key +
                                     "' has the wrong type: " + py::str(py::type::of(item.second)).cast<std::string>());
        }
        row->set(o, text);
    }
    return o;
}

py::dict measures_dict(const uvr::ErrorMeasures& e)
{
    py::dict d;
    d["rmse"] = e.rmse;
    d["max_abs"] = e.max_abs;
    d["psnr"] = e.psnr;  // +inf for identical images, as Python's float has it
    d["visible_fraction"] = e.visible_fraction;
    d["covered_left_empty"] = e.covered_left_empty;
    return d;
}

// One array (named `name`), a dict of name -> array, or None.
std::vector<std::pair<std::string, py::handle>> named_arrays(const py::handle& in, const std::string& name)
{
    std::vector<std::pair<std::string, py::handle>> out;
    if (in.is_none()) return out;
    if (py::isinstance<py::dict>(in))
        for (const auto& item : in.cast<py::dict>()) out.emplace_back(py::str(item.first), item.second);
    else
        out.emplace_back(name, in);
    return out;
}

// Repeats every point per tetrahedron (point 4 t + k is tetrahedron t's vertex k), carrying the point fields along:
// what per-cell vertex values need, each tetrahedron keeping its own four values.
void repeat_points_per_cell(uvr::TetMesh& mesh)
{
    std::vector<glm::dvec3> points;
    points.reserve(4 * mesh.tets.size());
    std::vector<std::vector<double>> values(mesh.fields.size());
    for (uvr::Tet& t : mesh.tets)
        for (uint32_t& v : t) {
            for (std::size_t f = 0; f < mesh.fields.size(); ++f) values[f].push_back(mesh.fields[f].values[v]);
            points.push_back(mesh.points[v]);
            v = uint32_t(points.size() - 1);
        }
    mesh.points = std::move(points);
    for (std::size_t f = 0; f < mesh.fields.size(); ++f) mesh.fields[f].values = std::move(values[f]);
}

// Point fields (length N), per-cell vertex fields (M x 4: each tetrahedron's values at its vertices, in its vertex
// order) and cell fields (length M). Per-cell vertex values repeat the points per tetrahedron.
void add_mesh_fields(uvr::TetMesh& mesh, const std::vector<std::pair<std::string, py::handle>>& scalars,
                     const std::vector<std::pair<std::string, py::handle>>& cell_scalars)
{
    using F64 = py::array_t<double, py::array::c_style | py::array::forcecast>;
    if (scalars.empty() && cell_scalars.empty()) throw InputError("arrays", "no scalar field given");
    std::vector<std::pair<std::string, F64>> per_vertex;
    for (const auto& [field_name, values_in] : scalars) {
        const F64 values = F64::ensure(values_in);
        if (values && values.ndim() == 2 && values.shape(1) == 4) {
            per_vertex.emplace_back(field_name, values);
            continue;
        }
        if (!values || values.ndim() != 1)
            throw InputError("arrays", "scalars '" + field_name + "' must be a one-dimensional array of numbers (one "
                                       "per point) or an M x 4 array (each tetrahedron's values at its vertices)");
        mesh.fields.push_back({field_name, std::vector<double>(values.data(), values.data() + values.size())});
    }
    if (!per_vertex.empty()) {
        for (const auto& f : mesh.fields)  // lengths are checked before the points are repeated
            if (f.values.size() != mesh.points.size())
                throw InputError("arrays", "field '" + f.name + "' has " + std::to_string(f.values.size()) +
                                               " values for " + std::to_string(mesh.points.size()) + " points");
        repeat_points_per_cell(mesh);
    }
    for (const auto& [field_name, values] : per_vertex) {
        if (std::size_t(values.shape(0)) != mesh.tets.size())
            throw InputError("arrays", "scalars '" + field_name + "' has " + std::to_string(values.shape(0)) +
                                           " rows for " + std::to_string(mesh.tets.size()) + " tetrahedra");
        mesh.fields.push_back({field_name, std::vector<double>(values.data(), values.data() + values.size())});
    }
    for (const auto& [field_name, values_in] : cell_scalars) {
        const F64 values = F64::ensure(values_in);
        if (!values || values.ndim() != 1)
            throw InputError("arrays", "cell_scalars '" + field_name + "' must be a one-dimensional array of numbers "
                                       "(one per tetrahedron)");
        mesh.fields.push_back({field_name, std::vector<double>(values.data(), values.data() + values.size()),
                               uvr::FieldAssociation::cell});
    }
}

Data make_mesh(const py::handle& points_in, const py::handle& tets_in, const py::handle& scalars_in,
               const std::string& name, const py::handle& cell_scalars_in)
{
    using F64 = py::array_t<double, py::array::c_style | py::array::forcecast>;
    const F64 points = F64::ensure(points_in);
    if (!points || points.ndim() != 2 || points.shape(1) != 3)
        throw InputError("arrays", "points must be an N x 3 array of numbers");
    const py::array tets_any = py::array::ensure(tets_in);
    if (!tets_any || tets_any.ndim() != 2 || tets_any.shape(1) != 4 ||
        (tets_any.size() > 0 && tets_any.dtype().kind() != 'i' && tets_any.dtype().kind() != 'u'))
        throw InputError("arrays", "tetrahedra must be an M x 4 array of integers (point indices)");
    using I64 = py::array_t<int64_t, py::array::c_style | py::array::forcecast>;
    const I64 tets = I64::ensure(tets_any);
    uvr::TetMesh mesh;
    mesh.source = "arrays";
    mesh.points.resize(std::size_t(points.shape(0)));
    const double* p = points.data();
    for (std::size_t i = 0; i < mesh.points.size(); ++i) mesh.points[i] = {p[3 * i], p[3 * i + 1], p[3 * i + 2]};
    mesh.tets.resize(std::size_t(tets.shape(0)));
    const int64_t* t = tets.data();
    for (std::size_t i = 0; i < mesh.tets.size(); ++i)
        for (int c = 0; c < 4; ++c) {
            const int64_t v = t[4 * i + std::size_t(c)];
            if (v < 0 || v >= int64_t(mesh.points.size()))
                throw InputError("arrays", "tetrahedron " + std::to_string(i) + " names point " + std::to_string(v) +
                                               ", out of range (" + std::to_string(mesh.points.size()) + " points)");
            mesh.tets[i][std::size_t(c)] = uint32_t(v);
        }
    add_mesh_fields(mesh, named_arrays(scalars_in, name), named_arrays(cell_scalars_in, "cell_scalars"));
    Data d;
    const std::size_t reoriented = uvr::finalize_mesh(mesh);  // lengths, indices, finiteness, volumes
    if (reoriented)
        d.dataset.warnings.push_back("arrays: " + std::to_string(reoriented) +
                                     " inverted tetrahedra re-oriented (vertices 2 and 3 swapped)");
    d.dataset.mesh = std::move(mesh);
    return d;
}

Data make_volume(const py::handle& values_in, std::vector<double> spacing, std::vector<double> origin,
                 const std::string& name)
{
    using F32 = py::array_t<float, py::array::c_style | py::array::forcecast>;
    const F32 values = F32::ensure(values_in);
    if (!values || values.ndim() != 3)
        throw InputError("arrays", "volume values must be a Z x Y x X array of numbers (x fastest, as NumPy's C order)");
    if (spacing.size() != 3 || origin.size() != 3)
        throw InputError("arrays", "spacing and origin take three numbers (x, y, z)");
    uvr::Volume v;
    v.source = "arrays";
    v.name = name;
    v.dims = {values.shape(2), values.shape(1), values.shape(0)};
    v.spacing = {spacing[0], spacing[1], spacing[2]};
    v.origin = {origin[0], origin[1], origin[2]};
    v.type = uvr::VoxelType::f32;
    v.values.assign(values.data(), values.data() + values.size());
    uvr::finalize_volume(v);
    Data d;
    d.dataset.volume = std::move(v);
    return d;
}

PyScene make_scene(const py::object& source, const std::string& field, const std::string& q, const py::object& dims,
                   const std::string& dtype, bool big_endian, const py::object& tf, const py::object& camera,
                   const py::object& view, const py::object& size, const std::string& time_step)
{
    uvr::cli::SceneOptions o;
    o.input.field = field;
    o.input.time_step = time_step;
    o.input.q_file = q;
    o.input.dtype = dtype;
    o.input.big_endian = big_endian;
    if (!dims.is_none()) {
        const auto d = dims.cast<std::vector<long long>>();
        if (d.size() != 3) throw InputError("", "dims takes three sizes (x, y, z)");
        o.input.dims = std::to_string(d[0]) + "," + std::to_string(d[1]) + "," + std::to_string(d[2]);
    }
    const auto wh = size.cast<std::vector<int>>();
    if (wh.size() != 2) throw InputError("", "size takes (width, height)");
    o.size = std::to_string(wh[0]) + "x" + std::to_string(wh[1]);
    if (!view.is_none()) {
        const auto ae = view.cast<std::vector<double>>();
        if (ae.size() != 2) throw InputError("", "view takes (azimuth, elevation) in degrees");
        char text[64];
        std::snprintf(text, sizeof text, "%.17g,%.17g", ae[0], ae[1]);
        o.view = text;
    }
    if (py::isinstance<py::str>(tf)) o.tf_path = tf.cast<std::string>();  // a file, or preset:NAME
    else if (!tf.is_none()) o.tf = uvr::parse_transfer_function(json_text(tf), "tf (dict)");
    if (py::isinstance<py::str>(camera)) o.camera_path = camera.cast<std::string>();
    else if (!camera.is_none()) o.camera = uvr::parse_camera(json_text(camera), "camera (dict)");
    PyScene s;
    if (py::isinstance<py::str>(source)) {
        o.input.path = source.cast<std::string>();
        s.scene = std::make_unique<uvr::cli::Scene>(uvr::cli::setup_scene(o));
        s.options = o;
    } else if (py::isinstance<Data>(source)) {
        s.scene = std::make_unique<uvr::cli::Scene>(uvr::cli::setup_scene(source.cast<const Data&>().dataset, o));
    } else {
        throw InputError("", "a scene's source is a file name (or builtin:NAME) or what uvr.mesh / uvr.volume made");
    }
    return s;
}

uvr::cli::AlgoResult run(const PyScene& s, const std::string& algo, const AlgoOptions& o)
{
    uvr::cli::run_algorithm_check(algo);
    py::gil_scoped_release free_python;  // the render runs on uvr's threads; Python may go on meanwhile
    return uvr::cli::run_algorithm(*s.scene, algo, o);
}

// uvr.Error and the translation of uvr's errors into it.
void bind_errors(py::module_& m)
{
    // Every error uvr reports (a file, an option, an array) arrives as uvr.Error, a ValueError, with uvr's message,
    // its options named as Python passes them (python_names).
    static py::exception<InputError> error(m, "Error", PyExc_ValueError);
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const InputError& e) {
            error(python_names(e.what()).c_str());
        }
    });
}

// uvr.Data and the functions that make it from arrays: mesh, volume.
void bind_data(py::module_& m)
{
    py::class_<Data>(m, "Data", "A mesh or volume made from arrays; hand it to uvr.Scene");

    m.def("mesh", &make_mesh, py::arg("points"), py::arg("tetrahedra"), py::arg("scalars") = py::none(),
          py::arg("name") = "scalars", py::arg("cell_scalars") = py::none(),
          "A tetrahedral mesh from arrays: points N x 3, tetrahedra M x 4 (point indices); scalars of length N (point "
          "data) or M x 4 (each tetrahedron's own values at its vertices: per-cell vertex data), or a dict name -> "
          "array for several fields; cell_scalars of length M (one value per tetrahedron), or a dict. Checked as a "
          "file's mesh is: indices, finiteness, volumes.");
    m.def("volume", &make_volume, py::arg("values"), py::arg("spacing") = std::vector<double>{1.0, 1.0, 1.0},
          py::arg("origin") = std::vector<double>{0.0, 0.0, 0.0}, py::arg("name") = "scalars",
          "A regular grid from a Z x Y x X array (x fastest: NumPy's C order), with spacing and origin (x, y, z).");
}

// uvr.Scene and its read-only properties.
void bind_scene(py::module_& m)
{
    py::class_<PyScene>(m, "Scene", "Data, field, transfer function, camera and size: what every render takes")
        .def(py::init(&make_scene), py::arg("source"), py::kw_only(), py::arg("field") = "", py::arg("q") = "",
             py::arg("dims") = py::none(), py::arg("dtype") = "uint8", py::arg("big_endian") = false,
             py::arg("tf") = py::none(), py::arg("camera") = py::none(), py::arg("view") = py::none(),
             py::arg("size") = std::vector<int>{512, 512}, py::arg("time") = "last",
             "source: a file (any format uvr reads, builtin:torus, ...) or uvr.mesh / uvr.volume's data. tf and "
             "camera: dicts in the JSON of the files (docs/spec.md §1, §2), or a file name, or tf='preset:NAME'. view: "
             "(azimuth, elevation) orbiting the default camera. size: (width, height). time: an Exodus II file's "
             "time step, an index from 1 or 'last'.")
        .def_property_readonly("width", [](const PyScene& s) { return s.scene->width; })
        .def_property_readonly("height", [](const PyScene& s) { return s.scene->height; })
        .def_property_readonly("kind", [](const PyScene& s) { return s.scene->is_volume() ? "volume" : "mesh"; })
        .def_property_readonly("field", [](const PyScene& s) { return s.scene->field_name(); })
        .def_property_readonly("camera", [](const PyScene& s) { return json_value(uvr::camera_json(s.scene->camera)); })
        .def_property_readonly("tf",
                               [](const PyScene& s) { return json_value(uvr::transfer_function_json(s.scene->tf)); })
        .def_property_readonly("tetrahedra",
                               [](const PyScene& s) { return s.scene->is_volume() ? 0 : s.scene->mesh().tets.size(); });
}

// The renders: render (any algorithm) and reference.
void bind_render(py::module_& m)
{
    m.def(
        "render",
        [](const PyScene& s, const std::string& algo, bool with_stats, const py::kwargs& kwargs) -> py::object {
            uvr::cli::AlgoResult r = run(s, algo, algo_options(kwargs));
            py::array_t<float> image = image_array(std::move(r.image));
            if (!with_stats) return image;
            py::dict stats;
            stats["ms"] = r.ms;
            stats["cached"] = r.cached;
            stats["stats"] = json_value(r.stats.dump());
            return py::make_tuple(image, stats);
        },
        py::arg("scene"), py::arg("algo") = "havs", py::kw_only(), py::arg("with_stats") = false,
        "The image of `algo` (reference, havs, vicp, raycast) as an H x W x 4 float32 array (premultiplied RGBA, "
        "row 0 on top), the bits `uvr render` writes. Options as the program's, '_' for '-': backend='gl', k=6, "
        "segment='exact', ... With with_stats=True: (image, {'ms', 'cached', 'stats'}).");
    m.def(
        "reference",
        [](const PyScene& s, bool cache) {
            AlgoOptions o;
            o.no_cache = !cache;
            return image_array(run(s, "reference", o).image);
        },
        py::arg("scene"), py::kw_only(), py::arg("cache") = true,
        "The exact reference image (cached on disk as the program caches it).");
}

// The measures: measure (an image against the reference) and budget (an algorithm's error budget).
void bind_measures(py::module_& m)
{
    m.def(
        "measure",
        [](const py::handle& image, const py::handle& reference) {
            const ArrayImage a = array_image(image, "image");
            const ArrayImage r = array_image(reference, "reference");
            if (r.channels != 4) throw InputError("", "the reference must be H x W x 4 (premultiplied RGBA)");
            return measures_dict(uvr::measure_errors(a.view, r.view, a.channels));
        },
        py::arg("image"), py::arg("reference"),
        "docs/spec.md §4's measures of an image against the reference: rmse, max_abs, psnr, visible_fraction (and "
        "covered_left_empty). An H x W x 3 image is colour only, compared with the reference's colour over black.");
    m.def(
        "budget",
        [](const PyScene& s, const std::string& algo, const std::string& report, const py::kwargs& kwargs) {
            const AlgoOptions o = algo_options(kwargs);
            std::string text;
            {
                py::gil_scoped_release free_python;
                const uvr::cli::Scene& sc = *s.scene;
                text = uvr::cli::run_budget(sc, algo, o, report, sc.is_volume() ? sc.volume().source : sc.mesh().source)
                           .dump();
            }
            return json_value(text);
        },
        py::arg("scene"), py::arg("algo"), py::kw_only(), py::arg("report"),
        "The error budget of `algo` (havs, vicp, raycast) as `uvr budget` computes it (docs/budget.md): the baseline "
        "with every switch exact, one run per factor, the total, each against the reference; writes the report to "
        "`report` and returns budget.json's object (a dict). Options as render's.");
    m.def(
        "verify",
        [](PyScene& s, const std::string& algo, const std::string& refine, int levels, double from, bool isolate,
           const py::kwargs& kwargs) {
            uvr::cli::VerifyRequest r{algo,    uvr::parse_choice("refine", uvr::cli::kRefinements, refine),
                                      levels,  from,
                                      isolate, algo_options(kwargs),
                                      ""};
            using uvr::cli::Refinement;
            if (r.refine == Refinement::mesh && !s.options)
                throw InputError("", "refine='mesh' refines builtin:grid-N: make the scene from that name");
            std::string text;
            if (r.refine == Refinement::size) {
                // The levels render the scene itself at larger sizes: no other Python thread may see it meanwhile.
                text = uvr::cli::verify_refinement(*s.scene, r).dump();
            } else {
                py::gil_scoped_release free_python;
                text = (r.refine == Refinement::mesh ? uvr::cli::verify_refinement(*s.options, r)
                                                     : uvr::cli::verify_refinement(*s.scene, r))
                           .dump();
            }
            return json_value(text);
        },
        py::arg("scene"), py::arg("algo"), py::arg("refine"), py::kw_only(), py::arg("levels") = 4,
        py::arg("start") = 0.0, py::arg("isolate") = false,
        "The observed order of accuracy as `uvr verify` computes it (docs/verification.md): `algo` rendered at "
        "`levels` refinements of `refine` (step, table, size, or mesh on a scene made from builtin:grid-N) from "
        "`start` (the program's --from; 0 the default), each against the reference (mesh: the analytic field's "
        "integral; size: the next level's box average); isolate=True sets every other switch exact. Returns the "
        "JSON's object (a dict). Options as render's.");
    m.def(
        "verify_images",
        [](const py::sequence& images, const std::vector<double>& h, const py::object& reference,
           const py::object& expected) {
            std::vector<uvr::Image> levels;
            int channels = 4;
            for (const py::handle& im : images) {
                const ArrayImage a = array_image(im, "images");
                channels = std::min(channels, a.channels);
                uvr::Image copy(a.view.width, a.view.height);
                std::copy(a.view.rgba, a.view.rgba + copy.rgba.size(), copy.rgba.begin());
                levels.push_back(std::move(copy));
            }
            std::optional<ArrayImage> ref;
            if (!reference.is_none()) ref = array_image(reference, "reference");
            uvr::Image ref_image;
            if (ref) {
                ref_image = uvr::Image(ref->view.width, ref->view.height);
                std::copy(ref->view.rgba, ref->view.rgba + ref_image.rgba.size(), ref_image.rgba.begin());
            }
            const double p = expected.is_none() ? std::numeric_limits<double>::quiet_NaN() : expected.cast<double>();
            return json_value(uvr::cli::verify_images(levels, h, ref ? &ref_image : nullptr, channels, p).dump());
        },
        py::arg("images"), py::arg("h"), py::kw_only(), py::arg("reference") = py::none(),
        py::arg("expected") = py::none(),
        "The observed order of an outside renderer's images at decreasing `h` (H x W x 4 or H x W x 3 arrays) against "
        "`reference`, or from their successive differences without one, as `uvr verify --images` computes it; "
        "`expected` gives the verdict. Returns a dict.");
}

// What uvr offers: algorithms and options.
void bind_catalogue(py::module_& m)
{
    m.def(
        "algorithms",
        [] {
            py::dict d;
            for (const auto& a : uvr::cli::algorithms()) d[py::str(a.name)] = a.backends;
            return d;
        },
        "Every algorithm's name and the backends it renders on.");
    m.def(
        "options",
        [] {
            py::dict d;
            for (const auto& r : uvr::cli::algo_option_table())
                d[py::str(uvr::cli::python_keyword(r))] = py::dict(
                    py::arg("option") = "--" + r.name, py::arg("help") = r.help, py::arg("default") = r.default_text,
                    py::arg("switch") = r.flag, py::arg("inverted") = r.python_inverted);
            return d;
        },
        "Every keyword option of render() and budget(): its program option (--table-size), help and default.");
}

}  // namespace

PYBIND11_MODULE(uvr, m)
{
    m.doc() = "uvr: how right GPU volume renderers of tetrahedral meshes are (docs/python.md)";
    m.attr("__version__") = "0.1";
    bind_errors(m);
    bind_data(m);
    bind_scene(m);
    bind_render(m);
    bind_measures(m);
    bind_catalogue(m);
}
