// Exodus II reader: files written here through the Exodus API (every element type, both nodal-variable layouts,
// netCDF-4), read back exactly, and bad input refused with a message naming the file.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <catch2/catch.hpp>
#include <exodusII.h>
#include <netcdf.h>
#include <nlohmann/json.hpp>

#include "reference/dataset.h"
#include "reference/error.h"
#include "reference/image.h"
#include "reference/topology.h"
#include "test_support.h"

namespace {

using uvr::test::file_contents;
using uvr::test::file_prefix;
using uvr::test::TempDir;

struct BlockSpec {
    int64_t id;
    std::string type, name;
    int nodes_per_element;
    std::vector<int> connectivity;  // 1-based node numbers, nodes_per_element per element
    int elements() const { return nodes_per_element ? int(connectivity.size()) / nodes_per_element : 0; }
};

// What write_exodus() puts in a file.
struct ExoSpec {
    int mode = EX_LARGE_MODEL;  // or EX_NORMAL_MODEL (all nodal variables in one array), EX_NETCDF4
    int num_dim = 3;
    std::string title = "uvr test";
    std::vector<glm::dvec3> points;
    std::vector<BlockSpec> blocks;
    std::vector<std::string> nodal_names, element_names;
    std::vector<double> times;
    std::function<double(int step, int var, int node)> nodal_value;
    std::function<double(int step, int var, int block, int element)> element_value;
    std::vector<int> truth;  // blocks x element variables; empty: every variable on every block
    bool sets = false;       // one node set ("inlet") and one unnamed side set (id 40)
};

std::vector<char*> c_strings(std::vector<std::string>& names)
{
    std::vector<char*> out;
    for (auto& n : names) out.push_back(n.data());
    return out;
}

void put_variables(int id, const ExoSpec& s)
{
    std::vector<std::string> nodal = s.nodal_names, element = s.element_names;
    if (!nodal.empty()) {
        REQUIRE(ex_put_variable_param(id, EX_NODAL, int(nodal.size())) >= 0);
        REQUIRE(ex_put_variable_names(id, EX_NODAL, int(nodal.size()), c_strings(nodal).data()) >= 0);
    }
    if (!element.empty()) {
        REQUIRE(ex_put_variable_param(id, EX_ELEM_BLOCK, int(element.size())) >= 0);
        REQUIRE(ex_put_variable_names(id, EX_ELEM_BLOCK, int(element.size()), c_strings(element).data()) >= 0);
        std::vector<int> truth = s.truth;
        if (truth.empty()) truth.assign(s.blocks.size() * element.size(), 1);
        REQUIRE(ex_put_truth_table(id, EX_ELEM_BLOCK, int(s.blocks.size()), int(element.size()), truth.data()) >= 0);
    }
    for (int step = 1; step <= int(s.times.size()); ++step) {
        REQUIRE(ex_put_time(id, step, &s.times[std::size_t(step - 1)]) >= 0);
        for (int v = 0; v < int(nodal.size()); ++v) {
            std::vector<double> values;
            for (int n = 0; n < int(s.points.size()); ++n) values.push_back(s.nodal_value(step, v, n));
            REQUIRE(ex_put_var(id, step, EX_NODAL, v + 1, 1, int64_t(values.size()), values.data()) >= 0);
        }
        for (int v = 0; v < int(element.size()); ++v)
            for (int b = 0; b < int(s.blocks.size()); ++b) {
                if (!s.truth.empty() && !s.truth[std::size_t(b) * element.size() + std::size_t(v)]) continue;
                std::vector<double> values;
                for (int e = 0; e < s.blocks[std::size_t(b)].elements(); ++e)
                    values.push_back(s.element_value(step, v, b, e));
                REQUIRE(ex_put_var(id, step, EX_ELEM_BLOCK, v + 1, s.blocks[std::size_t(b)].id,
                                   int64_t(values.size()), values.data()) >= 0);
            }
    }
}

void put_sets(int id)
{
    const int nodes[] = {1, 2, 3};
    REQUIRE(ex_put_set_param(id, EX_NODE_SET, 30, 3, 0) >= 0);
    REQUIRE(ex_put_set(id, EX_NODE_SET, 30, nodes, nullptr) >= 0);
    char inlet[] = "inlet";
    char* names[] = {inlet};
    REQUIRE(ex_put_names(id, EX_NODE_SET, names) >= 0);
    const int elements[] = {1}, sides[] = {1};
    REQUIRE(ex_put_set_param(id, EX_SIDE_SET, 40, 1, 0) >= 0);
    REQUIRE(ex_put_set(id, EX_SIDE_SET, 40, elements, sides) >= 0);
}

void write_exodus(const std::string& path, const ExoSpec& s)
{
    int cpu_word_size = sizeof(double), io_word_size = sizeof(double);
    const int id = ex_create(path.c_str(), EX_CLOBBER | s.mode, &cpu_word_size, &io_word_size);
    REQUIRE(id >= 0);
    int64_t elements = 0;
    for (const BlockSpec& b : s.blocks) elements += b.elements();
    REQUIRE(ex_put_init(id, s.title.c_str(), s.num_dim, int64_t(s.points.size()), elements,
                        int64_t(s.blocks.size()), s.sets ? 1 : 0, s.sets ? 1 : 0) >= 0);
    std::vector<double> x, y, z;
    for (const glm::dvec3& p : s.points) {
        x.push_back(p.x);
        y.push_back(p.y);
        z.push_back(p.z);
    }
    REQUIRE(ex_put_coord(id, x.data(), y.data(), s.num_dim == 3 ? z.data() : nullptr) >= 0);
    std::vector<std::string> names;
    for (const BlockSpec& b : s.blocks) {
        REQUIRE(ex_put_block(id, EX_ELEM_BLOCK, b.id, b.type.c_str(), b.elements(), b.nodes_per_element, 0, 0, 0) >=
                0);
        if (b.elements() > 0)
            REQUIRE(ex_put_conn(id, EX_ELEM_BLOCK, b.id, b.connectivity.data(), nullptr, nullptr) >= 0);
        names.push_back(b.name);
    }
    if (!names.empty()) REQUIRE(ex_put_names(id, EX_ELEM_BLOCK, c_strings(names).data()) >= 0);
    if (s.sets) put_sets(id);
    put_variables(id, s);
    REQUIRE(ex_close(id) >= 0);
}

// Adds `corners` (and `extra` further nodes, standing for mid-side nodes) to `s` as one element of a new block.
void add_element(ExoSpec& s, int64_t id, const std::string& type, const std::string& name,
                 const std::vector<glm::dvec3>& corners, int extra = 0)
{
    BlockSpec b{id, type, name, int(corners.size()) + extra, {}};
    for (const glm::dvec3& c : corners) {
        s.points.push_back(c);
        b.connectivity.push_back(int(s.points.size()));
    }
    for (int k = 0; k < extra; ++k) {  // mid-side nodes: somewhere off the element, so that using one shows
        s.points.push_back(corners[0] + glm::dvec3(0.5, 0.5, 7.0 + k));
        b.connectivity.push_back(int(s.points.size()));
    }
    s.blocks.push_back(b);
}

// Corner nodes in Exodus order, each element on its own around x = `x0`. Volumes: tetrahedron 1/6, hexahedron 1,
// wedge 1/2, pyramid 1/3.
std::vector<glm::dvec3> tetra(double x0) { return {{x0, 0, 0}, {x0 + 1, 0, 0}, {x0, 1, 0}, {x0, 0, 1}}; }
std::vector<glm::dvec3> hexahedron(double x0)
{
    return {{x0, 0, 0}, {x0 + 1, 0, 0}, {x0 + 1, 1, 0}, {x0, 1, 0},
            {x0, 0, 1}, {x0 + 1, 0, 1}, {x0 + 1, 1, 1}, {x0, 1, 1}};
}
std::vector<glm::dvec3> wedge(double x0)
{
    return {{x0, 0, 0}, {x0 + 1, 0, 0}, {x0, 1, 0}, {x0, 0, 1}, {x0 + 1, 0, 1}, {x0, 1, 1}};
}
std::vector<glm::dvec3> pyramid(double x0)
{
    return {{x0, 0, 0}, {x0 + 1, 0, 0}, {x0 + 1, 1, 0}, {x0, 1, 0}, {x0 + 0.5, 0.5, 1}};
}

// Per block of every_element_type() (block b lies in 2b <= x < 2b + 2): its tetrahedra and volume.
struct Expected {
    std::size_t tets;
    double volume;
};
const std::vector<Expected> kExpected = {{1, 1.0 / 6}, {6, 1.0}, {3, 0.5}, {2, 1.0 / 3}, {1, 1.0 / 6}, {6, 1.0}};

double pressure(int step, int block) { return 10.0 * (block + 1) + 0.5 * step; }

// One element of each type (TETRA, HEX8, WEDGE6, PYRAMID5, TETRA10 and HEX20 by their corners), two nodal
// variables, one element variable, two time steps.
ExoSpec every_element_type(int mode)
{
    ExoSpec s;
    s.mode = mode;
    s.title = "every element type";
    add_element(s, 1, "TETRA", "tets", tetra(0));
    add_element(s, 2, "HEX8", "hexes", hexahedron(2));
    add_element(s, 3, "WEDGE6", "wedges", wedge(4));
    add_element(s, 4, "PYRAMID5", "pyramids", pyramid(6));
    add_element(s, 5, "TETRA10", "quadratic tets", tetra(8), 6);
    add_element(s, 6, "HEX20", "quadratic hexes", hexahedron(10), 12);
    s.nodal_names = {"temperature", ""};
    s.element_names = {"pressure"};
    s.times = {0.5, 1.5};
    const std::vector<glm::dvec3> points = s.points;
    s.nodal_value = [points](int step, int var, int node) {
        return var == 0 ? points[std::size_t(node)].x + 100.0 * step : -node - 1000.0 * step;
    };
    s.element_value = [](int step, int, int block, int) { return pressure(step, block); };
    return s;
}

// A minimal Exodus II file (one tetrahedron) written with netCDF alone, to damage it in ways the Exodus API cannot:
// `coordinate_values` values in each coordinate array (4 is right), `word_sizes` values of the attribute
// floating_point_word_size (1 is right), and the element type name.
void write_raw_exodus(const std::string& path, std::size_t coordinate_values, std::size_t word_sizes,
                      const std::string& type)
{
    int nc = -1;
    REQUIRE(nc_create(path.c_str(), NC_CLOBBER | NC_64BIT_OFFSET, &nc) == NC_NOERR);
    auto dim = [&](const char* name, std::size_t len) {
        int d = -1;
        REQUIRE(nc_def_dim(nc, name, len, &d) == NC_NOERR);
        return d;
    };
    auto var = [&](const char* name, nc_type t, std::vector<int> dims) {
        int v = -1;
        REQUIRE(nc_def_var(nc, name, t, int(dims.size()), dims.data(), &v) == NC_NOERR);
        return v;
    };
    const float version = 6.02f;
    const int word_size[2] = {8, 8}, large_model = 1;
    REQUIRE(nc_put_att_float(nc, NC_GLOBAL, "api_version", NC_FLOAT, 1, &version) == NC_NOERR);
    REQUIRE(nc_put_att_float(nc, NC_GLOBAL, "version", NC_FLOAT, 1, &version) == NC_NOERR);
    REQUIRE(nc_put_att_int(nc, NC_GLOBAL, "floating_point_word_size", NC_INT, word_sizes, word_size) == NC_NOERR);
    REQUIRE(nc_put_att_int(nc, NC_GLOBAL, "file_size", NC_INT, 1, &large_model) == NC_NOERR);
    REQUIRE(nc_put_att_text(nc, NC_GLOBAL, "title", 3, "raw") == NC_NOERR);
    for (const char* name : {"len_string", "len_name"}) dim(name, 33);
    dim("len_line", 81);
    dim("four", 4);
    dim("time_step", NC_UNLIMITED);
    dim("num_dim", 3);
    const int nodes = dim("num_nodes", 4), blocks = dim("num_el_blk", 1);
    dim("num_elem", 1);
    const int elements = dim("num_el_in_blk1", 1), corners = dim("num_nod_per_el1", 4);
    const int coordinates = coordinate_values == 4 ? nodes : dim("damaged", coordinate_values);
    const int status = var("eb_status", NC_INT, {blocks}), ids = var("eb_prop1", NC_INT, {blocks});
    REQUIRE(nc_put_att_text(nc, ids, "name", 2, "ID") == NC_NOERR);
    const int x = var("coordx", NC_DOUBLE, {coordinates}), y = var("coordy", NC_DOUBLE, {coordinates}),
              z = var("coordz", NC_DOUBLE, {coordinates}), conn = var("connect1", NC_INT, {elements, corners});
    REQUIRE(nc_put_att_text(nc, conn, "elem_type", type.size(), type.c_str()) == NC_NOERR);
    REQUIRE(nc_enddef(nc) == NC_NOERR);
    const int one = 1, connectivity[4] = {1, 2, 3, 4};
    std::vector<double> xs(coordinate_values, 0.0), ys(xs), zs(xs);
    xs[1] = ys[2] = zs[3] = 1.0;
    REQUIRE(nc_put_var_int(nc, status, &one) == NC_NOERR);
    REQUIRE(nc_put_var_int(nc, ids, &one) == NC_NOERR);
    REQUIRE(nc_put_var_double(nc, x, xs.data()) == NC_NOERR);
    REQUIRE(nc_put_var_double(nc, y, ys.data()) == NC_NOERR);
    REQUIRE(nc_put_var_double(nc, z, zs.data()) == NC_NOERR);
    REQUIRE(nc_put_var_int(nc, conn, connectivity) == NC_NOERR);
    REQUIRE(nc_close(nc) == NC_NOERR);
}

const uvr::ScalarField& field(const uvr::TetMesh& mesh, const std::string& name)
{
    auto it = std::find_if(mesh.fields.begin(), mesh.fields.end(), [&](const auto& f) { return f.name == name; });
    REQUIRE(it != mesh.fields.end());
    return *it;
}

void require_exodus_error(const std::string& path, const std::string& time_step, const std::string& phrase,
                          const std::string& phrase2 = "")
{
    uvr::test::require_input_error([&] { uvr::read_exodus(path, time_step); }, {path, phrase, phrase2});
}

bool same_fields(const uvr::TetMesh& a, const uvr::TetMesh& b)
{
    if (a.fields.size() != b.fields.size()) return false;
    for (std::size_t i = 0; i < a.fields.size(); ++i)
        if (a.fields[i].name != b.fields[i].name || a.fields[i].values != b.fields[i].values ||
            a.fields[i].association != b.fields[i].association)
            return false;
    return true;
}

bool has_warning(const uvr::Dataset& d, const std::string& phrase)
{
    return std::any_of(d.warnings.begin(), d.warnings.end(),
                       [&](const std::string& w) { return w.find(phrase) != std::string::npos; });
}

// The block (index into kExpected) a tetrahedron lies in, from its centroid.
std::size_t block_of(const uvr::TetMesh& mesh, const uvr::Tet& t)
{
    double x = 0;
    for (uint32_t v : t) x += mesh.points[v].x / 4;
    return std::size_t(std::floor(x / 2));
}

void check_every_element_type(const uvr::Dataset& d, const ExoSpec& s, int step)
{
    REQUIRE(d.mesh);
    const uvr::TetMesh& mesh = *d.mesh;
    CHECK(mesh.points.size() == s.points.size());
    std::vector<std::size_t> tets(kExpected.size(), 0);
    std::vector<double> volume(kExpected.size(), 0.0);
    for (const uvr::Tet& t : mesh.tets) {
        const std::size_t b = block_of(mesh, t);
        REQUIRE(b < kExpected.size());
        ++tets[b];
        const auto& p = mesh.points;
        volume[b] += uvr::signed_volume6(p[t[0]], p[t[1]], p[t[2]], p[t[3]]) / 6;
    }
    for (std::size_t b = 0; b < kExpected.size(); ++b) {
        INFO("block " << b + 1);
        CHECK(tets[b] == kExpected[b].tets);
        CHECK(volume[b] == Approx(kExpected[b].volume).epsilon(1e-12));
    }
    CHECK(uvr::total_tet_volume(mesh) == Approx(1.0 / 6 + 1 + 0.5 + 1.0 / 3 + 1.0 / 6 + 1).epsilon(1e-12));
    // Exodus's orientation was carried over (the wedge's corners reordered into VTK's): nothing came out inverted.
    CHECK_FALSE(has_warning(d, "re-oriented"));

    const uvr::ScalarField& t = field(mesh, "temperature");
    REQUIRE(t.association == uvr::FieldAssociation::point);
    const uvr::ScalarField& unnamed = field(mesh, "nodal_var_2");
    for (std::size_t n = 0; n < s.points.size(); ++n) {
        CHECK(t.values[n] == s.nodal_value(step, 0, int(n)));
        CHECK(unnamed.values[n] == s.nodal_value(step, 1, int(n)));
    }
    const uvr::ScalarField& p = field(mesh, "pressure");
    REQUIRE(p.association == uvr::FieldAssociation::cell);
    REQUIRE(p.values.size() == mesh.tets.size());
    for (std::size_t i = 0; i < mesh.tets.size(); ++i)
        CHECK(p.values[i] == pressure(step, int(block_of(mesh, mesh.tets[i]))));
}

}  // namespace

