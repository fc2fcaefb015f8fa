// VTK legacy reader: the real data files' counts, hand-written files in each layout, and bad input.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>

#include <catch2/catch.hpp>

#include "reference/dataset.h"
#include "reference/error.h"
#include "test_support.h"

namespace {

using uvr::test::data_path;
using uvr::test::file_contents;
using uvr::test::TempDir;

// The data's documented ranges are printed rounded (post.vtk 0.355..1.641 and hexa.vtk's minimum 0.753 to 3 decimals,
// hexa.vtk's maximum 17.32 to 2), so the true extremes differ from them by up to half a unit in the last place.
constexpr double kThreeDecimalTolerance = 5e-4;
constexpr double kTwoDecimalTolerance = 5e-3;

// Runs `load` and requires an InputError whose message names `file` and contains `phrase`.
void require_input_error(const std::function<void()>& load, const std::string& file, const std::string& phrase)
{
    uvr::test::require_input_error(load, {file, phrase});
}

void require_legacy_error(const std::string& path, const std::string& phrase)
{
    require_input_error([&] { uvr::read_vtk_legacy(path); }, path, phrase);
}

// Big-endian bytes of each value, as BINARY legacy files store them.
template <class T>
std::string be(std::initializer_list<T> values)
{
    std::string out;
    for (T v : values) {
        char b[sizeof(T)];
        std::memcpy(b, &v, sizeof(T));
        std::reverse(b, b + sizeof(T));
        out.append(b, sizeof(T));
    }
    return out;
}

bool has_warning(const uvr::Dataset& d, const std::string& phrase)
{
    return std::any_of(d.warnings.begin(), d.warnings.end(),
                       [&](const std::string& w) { return w.find(phrase) != std::string::npos; });
}

// The small mesh of the hand-written files: two positively oriented tetrahedra sharing the face 1 2 3.
const std::vector<glm::dvec3> kPoints = {{0, 0, 0}, {1.5, 0, 0}, {0, 2.25, 0}, {0, 0, 3.125}, {1.5, 2.25, 3.125}};
const std::vector<uvr::Tet> kTets = {{0, 1, 2, 3}, {1, 2, 3, 4}};
const std::vector<double> kTemperature = {0.5, 1, 2, 4, 8};

void check_small_mesh(const uvr::Dataset& d)
{
    REQUIRE(d.mesh);
    CHECK(d.mesh->points == kPoints);
    CHECK(d.mesh->tets == kTets);
    REQUIRE(d.mesh->fields.size() >= 1);
    CHECK(d.mesh->fields[0].name == "temperature");
    CHECK(d.mesh->fields[0].values == kTemperature);
}

const char* const kAsciiV51 = R"(# vtk DataFile Version 5.1
vtk output
ASCII
DATASET UNSTRUCTURED_GRID
POINTS 5 float
0 0 0 1.5 0 0 0 2.25 0
0 0 3.125 1.5 2.25 3.125
CELLS 3 8
OFFSETS vtktypeint64
0 4 8
CONNECTIVITY vtktypeint64
0 1 2 3
1 2 3 4
CELL_TYPES 2
10
10

POINT_DATA 5
SCALARS temperature double 1
LOOKUP_TABLE default
0.5 1 2 4 8
)";

// An ASCII mesh with the old CELLS form, to be edited into bad variants.
std::string ascii_old(const std::string& points, const std::string& cells, const std::string& types)
{
    return "# vtk DataFile Version 2.0\nsmall\nASCII\nDATASET UNSTRUCTURED_GRID\n" + points + cells + types;
}
const std::string kOldPoints = "POINTS 5 float\n0 0 0\n1.5 0 0\n0 2.25 0\n0 0 3.125\n1.5 2.25 3.125\n";
const std::string kOldTypes = "CELL_TYPES 2\n10\n10\n";

std::string binary_header(const std::string& version)
{
    return "# vtk DataFile Version " + version + "\nbinary test\nBINARY\nDATASET UNSTRUCTURED_GRID\n";
}
std::string binary_points()
{
    return "POINTS 5 float\n" + be<float>({0, 0, 0, 1.5f, 0, 0, 0, 2.25f, 0, 0, 0, 3.125f, 1.5f, 2.25f, 3.125f}) + "\n";
}

}  // namespace

