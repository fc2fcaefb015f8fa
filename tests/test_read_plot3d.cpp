// The PLOT3D reader: the NASA Blunt Fin and Oxygen Post grids, layout detection, iblank, and broken files.
#include <cstring>
#include <functional>

#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

#include "reference/dataset.h"
#include "test_support.h"

using namespace uvr;
using uvr::test::data_path;
using uvr::test::require_input_error;
using uvr::test::TempDir;

namespace {

struct Options {
    bool big_endian = true;
    bool double_precision = false;
    bool fortran = false;    // Fortran unformatted records around the header and the body
    bool grid_count = false; // a leading grid count of 1
};

template <class T>
void put(std::string& out, T v, bool big_endian)
{
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    if (big_endian)
        for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(b[i], b[sizeof(T) - 1 - i]);
    out.append(b, sizeof(T));
}

void put_real(std::string& out, double v, const Options& o)
{
    if (o.double_precision)
        put<double>(out, v, o.big_endian);
    else
        put<float>(out, static_cast<float>(v), o.big_endian);
}

std::string record(const std::string& payload, const Options& o)
{
    if (!o.fortran) return payload;
    std::string r;
    put<int32_t>(r, static_cast<int32_t>(payload.size()), o.big_endian);
    r += payload;
    put<int32_t>(r, static_cast<int32_t>(payload.size()), o.big_endian);
    return r;
}

std::string header(int ni, int nj, int nk, const Options& o)
{
    std::string h;
    if (o.grid_count) {
        std::string count;
        put<int32_t>(count, 1, o.big_endian);
        h += record(count, o);
    }
    std::string dims;
    for (int d : {ni, nj, nk}) put<int32_t>(dims, d, o.big_endian);
    return h + record(dims, o);
}

// A grid whose point (i, j, k) is at place(i, j, k), by default a grid of unit cubes; `iblank` empty for none.
std::string xyz_file(int ni, int nj, int nk, const std::vector<int32_t>& iblank, const Options& o,
                     const std::function<glm::dvec3(int, int, int)>& place = {})
{
    std::string body;
    for (int axis = 0; axis < 3; ++axis)
        for (int k = 0; k < nk; ++k)
            for (int j = 0; j < nj; ++j)
                for (int i = 0; i < ni; ++i) put_real(body, place ? place(i, j, k)[axis] : (axis == 0 ? i : axis == 1 ? j : k), o);
    for (int32_t b : iblank) put<int32_t>(body, b, o.big_endian);
    return header(ni, nj, nk, o) + record(body, o);
}

// Q variable v at point p is 10 * v + p, so that each field can be recognised.
std::string q_file(int ni, int nj, int nk, const Options& o)
{
    std::string refs, body;
    for (double r : {2.95, 0.0, 2.0e6, 0.0}) put_real(refs, r, o);
    const int n = ni * nj * nk;
    for (int v = 0; v < 5; ++v)
        for (int p = 0; p < n; ++p) put_real(body, 10.0 * v + p, o);
    return header(ni, nj, nk, o) + record(refs, o) + record(body, o);
}

}  // namespace

TEST_CASE("PLOT3D reader builds the classic tetrahedral meshes of the NASA grids")
{
    SECTION("Blunt Fin: 40x32x32 points, 187,395 tetrahedra, five Q fields with Density first")
    {
        Dataset d = read_plot3d(data_path("vtk-data/bluntfinxyz.bin"), data_path("vtk-data/bluntfinq.bin"));
        REQUIRE(d.mesh);
        const TetMesh& m = *d.mesh;
        CHECK(m.points.size() == 40960);
        CHECK(m.tets.size() == 187395);
        REQUIRE(m.fields.size() == 5);
        const char* names[5] = {"Density", "MomentumX", "MomentumY", "MomentumZ", "StagnationEnergy"};
        for (int f = 0; f < 5; ++f) {
            INFO("field " << f);
            CHECK(m.fields[f].name == names[f]);
            CHECK(m.fields[f].values.size() == 40960);
        }
        CHECK(find_field(m, "") == 0);
        const Range density = field_range(m.fields[0]);
        INFO("density " << density.lo << " .. " << density.hi);
        CHECK(density.lo > 0.0);
        CHECK(density.hi > density.lo);
        INFO("the 484 trailing zero bytes of bluntfinq.bin are padding, not worth a warning");
        CHECK(d.warnings.empty());
    }
    SECTION("Oxygen Post: 38x76x38 points with iblank (no zeros), 513,375 tetrahedra")
    {
        Dataset d = read_plot3d(data_path("vtk-data/postxyz.bin"), data_path("vtk-data/postq.bin"));
        REQUIRE(d.mesh);
        CHECK(d.mesh->points.size() == 109744);
        CHECK(d.mesh->tets.size() == 513375);
        CHECK(d.mesh->fields.size() == 5);
        CHECK(d.warnings.empty());
    }
    SECTION("an empty Q path gives the geometry alone")
    {
        Dataset d = read_plot3d(data_path("vtk-data/bluntfinxyz.bin"), "");
        REQUIRE(d.mesh);
        CHECK(d.mesh->tets.size() == 187395);
        CHECK(d.mesh->fields.empty());
    }
}