TEST_CASE("Exodus reader reads every 3-D element type with its variables at each time step", "[exodus]")
{
    TempDir dir("exodus");
    const ExoSpec s = every_element_type(EX_LARGE_MODEL);
    const std::string path = dir.file("all.exo");
    write_exodus(path, s);

    const uvr::Dataset first = uvr::read_exodus(path, "1");
    check_every_element_type(first, s, 1);
    const uvr::Dataset last = uvr::read_exodus(path, "last");
    check_every_element_type(last, s, 2);
    CHECK(same_fields(*uvr::load_dataset(path).mesh, *last.mesh));  // .exo comes here, at the last step by default

    // Higher-order blocks are read by their corners, with a warning.
    CHECK(has_warning(first, "element block 5 (TETRA10): the 6 higher-order nodes"));
    CHECK(has_warning(first, "element block 6 (HEX20): the 12 higher-order nodes"));
    for (const std::string& w : first.warnings) CHECK_THAT(w, Catch::StartsWith(path + ": "));

    const nlohmann::json info = nlohmann::json::parse(last.info_json);
    CHECK(info["format"] == "Exodus II");
    CHECK(info["title"] == "every element type");
    REQUIRE(info["blocks"].size() == 6);
    CHECK(info["blocks"][2] ==
          nlohmann::json(
              {{"id", 3}, {"name", "wedges"}, {"type", "WEDGE6"}, {"elements", 1}, {"nodes_per_element", 6}}));
    CHECK(info["blocks"][5]["name"] == "quadratic hexes");
    CHECK(info["blocks"][5]["nodes_per_element"] == 20);
    CHECK(info["nodal_variables"] == nlohmann::json({"temperature", "nodal_var_2"}));
    CHECK(info["element_variables"] == nlohmann::json({"pressure"}));
    CHECK(info["times"] == nlohmann::json({0.5, 1.5}));
    CHECK(info["time_step"] == 2);
    CHECK(nlohmann::json::parse(first.info_json)["time_step"] == 1);
    CHECK(info["node_sets"].empty());
    CHECK(info["side_sets"].empty());
}