TEST_CASE("VTK legacy reader reproduces the counts of the real data files", "[vtk][legacy]")
{
    SECTION("post.vtk: binary tetrahedra with a leading FIELD block and a Pressure field")
    {
        const auto d = uvr::read_vtk_legacy(data_path("vtk-data/post.vtk"));
        REQUIRE(d.mesh);
        CHECK(d.mesh->points.size() == 2288);
        CHECK(d.mesh->tets.size() == 8750);
        REQUIRE(d.mesh->fields.size() == 1);
        CHECK(d.mesh->fields[0].name == "Pressure");
        const uvr::Range r = uvr::field_range(d.mesh->fields[0]);
        INFO("Pressure range " << r.lo << " .. " << r.hi);
        CHECK(r.lo == Approx(0.355).margin(kThreeDecimalTolerance));
        CHECK(r.hi == Approx(1.641).margin(kThreeDecimalTolerance));
    }
    SECTION("tetraMesh.vtk: ASCII tetrahedra with integer scalars and an empty CELL_DATA")
    {
        const auto d = uvr::read_vtk_legacy(data_path("vtk-data/tetraMesh.vtk"));
        REQUIRE(d.mesh);
        CHECK(d.mesh->points.size() == 55);
        CHECK(d.mesh->tets.size() == 160);
        REQUIRE(d.mesh->fields.size() == 1);
        for (double v : d.mesh->fields[0].values) {
            INFO("value " << v);
            CHECK(v == std::round(v));
            CHECK(v >= 0);
            CHECK(v <= 4);
        }
        CHECK_FALSE(has_warning(d, "CELL_DATA"));
    }
    SECTION("a_grid.vtk: binary doubles, no fields")
    {
        const auto d = uvr::read_vtk_legacy(data_path("vtk-data/a_grid.vtk"));
        REQUIRE(d.mesh);
        CHECK(d.mesh->points.size() == 1317);
        CHECK(d.mesh->tets.size() == 4802);
        CHECK(d.mesh->fields.empty());
    }
    SECTION("uGridEx.vtk: hexahedra are split, 2D/1D/0D cells skipped with warnings")
    {
        // The file holds 2 hexahedra, 2 tetrahedra and 8 lower-dimensional cells (strip, polygon, quad, 2 triangles,
        // 2 lines, vertex); no wedge or pyramid. cells.cpp cones a hexahedron into 6 tetrahedra.
        constexpr std::size_t kTetsPerHex = 6;
        const auto d = uvr::read_vtk_legacy(data_path("vtk-data/uGridEx.vtk"));
        REQUIRE(d.mesh);
        CHECK(d.mesh->points.size() == 27);
        CHECK(d.mesh->tets.size() == 2 * kTetsPerHex + 2);
        for (const char* kind : {"triangle strip", "polygon", "quad", "triangle", "line", "vertex"}) {
            INFO("skipped kind " << kind);
            CHECK(has_warning(d, std::string("skipped ")));
            CHECK(has_warning(d, kind));
        }
        REQUIRE(d.mesh->fields.size() == 1);
        CHECK(uvr::field_range(d.mesh->fields[0]).hi == 26.0);
    }
    SECTION("hexa.vtk: 10648 hexahedra become 6 tetrahedra each")
    {
        const auto d = uvr::read_vtk_legacy(data_path("vtk-data/hexa.vtk"));
        REQUIRE(d.mesh);
        CHECK(d.mesh->points.size() == 12167);
        CHECK(d.mesh->tets.size() == 10648 * 6);
        REQUIRE(d.mesh->fields.size() == 1);
        const uvr::Range r = uvr::field_range(d.mesh->fields[0]);
        INFO("scalars range " << r.lo << " .. " << r.hi);
        CHECK(r.lo == Approx(0.753).margin(kThreeDecimalTolerance));
        CHECK(r.hi == Approx(17.32).margin(kTwoDecimalTolerance));
    }
    SECTION("ironProt.vtk: a binary unsigned-char volume")
    {
        const auto d = uvr::read_vtk_legacy(data_path("vtk-data/ironProt.vtk"));
        REQUIRE(d.volume);
        CHECK_FALSE(d.mesh);
        CHECK(d.volume->dims == std::array<int64_t, 3>{68, 68, 68});
        CHECK(d.volume->type == uvr::VoxelType::u8);
        CHECK(d.volume->values.size() == 68u * 68u * 68u);
        const uvr::Range r = uvr::volume_range(*d.volume);
        INFO("range " << r.lo << " .. " << r.hi);
        CHECK(r.lo == 0.0);
        CHECK(r.hi == 255.0);
        CHECK(d.volume->spacing == glm::dvec3(1.0));
    }
}