TEST_CASE("PLOT3D reader counts the grid's hexahedra, the collapsed and the folded ones")
{
    TempDir tmp("plot3d-census");
    const Options o;
    // 4 x 2 x 2 points, three cells: the first folded (its corner (0, 1, 1) pushed through the opposite face, to
    // x = 1.6, so the map turns inside out near that corner but not at the others), the second as written, the third
    // collapsed (its corners at i = 3, j = 1 moved onto those at j = 0: a wedge written as a hexahedron).
    const auto place = [](int i, int j, int k) {
        if (i == 0 && j == 1 && k == 1) return glm::dvec3(1.6, 1, 1);
        if (i == 3 && j == 1) return glm::dvec3(3, 0, k);
        return glm::dvec3(i, j, k);
    };
    const std::string path = tmp.write("census.xyz", xyz_file(4, 2, 2, {}, o, place));
    const Dataset d = read_plot3d(path, "", true);
    const nlohmann::json info = nlohmann::json::parse(d.info_json);
    CHECK(info["format"] == "PLOT3D");
    CHECK(info["dims"] == nlohmann::json({4, 2, 2}));
    CHECK(info["hexahedra"] == 3);
    CHECK(info["collapsed_hexahedra"] == 1);
    CHECK(info["folded_hexahedra"] == 1);
    // The NASA grids (docs/formats.md): Blunt Fin's 39 cells along its symmetry line are collapsed (the 39 points
    // that repeat a position), none folds; the Oxygen Post has neither.
    const nlohmann::json fin = nlohmann::json::parse(read_plot3d(data_path("vtk-data/bluntfinxyz.bin"), "", true).info_json);
    CHECK(fin["hexahedra"] == 39 * 31 * 31);
    CHECK(fin["collapsed_hexahedra"] == 39);
    CHECK(fin["folded_hexahedra"] == 0);
    const nlohmann::json post = nlohmann::json::parse(read_plot3d(data_path("vtk-data/postxyz.bin"), "", true).info_json);
    CHECK(post["hexahedra"] == 37 * 75 * 37);
    CHECK(post["collapsed_hexahedra"] == 0);
    CHECK(post["folded_hexahedra"] == 0);
    // A load that does not ask for the census (every render) skips its pass over the cells.
    CHECK_FALSE(nlohmann::json::parse(read_plot3d(path, "").info_json).contains("hexahedra"));
}

TEST_CASE("PLOT3D reader drops the cells that touch a blanked point")
{
    TempDir tmp("p3d-iblank");
    const Options be;
    // 3x3x3 points = 8 hexahedra = 40 tetrahedra; point (i, j, k) has index i + 3 (j + 3 k).
    auto tets_with_zero_at = [&](int index) {
        std::vector<int32_t> iblank(27, 1);
        if (index >= 0) iblank[index] = 0;
        const std::string xyz = tmp.write("grid.xyz", xyz_file(3, 3, 3, iblank, be));
        return read_plot3d(xyz, "").mesh->tets.size();
    };
    SECTION("no blanked point keeps all 40 tetrahedra") { CHECK(tets_with_zero_at(-1) == 40); }
    SECTION("a blanked corner point drops the one hexahedron that has it") { CHECK(tets_with_zero_at(0) == 35); }
    SECTION("a blanked edge midpoint drops the two hexahedra that share it") { CHECK(tets_with_zero_at(1) == 30); }
    SECTION("a blanked face centre drops four hexahedra") { CHECK(tets_with_zero_at(1 + 3 * 1) == 20); }
}

TEST_CASE("PLOT3D reader recognises byte order, precision, Fortran records and a grid count by the file size")
{
    TempDir tmp("p3d-layout");
    struct Case {
        const char* name;
        Options o;
    };
    const Case cases[] = {
        {"big-endian single precision", {true, false, false, false}},
        {"little-endian single precision", {false, false, false, false}},
        {"big-endian double precision", {true, true, false, false}},
        {"Fortran records, little-endian", {false, false, true, false}},
        {"Fortran records with a grid count, big-endian double", {true, true, true, true}},
        {"whole file with a grid count of 1", {true, false, false, true}},
    };
    for (const Case& c : cases) {
        SECTION(c.name)
        {
            const std::string xyz = tmp.write("g.xyz", xyz_file(3, 2, 2, {}, c.o));
            const std::string q = tmp.write("g.q", q_file(3, 2, 2, c.o));
            Dataset d = read_plot3d(xyz, q);
            REQUIRE(d.mesh);
            CHECK(d.mesh->points.size() == 12);
            CHECK(d.mesh->tets.size() == 10);
            REQUIRE(d.mesh->fields.size() == 5);
            // Point 7 = (1, 0, 1) in the grid's order; the reader keeps that order.
            CHECK(d.mesh->points[7].x == 1.0);
            CHECK(d.mesh->points[7].y == 0.0);
            CHECK(d.mesh->points[7].z == 1.0);
            CHECK(d.mesh->fields[2].values[7] == 27.0);
            CHECK(d.warnings.empty());
        }
    }
}