TEST_CASE("Exodus reader reads the classic layout of nodal variables and netCDF-4 files alike", "[exodus]")
{
    TempDir dir("exodus");
    const std::string large = dir.file("large.exo"), normal = dir.file("normal.exo"), hdf5 = dir.file("hdf5.exo");
    write_exodus(large, every_element_type(EX_LARGE_MODEL));
    write_exodus(normal, every_element_type(EX_NORMAL_MODEL));
    write_exodus(hdf5, every_element_type(EX_NETCDF4));

    // The classic layout stores every nodal variable in one array, vals_nod_var; the large one one array per variable.
    auto has_variable = [](const std::string& path, const char* name) {
        int ncid = -1, varid = -1;
        REQUIRE(nc_open(path.c_str(), NC_NOWRITE, &ncid) == NC_NOERR);
        const bool found = nc_inq_varid(ncid, name, &varid) == NC_NOERR;
        nc_close(ncid);
        return found;
    };
    CHECK(has_variable(normal, "vals_nod_var"));
    CHECK_FALSE(has_variable(normal, "vals_nod_var1"));
    CHECK(has_variable(large, "vals_nod_var1"));
    CHECK_FALSE(has_variable(large, "vals_nod_var"));
    CHECK(file_prefix(hdf5, 4) == "\x89HDF");
    CHECK(uvr::looks_like_exodus(normal));
    CHECK(uvr::looks_like_exodus(hdf5));

    for (const char* step : {"1", "last"}) {
        const uvr::Dataset a = uvr::read_exodus(large, step);
        for (const std::string& other : {normal, hdf5}) {
            INFO(other << " at time step " << step);
            const uvr::Dataset b = uvr::read_exodus(other, step);
            CHECK(b.mesh->points == a.mesh->points);
            CHECK(b.mesh->tets == a.mesh->tets);
            CHECK(same_fields(*b.mesh, *a.mesh));
        }
    }
}