TEST_CASE("VTK legacy reader reads hand-written files in each layout", "[vtk][legacy]")
{
    TempDir dir("vtk-legacy");
    SECTION("ASCII version 5.1 with OFFSETS and CONNECTIVITY")
    {
        check_small_mesh(uvr::read_vtk_legacy(dir.write("v51.vtk", kAsciiV51)));
    }
    SECTION("ASCII old CELLS form, SCALARS without LOOKUP_TABLE, METADATA, skipped arrays")
    {
        const std::string text = ascii_old(kOldPoints, "CELLS 2 10\n4 0 1 2 3\n4 1 2 3 4\n", kOldTypes) +
                                 "CELL_DATA 2\nSCALARS id int 1\nLOOKUP_TABLE default\n7 8\n"
                                 "POINT_DATA 5\nSCALARS temperature double\n0.5 1 2 4 8\n"
                                 "METADATA\nINFORMATION 0\n\n"
                                 "NORMALS n float\n1 0 0 0 1 0 0 0 1 1 1 1 0 0 1\n"
                                 "TEXTURE_COORDINATES uv 2 float\n0 0 1 0 0 1 1 1 0.5 0.5\n"
                                 "FIELD FieldData 2\npressure 1 5 float\n5 4 3 2 1\nflow 2 5 float\n"
                                 "1 2 3 4 5 6 7 8 9 10\n";
        const auto d = uvr::read_vtk_legacy(dir.write("old.vtk", text));
        check_small_mesh(d);
        REQUIRE(d.mesh->fields.size() == 3);
        CHECK(d.mesh->fields[1].name == "pressure");
        CHECK(d.mesh->fields[1].values == std::vector<double>{5, 4, 3, 2, 1});
        // The cell scalars, one per tetrahedron (each cell is one).
        CHECK(d.mesh->fields[2].name == "id");
        CHECK(d.mesh->fields[2].association == uvr::FieldAssociation::cell);
        CHECK(d.mesh->fields[2].values == std::vector<double>{7, 8});
        CHECK_FALSE(has_warning(d, "CELL_DATA"));
        CHECK(has_warning(d, "'flow'"));
    }
    SECTION("BINARY big-endian, old CELLS form, with arrays and METADATA to skip around the data used")
    {
        const std::string text =
            binary_header("3.0") + "FIELD FieldData 2\nTIME 1 1 double\n" + be<double>({2.5}) +
            "\nname 1 1 string\n" + std::string("\xC5hello") + "\n" + binary_points() + "CELLS 2 10\n" +
            be<int32_t>({4, 0, 1, 2, 3, 4, 1, 2, 3, 4}) + "\nCELL_TYPES 2\n" + be<int32_t>({10, 10}) +
            "\nCELL_DATA 2\nSCALARS id int 1\nLOOKUP_TABLE default\n" + be<int32_t>({7, 8}) +
            "\nPOINT_DATA 5\nSCALARS temperature double 1\nLOOKUP_TABLE default\n" +
            be<double>({0.5, 1, 2, 4, 8}) + "\nVECTORS velocity float\n" + std::string(60, '\n') +
            "\nLOOKUP_TABLE mytable 2\n" + std::string(8, '\xFF') + "\nFIELD FieldData 2\npressure 1 5 float\n" +
            be<float>({5, 4, 3, 2, 1}) + "\nMETADATA\nINFORMATION 0\n\nflow 3 5 bit\n" + std::string(2, '\0') + "\n";
        const auto d = uvr::read_vtk_legacy(dir.write("binary.vtk", text));
        check_small_mesh(d);
        REQUIRE(d.mesh->fields.size() == 3);
        CHECK(d.mesh->fields[1].name == "pressure");
        CHECK(d.mesh->fields[1].values == std::vector<double>{5, 4, 3, 2, 1});
        // The cell scalars, one per tetrahedron (each cell is one).
        CHECK(d.mesh->fields[2].name == "id");
        CHECK(d.mesh->fields[2].association == uvr::FieldAssociation::cell);
        CHECK(d.mesh->fields[2].values == std::vector<double>{7, 8});
        CHECK_FALSE(has_warning(d, "CELL_DATA"));
        CHECK(has_warning(d, "'flow'"));
    }
    SECTION("BINARY version 5.1 with vtktypeint64 OFFSETS and CONNECTIVITY")
    {
        const std::string text = binary_header("5.1") + binary_points() + "CELLS 3 8\nOFFSETS vtktypeint64\n" +
                                 be<int64_t>({0, 4, 8}) + "\nCONNECTIVITY vtktypeint64\n" +
                                 be<int64_t>({0, 1, 2, 3, 1, 2, 3, 4}) + "\nCELL_TYPES 2\n" + be<int32_t>({10, 10}) +
                                 "\nPOINT_DATA 5\nSCALARS temperature double 1\nLOOKUP_TABLE default\n" +
                                 be<double>({0.5, 1, 2, 4, 8}) + "\n";
        check_small_mesh(uvr::read_vtk_legacy(dir.write("binary51.vtk", text)));
    }
    SECTION("ASCII STRUCTURED_POINTS volume with origin and spacing")
    {
        const std::string text = "# vtk DataFile Version 2.0\nvolume\nASCII\nDATASET STRUCTURED_POINTS\n"
                                 "DIMENSIONS 3 2 2\nORIGIN 1 2 3\nSPACING 0.5 0.25 2\nPOINT_DATA 12\n"
                                 "SCALARS density short 1\nLOOKUP_TABLE default\n0 1 2 3 4 5 6 7 8 9 10 -11\n";
        const auto d = uvr::read_vtk_legacy(dir.write("volume.vtk", text));
        REQUIRE(d.volume);
        CHECK(d.volume->dims == std::array<int64_t, 3>{3, 2, 2});
        CHECK(d.volume->origin == glm::dvec3(1, 2, 3));
        CHECK(d.volume->spacing == glm::dvec3(0.5, 0.25, 2));
        CHECK(d.volume->type == uvr::VoxelType::i16);
        CHECK(d.volume->name == "density");
        CHECK(d.volume->values == std::vector<float>{0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, -11});
    }
}