TEST_CASE("PLOT3D reader warns about Q data it does not understand and accepts zero padding")
{
    TempDir tmp("p3d-trailing");
    const Options be;
    const std::string xyz = tmp.write("g.xyz", xyz_file(2, 2, 2, {}, be));
    SECTION("zero padding is silent")
    {
        const std::string q = tmp.write("g.q", q_file(2, 2, 2, be) + std::string(100, '\0'));
        CHECK(read_plot3d(xyz, q).warnings.empty());
    }
    SECTION("non-zero trailing bytes are reported")
    {
        const std::string q = tmp.write("g.q", q_file(2, 2, 2, be) + std::string(100, '\x7f'));
        Dataset d = read_plot3d(xyz, q);
        REQUIRE(d.warnings.size() == 1);
        INFO(d.warnings[0]);
        CHECK_THAT(d.warnings[0], Catch::Contains("g.q") && Catch::Contains("ignored 100 bytes"));
    }
}

TEST_CASE("PLOT3D reader rejects broken files with the file named")
{
    TempDir tmp("p3d-bad");
    const std::string blunt_xyz = data_path("vtk-data/bluntfinxyz.bin"), blunt_q = data_path("vtk-data/bluntfinq.bin");
    const std::string post_xyz = data_path("vtk-data/postxyz.bin"), post_q = data_path("vtk-data/postq.bin");
    auto truncated = [&](const std::string& from, std::size_t n, const std::string& name) {
        return tmp.write(name, uvr::test::file_prefix(from, n));
    };
    SECTION("truncated bluntfinxyz.bin")
    {
        const std::string xyz = truncated(blunt_xyz, 300000, "bluntfinxyz.bin");
        require_input_error([&] { read_plot3d(xyz, blunt_q); },
                            {xyz, "truncated", "40x32x32", "491532 bytes", "holds 300000 bytes"});
    }
    SECTION("truncated bluntfinq.bin")
    {
        const std::string q = truncated(blunt_q, 500000, "bluntfinq.bin");
        require_input_error([&] { read_plot3d(blunt_xyz, q); },
                            {q, "truncated", "819216 bytes after the header", "holds 499988"});
    }
    SECTION("truncated postxyz.bin (inside the iblank array)")
    {
        const std::string xyz = truncated(post_xyz, 1755916 - 1000, "postxyz.bin");
        require_input_error([&] { read_plot3d(xyz, post_q); }, {xyz, "truncated", "38x76x38", "1755916 (with iblank)"});
    }
    SECTION("Q dimensions that do not match the grid name both files")
    {
        require_input_error([&] { read_plot3d(blunt_xyz, post_q); },
                            {post_q, blunt_xyz, "38x76x38", "does not match", "40x32x32"});
    }
    SECTION("empty grid file")
    {
        const std::string xyz = tmp.write("empty.xyz", "");
        require_input_error([&] { read_plot3d(xyz, ""); }, {xyz, "empty file"});
    }
    SECTION("empty Q file")
    {
        const std::string q = tmp.write("empty.q", "");
        require_input_error([&] { read_plot3d(blunt_xyz, q); }, {q, "empty file"});
    }
    SECTION("a header claiming 10^12 points fails at once")
    {
        std::string h;
        for (int32_t d : {10000, 10000, 10000}) put<int32_t>(h, d, true);
        const std::string xyz = tmp.write("huge.xyz", h + std::string(64, '\0'));
        require_input_error([&] { read_plot3d(xyz, ""); },
                            {xyz, "10000x10000x10000", "12000000000012 bytes", "holds 76 bytes"});
    }
    SECTION("dimensions that are not positive in either byte order")
    {
        const std::string xyz = tmp.write("neg.xyz", std::string(12, '\xff') + std::string(48, '\0'));
        require_input_error([&] { read_plot3d(xyz, ""); }, {xyz, "not a PLOT3D grid file"});
    }
    SECTION("a multi-grid file is recognised and refused")
    {
        const Options be;
        std::string f;
        put<int32_t>(f, 2, true);
        for (int g = 0; g < 2; ++g)
            for (int32_t d : {2, 2, 2}) put<int32_t>(f, d, true);
        for (int g = 0; g < 2; ++g)
            for (int v = 0; v < 24; ++v) put_real(f, v, be);
        const std::string xyz = tmp.write("multi.xyz", f);
        require_input_error([&] { read_plot3d(xyz, ""); }, {xyz, "multi-grid", "2 grids"});
    }
    SECTION("a grid whose hexahedra are all blanked has no tetrahedron")
    {
        const std::string xyz = tmp.write("blank.xyz", xyz_file(2, 2, 2, std::vector<int32_t>(8, 0), Options{}));
        require_input_error([&] { read_plot3d(xyz, ""); }, {xyz});
    }
}