TEST_CASE("Exodus reader skips lower-dimensional blocks, empty blocks, sets and undefined element variables",
          "[exodus]")
{
    TempDir dir("exodus");
    ExoSpec s;
    s.sets = true;
    add_element(s, 1, "tetra4", "caf\xe9", tetra(0));  // type names are case-insensitive; a Latin-1 name
    add_element(s, 2, "SHELL4", "skin", {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}});
    s.blocks.push_back({3, "HEX", "empty", 8, {}});
    add_element(s, 4, "HEX", "cub\xc3\xa9", hexahedron(2));  // UTF-8
    s.element_names = {"everywhere", "not on the cube"};
    s.truth = {1, 1, 1, 1, 1, 1, 1, 0};  // block-major: block 4 lacks the second variable
    s.times = {3.0};
    s.element_value = [](int, int var, int block, int) { return 100.0 * var + block; };
    const std::string path = dir.file("mixed.exo");
    write_exodus(path, s);

    const uvr::Dataset d = uvr::read_exodus(path, "last");
    REQUIRE(d.mesh);
    CHECK(d.mesh->tets.size() == 7);
    CHECK(has_warning(d, "element block 2 (SHELL4) skipped: 1 element(s) of a 0-D, 1-D or 2-D type"));
    CHECK(has_warning(d, "element variable 'not on the cube' is not defined on element block 4; it is dropped"));
    CHECK(has_warning(d, "1 node set skipped: uvr reads element blocks and variables"));
    CHECK(has_warning(d, "1 side set skipped: uvr reads element blocks and variables"));
    REQUIRE(d.mesh->fields.size() == 1);
    const uvr::ScalarField& f = d.mesh->fields[0];
    CHECK(f.name == "everywhere");
    CHECK(std::count(f.values.begin(), f.values.end(), 0.0) == 1);  // the tetrahedron (block index 0)
    CHECK(std::count(f.values.begin(), f.values.end(), 3.0) == 6);  // the cube's tetrahedra (block index 3)
    const nlohmann::json info = nlohmann::json::parse(d.info_json);
    CHECK(info["blocks"][2]["elements"] == 0);
    // Names go into JSON, which takes valid UTF-8 only.
    CHECK(info["blocks"][0]["name"] == "caf?");
    CHECK(info["blocks"][3]["name"] == "cub\xc3\xa9");
    CHECK(info["blocks"][1]["type"] == "SHELL4");
    CHECK(info["node_sets"] == nlohmann::json({"inlet"}));
    CHECK(info["side_sets"] == nlohmann::json({40}));
    CHECK(info["element_variables"] == nlohmann::json({"everywhere", "not on the cube"}));

    // No variable and no time step: a mesh without fields.
    ExoSpec bare;
    add_element(bare, 1, "TET4", "", tetra(0));
    write_exodus(dir.file("bare.exo"), bare);
    const uvr::Dataset b = uvr::read_exodus(dir.file("bare.exo"), "last");
    CHECK(b.mesh->fields.empty());
    const nlohmann::json bare_info = nlohmann::json::parse(b.info_json);
    CHECK(bare_info["times"].empty());
    CHECK(bare_info["time_step"].is_null());
}