TEST_CASE("VTK legacy reader rejects bad input with a message naming the file", "[vtk][legacy][errors]")
{
    TempDir dir("vtk-legacy-bad");
    SECTION("truncated copies of binary post.vtk")
    {
        const std::string full = file_contents(data_path("vtk-data/post.vtk"));
        for (std::size_t cut : {full.find("POINTS ") + 30, full.find("CELLS ") + 1000, full.find("CELL_TYPES") + 500,
                                full.size() - 10}) {
            INFO("cut at byte " << cut);
            require_legacy_error(dir.write("post-cut.vtk", full.substr(0, cut)), "truncated");
        }
    }
    SECTION("truncated copies of ASCII tetraMesh.vtk")
    {
        const std::string full = file_contents(data_path("vtk-data/tetraMesh.vtk"));
        // Short remainders fail the size check before reading; longer ones run out while reading, some inside a number.
        const std::size_t points = full.find("POINTS "), cells = full.find("CELLS ");
        for (std::size_t cut : {points + 200, points + 1000, full.find('-', points + 600) + 1, cells + 300,
                                cells + 1700, full.size() - 10}) {
            INFO("cut at byte " << cut);
            require_legacy_error(dir.write("tetra-cut.vtk", full.substr(0, cut)), "truncated");
        }
    }
    SECTION("POINTS 55 but fewer points given")
    {
        std::string text = file_contents(data_path("vtk-data/tetraMesh.vtk"));
        const std::size_t first = text.find('\n', text.find("POINTS ")) + 1;
        text.erase(first, text.find('\n', first) + 1 - first);
        require_legacy_error(dir.write("few-points.vtk", text), "expected 165 point coordinates, found 'CELLS'");
    }
    SECTION("CELLS header claims more cells than its lists hold")
    {
        std::string text = file_contents(data_path("vtk-data/tetraMesh.vtk"));
        text.replace(text.find("CELLS 160 800"), 13, "CELLS 161 800");
        require_legacy_error(dir.write("cells-count.vtk", text), "the header says 161");
    }
    SECTION("CELLS size disagrees with its lists")
    {
        const std::string text = ascii_old(kOldPoints, "CELLS 2 10\n4 0 1 2 3\n3 1 2 3 4\n", kOldTypes);
        require_legacy_error(dir.write("cells-size.vtk", text), "CELLS size mismatch");
    }
    SECTION("CELL_TYPES count disagrees with CELLS")
    {
        const std::string text = ascii_old(kOldPoints, "CELLS 2 10\n4 0 1 2 3\n4 1 2 3 4\n", "CELL_TYPES 1\n10\n10\n");
        require_legacy_error(dir.write("types-count.vtk", text), "CELL_TYPES lists 1 cells but CELLS holds 2");
    }
    SECTION("negative point index")
    {
        const std::string text = ascii_old(kOldPoints, "CELLS 2 10\n4 0 1 2 3\n4 1 -2 3 4\n", kOldTypes);
        require_legacy_error(dir.write("negative.vtk", text), "uses point -2");
    }
    SECTION("point index out of range")
    {
        const std::string text = ascii_old(kOldPoints, "CELLS 2 10\n4 0 1 2 3\n4 1 2 3 5\n", kOldTypes);
        require_legacy_error(dir.write("range.vtk", text), "uses point 5");
    }
    SECTION("NaN coordinate")
    {
        const std::string points = "POINTS 5 float\n0 0 0\n1.5 nan 0\n0 2.25 0\n0 0 3.125\n1.5 2.25 3.125\n";
        const std::string text = ascii_old(points, "CELLS 2 10\n4 0 1 2 3\n4 1 2 3 4\n", kOldTypes);
        require_legacy_error(dir.write("nan.vtk", text), "point 1");
    }
    SECTION("wrong magic line")
    {
        require_legacy_error(dir.write("magic.vtk", "# VTK file\nx\nASCII\nDATASET UNSTRUCTURED_GRID\n"),
                             "not a VTK legacy file: first line must start with '# vtk DataFile Version'");
    }
    SECTION("neither ASCII nor BINARY")
    {
        require_legacy_error(dir.write("format.vtk", "# vtk DataFile Version 2.0\nx\nTEXT\nDATASET POLYDATA\n"),
                             "ASCII or BINARY");
    }
    SECTION("unsupported dataset type")
    {
        require_legacy_error(dir.write("poly.vtk", "# vtk DataFile Version 2.0\nx\nASCII\nDATASET POLYDATA\n"),
                             "unsupported dataset type polydata");
    }
    SECTION("unknown data type name")
    {
        const std::string text = ascii_old("POINTS 5 floot\n0 0 0\n", "", "");
        require_legacy_error(dir.write("type.vtk", text), "unknown data type 'floot'");
    }
    SECTION("unknown cell type 99")
    {
        const std::string text = ascii_old(kOldPoints, "CELLS 2 10\n4 0 1 2 3\n4 1 2 3 4\n", "CELL_TYPES 2\n10\n99\n");
        require_legacy_error(dir.write("celltype.vtk", text), "unknown cell type 99");
    }
    SECTION("a surface-only mesh")
    {
        const std::string text = ascii_old(kOldPoints, "CELLS 2 8\n3 0 1 2\n3 1 2 3\n", "CELL_TYPES 2\n5\n5\n");
        require_legacy_error(dir.write("surface.vtk", text), "no 3D cell");
    }
    SECTION("an empty file")
    {
        require_legacy_error(dir.write("empty.vtk", ""), "empty file");
    }
    SECTION("a header claiming 10^12 points in a tiny file fails before allocating")
    {
        for (const char* format : {"ASCII", "BINARY"}) {
            INFO(format);
            const std::string text = std::string("# vtk DataFile Version 3.0\nx\n") + format +
                                     "\nDATASET UNSTRUCTURED_GRID\nPOINTS 1000000000000 float\n0 0 0 1 1 1\n";
            require_legacy_error(dir.write("huge.vtk", text), "truncated: point coordinates needs 3000000000000");
        }
    }
    SECTION("a number where a keyword belongs")
    {
        const std::string text = ascii_old(kOldPoints, "CELLS 2 10\n4 0 1 2 3\n4 1 2 3 4\n", kOldTypes) +
                                 "POINT_DATA 5\nSCALARS t float 1\nLOOKUP_TABLE default\n1 2 3 4 5 6\n";
        require_legacy_error(dir.write("extra.vtk", text), "found the number '6' where a keyword was expected");
    }
}