TEST_CASE("Exodus reader reads variables without a time step as a mesh without fields, with a warning", "[exodus]")
{
    TempDir dir("exodus");
    ExoSpec s;
    add_element(s, 1, "TETRA", "", tetra(0));
    s.nodal_names = {"t"};
    s.element_names = {"p"};
    write_exodus(dir.file("no_steps.exo"), s);
    const uvr::Dataset d = uvr::read_exodus(dir.file("no_steps.exo"), "last");
    REQUIRE(d.mesh);
    CHECK(d.mesh->tets.size() == 1);
    CHECK(d.mesh->fields.empty());
    CHECK(has_warning(d, "defines variables but holds no time step"));
    const nlohmann::json info = nlohmann::json::parse(d.info_json);
    CHECK(info["nodal_variables"] == nlohmann::json({"t"}));
    CHECK(info["element_variables"] == nlohmann::json({"p"}));
    CHECK(info["time_step"].is_null());
    // Rendering it asks for a field the mesh does not have.
    const uvr::test::CommandResult r = uvr::test::run_uvr("render '" + dir.file("no_steps.exo") +
                                                          "' --size 8x8 --out '" + dir.file("x.png") + "'");
    CHECK(r.exit_code != 0);
    CHECK_THAT(r.err, Catch::Contains("no scalar field"));
    CHECK_FALSE(std::filesystem::exists(dir.file("x.png")));
}

TEST_CASE("Exodus reader reads HEX27, WEDGE15 and PYRAMID13 blocks by their corners", "[exodus]")
{
    TempDir dir("exodus");
    ExoSpec s;
    add_element(s, 1, "HEX27", "", hexahedron(0), 19);
    add_element(s, 2, "WEDGE15", "", wedge(2), 9);
    add_element(s, 3, "PYRAMID13", "", pyramid(4), 8);
    s.nodal_names = {"x"};
    s.element_names = {"block"};
    s.times = {1.0};
    const std::vector<glm::dvec3> points = s.points;
    s.nodal_value = [points](int, int, int node) { return points[std::size_t(node)].x; };
    s.element_value = [](int, int, int block, int) { return double(block); };
    write_exodus(dir.file("higher.exo"), s);
    const uvr::Dataset d = uvr::read_exodus(dir.file("higher.exo"), "last");
    REQUIRE(d.mesh);
    // The corners split as the linear cells are (6, 3 and 2 tetrahedra); a higher-order node used as a corner would
    // sit 7 units above the element and change its volume.
    const Expected expected[] = {{6, 1.0}, {3, 0.5}, {2, 1.0 / 3.0}};
    std::size_t count[3] = {0, 0, 0};
    double volume[3] = {0, 0, 0};
    for (const uvr::Tet& t : d.mesh->tets) {
        const std::size_t b = block_of(*d.mesh, t);
        REQUIRE(b < 3);
        ++count[b];
        const auto& p = d.mesh->points;
        volume[b] += uvr::signed_volume6(p[t[0]], p[t[1]], p[t[2]], p[t[3]]) / 6.0;
    }
    for (int b = 0; b < 3; ++b) {
        INFO("block " << b + 1);
        CHECK(count[b] == expected[b].tets);
        CHECK(volume[b] == Approx(expected[b].volume).epsilon(1e-12));
    }
    CHECK(has_warning(d, "element block 1 (HEX27): the 19 higher-order nodes"));
    CHECK(has_warning(d, "element block 2 (WEDGE15): the 9 higher-order nodes"));
    CHECK(has_warning(d, "element block 3 (PYRAMID13): the 8 higher-order nodes"));
    const uvr::ScalarField& x = field(*d.mesh, "x");
    for (std::size_t i = 0; i < d.mesh->points.size(); ++i) CHECK(x.values[i] == d.mesh->points[i].x);
    CHECK(field(*d.mesh, "block").values.size() == d.mesh->tets.size());
}

TEST_CASE("Exodus reader rejects bad input with a message naming the file", "[exodus][errors]")
{
    TempDir dir("exodus");
    const std::string good = dir.file("good.exo");
    write_exodus(good, every_element_type(EX_LARGE_MODEL));
    const std::string bytes = file_contents(good);

    SECTION("not an Exodus II file")
    {
        require_exodus_error(dir.write("text.exo", "this is not a mesh\n"), "last", "not an Exodus II file");
        std::string noise(3000, '\0');
        for (std::size_t i = 0; i < noise.size(); ++i) noise[i] = char((i * 2654435761u) >> 13);
        require_exodus_error(dir.write("noise.exo", noise), "last", "not an Exodus II file");
        require_exodus_error(dir.write("empty.exo", ""), "last", "empty file");
        require_exodus_error(dir.file("missing.exo"), "last", "cannot open");
        // A netCDF file of something else.
        int ncid = -1, dim = -1, var = -1;
        const std::string other = dir.file("other.exo");
        REQUIRE(nc_create(other.c_str(), NC_CLOBBER, &ncid) == NC_NOERR);
        REQUIRE(nc_def_dim(ncid, "x", 3, &dim) == NC_NOERR);
        REQUIRE(nc_def_var(ncid, "temperature", NC_DOUBLE, 1, &dim, &var) == NC_NOERR);
        REQUIRE(nc_close(ncid) == NC_NOERR);
        require_exodus_error(other, "last", "not an Exodus II file", "the Exodus library cannot open it");
        CHECK_FALSE(uvr::looks_like_exodus(dir.file("text.exo")));
    }
    SECTION("truncated files")
    {
        require_exodus_error(dir.write("half.exo", bytes.substr(0, bytes.size() / 2)), "last", "truncated");
        require_exodus_error(dir.write("short.exo", bytes.substr(0, bytes.size() - 8)), "last", "truncated");
        require_exodus_error(dir.write("header.exo", bytes.substr(0, 200)), "last", "truncated");
        const std::string hdf5 = dir.file("hdf5.exo");
        write_exodus(hdf5, every_element_type(EX_NETCDF4));
        const std::string h = file_contents(hdf5);
        require_exodus_error(dir.write("half_hdf5.exo", h.substr(0, h.size() / 2)), "last", "truncated");
    }
    SECTION("time steps")
    {
        require_exodus_error(good, "3", "time step 3 is out of range", "1 to 2");
        require_exodus_error(good, "0", "out of range");
        require_exodus_error(good, "-1", "out of range");
        require_exodus_error(good, "abc", "'abc' is neither 'last' nor a number");
        require_exodus_error(good, "1.5", "neither 'last' nor a number");
        require_exodus_error(good, "", "neither 'last' nor a number");
        ExoSpec s;
        add_element(s, 1, "TETRA", "", tetra(0));
        s.nodal_names = {"t"};
        write_exodus(dir.file("no_steps.exo"), s);
        require_exodus_error(dir.file("no_steps.exo"), "1", "out of range", "no time step");
    }
    SECTION("a file of node and side sets without element blocks")
    {
        ExoSpec s;
        s.points = tetra(0);
        s.sets = true;
        write_exodus(dir.file("sets.exo"), s);
        require_exodus_error(dir.file("sets.exo"), "last", "no element block", "1 node set(s), 1 side set(s)");
        ExoSpec nodes;
        nodes.points = tetra(0);
        write_exodus(dir.file("nodes.exo"), nodes);
        require_exodus_error(dir.file("nodes.exo"), "last", "no element block", "0 node set(s), 0 side set(s)");
    }
    SECTION("meshes uvr does not read")
    {
        ExoSpec flat;
        flat.num_dim = 2;
        add_element(flat, 1, "QUAD4", "", {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}});
        write_exodus(dir.file("flat.exo"), flat);
        require_exodus_error(dir.file("flat.exo"), "last", "2-D", "3-D meshes");

        ExoSpec foo;
        add_element(foo, 7, "FOO", "", hexahedron(0));
        write_exodus(dir.file("foo.exo"), foo);
        require_exodus_error(dir.file("foo.exo"), "last", "element block 7 has element type 'FOO'", "does not read");

        ExoSpec surface;
        add_element(surface, 1, "TRI3", "", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
        write_exodus(dir.file("surface.exo"), surface);
        require_exodus_error(dir.file("surface.exo"), "last", "no 3D cell");

        ExoSpec few;
        add_element(few, 2, "HEX", "", {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}});
        write_exodus(dir.file("few.exo"), few);
        require_exodus_error(dir.file("few.exo"), "last", "element block 2 (HEX) has 4 nodes per element",
                             "fewer than its 8 corners");

        ExoSpec zero;
        add_element(zero, 3, "TETRA", "", tetra(0));
        zero.blocks[0].connectivity[2] = 0;
        write_exodus(dir.file("zero.exo"), zero);
        require_exodus_error(dir.file("zero.exo"), "last", "element block 3, element 1 uses node 0", "from 1 to 4");
    }
}

TEST_CASE("Exodus reader refuses damage that the Exodus library would trust", "[exodus][errors]")
{
    TempDir dir("exodus");
    const std::string good = dir.file("raw.exo");
    write_raw_exodus(good, 4, 1, "TETRA");
    const uvr::Dataset d = uvr::read_exodus(good, "last");
    REQUIRE(d.mesh);
    CHECK(d.mesh->tets.size() == 1);
    CHECK(uvr::total_tet_volume(*d.mesh) == Approx(1.0 / 6));

    // The library would read the whole array into a buffer of 4 values.
    const std::string long_coordinates = dir.file("long_coordinates.exo");
    write_raw_exodus(long_coordinates, 5, 1, "TETRA");
    require_exodus_error(long_coordinates, "last", "coordinates holds 5 values, but the file's dimensions say 4");
    // The library would read the attribute into a single int.
    const std::string two_word_sizes = dir.file("two_word_sizes.exo");
    write_raw_exodus(two_word_sizes, 4, 2, "TETRA");
    require_exodus_error(two_word_sizes, "last", "'floating_point_word_size' must hold one value");
    // The library would copy the whole name into a buffer of 33 characters on its stack.
    const std::string long_type = dir.file("long_type.exo");
    write_raw_exodus(long_type, 4, 1, "TETRA" + std::string(200, 'X'));
    require_exodus_error(long_type, "last", "element block 1 has an element type name of 205 characters");
    // A name of 32 characters is allowed, and then an unknown type.
    const std::string longest_type = dir.file("longest_type.exo");
    write_raw_exodus(longest_type, 4, 1, "TETRA" + std::string(27, 'X'));
    require_exodus_error(longest_type, "last", "element block 1 has element type 'TETRAXXX", "does not read");
}

TEST_CASE("uvr info shows an Exodus II file's blocks, variables and time step", "[exodus][cli]")
{
    TempDir dir("exodus");
    const std::string path = dir.file("all.exo");
    write_exodus(path, every_element_type(EX_LARGE_MODEL));
    const uvr::test::CommandResult r = uvr::test::run_uvr("info '" + path + "' --json --time 1");
    INFO("stderr: " << r.err);
    REQUIRE(r.exit_code == 0);
    const nlohmann::json j = nlohmann::json::parse(r.out);
    CHECK(j["tetrahedra"] == 19);
    const nlohmann::json& format = j["format"];
    CHECK(format["format"] == "Exodus II");
    std::vector<std::string> blocks;
    for (const auto& b : format["blocks"]) blocks.push_back(b["name"]);
    CHECK(blocks == std::vector<std::string>{"tets", "hexes", "wedges", "pyramids", "quadratic tets",
                                             "quadratic hexes"});
    CHECK(format["nodal_variables"] == nlohmann::json({"temperature", "nodal_var_2"}));
    CHECK(format["element_variables"] == nlohmann::json({"pressure"}));
    CHECK(format["time_step"] == 1);
    CHECK_THAT(r.err, Catch::Contains("higher-order nodes"));

    const uvr::test::CommandResult bad = uvr::test::run_uvr("info '" + path + "' --time 9");
    CHECK(bad.exit_code != 0);
    CHECK_THAT(bad.err, Catch::Contains("time step 9 is out of range"));
}

// A 4 x 3 x 2 block of unit hexahedra sharing their nodes, the nodal variable x + 2y - z and the element variable
// (i + j + k) mod 3, one time step.
ExoSpec hexahedral_block()
{
    ExoSpec s;
    constexpr int nx = 4, ny = 3, nz = 2;
    for (int k = 0; k <= nz; ++k)
        for (int j = 0; j <= ny; ++j)
            for (int i = 0; i <= nx; ++i) s.points.push_back({i, j, k});
    BlockSpec b{1, "HEX8", "block", 8, {}};
    const int corner[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    std::vector<double> cell;
    for (int k = 0; k < nz; ++k)
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i) {
                for (const auto& c : corner)
                    b.connectivity.push_back(1 + (i + c[0]) + (nx + 1) * ((j + c[1]) + (ny + 1) * (k + c[2])));
                cell.push_back(double((i + j + k) % 3));
            }
    s.blocks.push_back(b);
    s.nodal_names = {"temperature"};
    s.element_names = {"material"};
    s.times = {0.0};
    const std::vector<glm::dvec3> points = s.points;
    s.nodal_value = [points](int, int, int n) { return points[n].x + 2.0 * points[n].y - points[n].z; };
    s.element_value = [cell](int, int, int, int e) { return cell[std::size_t(e)]; };
    return s;
}

TEST_CASE("uvr render draws an Exodus II hexahedral mesh with every algorithm, GL as the emulation bit for bit",
          "[exodus][cli]")
{
    TempDir dir("exodus-render");
    const std::string path = dir.file("block.exo");
    write_exodus(path, hexahedral_block());
    for (const char* field : {"temperature", "material"}) {
        const std::string args = "render '" + path + "' --field " + field + " --size 64x48 --view 30,25 --out '";
        const auto render = [&](const std::string& algo, const std::string& backend) {
            const std::string out = dir.file(std::string(field) + "-" + algo + "-" + backend + ".npy");
            const uvr::test::CommandResult r =
                uvr::test::run_uvr(args + out + "' --algo " + algo + (backend.empty() ? "" : " --backend " + backend));
            INFO(field << ", " << algo << " " << backend << ": " << r.err);
            REQUIRE(r.exit_code == 0);
            return out;
        };
        INFO("field " << field);
        const uvr::Image ref = uvr::read_npy(render("reference", ""));
        CHECK(*std::max_element(ref.rgba.begin(), ref.rgba.end()) > 0.1f);  // the block is in view
        CHECK(file_contents(render("havs", "gl")) == file_contents(render("havs", "emu")));
        CHECK(file_contents(render("vicp", "gl")) == file_contents(render("vicp", "emu")));
    }
}

TEST_CASE("a .g file is read as Exodus II when it is netCDF and as a PLOT3D grid otherwise", "[exodus]")
{
    TempDir dir("exodus-g");
    const std::string genesis = dir.file("mesh.g");
    write_exodus(genesis, hexahedral_block());
    const uvr::Dataset exodus = uvr::load_dataset(genesis);
    REQUIRE(exodus.mesh);
    CHECK(exodus.mesh->tets.size() == 4 * 3 * 2 * 6);
    CHECK(nlohmann::json::parse(exodus.info_json)["format"] == "Exodus II");
    // Blunt Fin's PLOT3D grid under the name .g: PLOT3D, as before.
    const std::string grid = dir.file("grid.g");
    std::filesystem::copy_file(uvr::test::data_path("vtk-data/bluntfinxyz.bin"), grid);
    const uvr::Dataset plot3d = uvr::load_dataset(grid);
    REQUIRE(plot3d.mesh);
    CHECK(plot3d.mesh->tets.size() == 187395);
    CHECK(nlohmann::json::parse(plot3d.info_json)["format"] == "PLOT3D");
}
