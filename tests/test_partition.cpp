// Partitioned meshes: recursive coordinate bisection, the .vtu pieces and .pvtu file `uvr partition` writes, and
// reading them back as one mesh (docs/distributed.md).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "field_scenes.h"
#include "reference/builtin_mesh.h"
#include "reference/dataset.h"
#include "reference/partition.h"
#include "gpu/pipeline/segment.h"
#include "reference/write_vtk_xml.h"
#include "test_support.h"

using uvr::test::CommandResult;
using uvr::test::run_uvr;
using uvr::test::TempDir;

namespace {

glm::dvec3 centroid(const uvr::TetMesh& m, std::size_t c)
{
    const uvr::Tet& t = m.tets[c];
    return 0.25 * (m.points[t[0]] + m.points[t[1]] + m.points[t[2]] + m.points[t[3]]);
}

// Writes `mesh` in `parts` pieces as `uvr partition` does, and returns the .pvtu's path.
std::string write_partitioned(const uvr::TetMesh& mesh, uint32_t parts, const TempDir& dir)
{
    const std::vector<uint32_t> part_of = uvr::partition_rcb(mesh, parts);
    std::vector<std::string> pieces;
    for (uint32_t p = 0; p < parts; ++p) {
        pieces.push_back("piece_" + std::to_string(p) + ".vtu");
        uvr::write_vtu(dir.file(pieces.back()), uvr::extract_part(mesh, part_of, p));
    }
    uvr::write_pvtu(dir.file("mesh.pvtu"), mesh, pieces);
    return dir.file("mesh.pvtu");
}

// The pieces hold the parts' cells in mesh order, one part after the other: read back, tetrahedron i of the joined
// mesh is cell order[i] of the original. Each must have the same corners, point values and cell values, exactly.
void require_same_mesh(const uvr::TetMesh& original, const uvr::Dataset& read, uint32_t parts)
{
    const std::vector<uint32_t> part_of = uvr::partition_rcb(original, parts);
    std::vector<uint32_t> order;
    for (uint32_t p = 0; p < parts; ++p)
        for (uint32_t c = 0; c < original.tets.size(); ++c)
            if (part_of[c] == p) order.push_back(c);
    REQUIRE(read.mesh);
    const uvr::TetMesh& m = *read.mesh;
    REQUIRE(m.tets.size() == order.size());
    REQUIRE(m.fields.size() == original.fields.size());
    REQUIRE(read.piece_of_cell.size() == order.size());
    for (std::size_t i = 0; i < order.size(); ++i) {
        const uint32_t c = order[i];
        REQUIRE(read.piece_of_cell[i] == part_of[c]);
        for (int v = 0; v < 4; ++v) {
            REQUIRE(m.points[m.tets[i][v]] == original.points[original.tets[c][v]]);
            for (std::size_t f = 0; f < m.fields.size(); ++f)
                if (m.fields[f].association == uvr::FieldAssociation::point)
                    REQUIRE(m.fields[f].values[m.tets[i][v]] == original.fields[f].values[original.tets[c][v]]);
        }
        for (std::size_t f = 0; f < m.fields.size(); ++f) {
            REQUIRE(m.fields[f].name == original.fields[f].name);
            REQUIRE(m.fields[f].association == original.fields[f].association);
            if (m.fields[f].association == uvr::FieldAssociation::cell)
                REQUIRE(m.fields[f].values[i] == original.fields[f].values[c]);
        }
    }
}

std::vector<uint8_t> file_bytes(const std::string& path)
{
    const std::string s = uvr::test::file_contents(path);
    return {s.begin(), s.end()};
}

}  // namespace

TEST_CASE("rcb gives every part its share of the cells, separated by a plane, the same on every run")
{
    const uvr::TetMesh mesh = uvr::load_builtin("builtin:torus-small");
    for (uint32_t parts = 1; parts <= 7; ++parts) {
        const std::vector<uint32_t> part_of = uvr::partition_rcb(mesh, parts);
        CHECK(uvr::partition_rcb(mesh, parts) == part_of);
        std::vector<std::size_t> size(parts, 0);
        for (uint32_t p : part_of) {
            REQUIRE(p < parts);
            ++size[p];
        }
        // Each bisection level rounds one share down: sizes differ by at most one cell per level.
        const std::size_t levels = std::size_t(std::ceil(std::log2(double(parts))));
        INFO(parts << " parts");
        CHECK(*std::max_element(size.begin(), size.end()) - *std::min_element(size.begin(), size.end()) <= levels);
    }
    // Two parts: the torus's centroids span x and y alike, so the cut is normal to x (the lowest axis on a tie).
    const std::vector<uint32_t> halves = uvr::partition_rcb(mesh, 2);
    double left_max = -1e300, right_min = 1e300;
    for (std::size_t c = 0; c < mesh.tets.size(); ++c) {
        if (halves[c] == 0)
            left_max = std::max(left_max, centroid(mesh, c).x);
        else
            right_min = std::min(right_min, centroid(mesh, c).x);
    }
    CHECK(left_max <= right_min);
    CHECK_THROWS_WITH(uvr::partition_rcb(mesh, 0), Catch::Contains("cannot split 6904 tetrahedra into 0 parts"));
    CHECK_THROWS_WITH(uvr::partition_rcb(mesh, 6905), Catch::Contains("into 6905 parts"));
}

TEST_CASE("METIS gives parts within its size bound that cut fewer faces than rcb, the same on every run")
{
    const uvr::TetMesh mesh = uvr::load_builtin("builtin:torus-small");
    const uvr::MeshTopology topo = uvr::build_topology(mesh);
    auto cut_faces = [&](const std::vector<uint32_t>& part_of) {
        std::size_t cut = 0;
        for (const uvr::PartCounts& c : uvr::count_parts(topo, part_of)) cut += c.cut_faces;
        return cut / 2;  // each cut face is counted by both of its parts
    };
    for (uint32_t parts = 1; parts <= 6; ++parts) {
        INFO(parts << " parts");
        const std::vector<uint32_t> part_of = uvr::partition_metis(mesh, parts);
        CHECK(uvr::partition_metis(mesh, parts) == part_of);
        const std::vector<uvr::PartCounts> counts = uvr::count_parts(topo, part_of);
        REQUIRE(counts.size() == parts);
        const double bound = std::ceil(uvr::kMetisImbalance * double(mesh.tets.size()) / parts);
        for (const uvr::PartCounts& c : counts) {
            CHECK(c.tetrahedra > 0);
            CHECK(double(c.tetrahedra) <= bound);
        }
        if (parts > 1) CHECK(cut_faces(part_of) < cut_faces(uvr::partition_rcb(mesh, parts)));
    }
    CHECK_THROWS_WITH(uvr::partition_metis(mesh, 6905), Catch::Contains("into 6905 parts"));
}

TEST_CASE("a mesh written in pieces reads back from its .pvtu with the same cells, points and fields")
{
    SECTION("point data, per-cell vertex data and cell data")
    {
        for (const uvr::TetMesh& mesh :
             {uvr::load_builtin("builtin:torus-small"), uvr::test::two_cube_seam(), uvr::test::cell_data_box()}) {
            INFO(mesh.source);
            for (uint32_t parts : {1u, 2u, 5u}) {
                TempDir dir("pvtu");
                require_same_mesh(mesh, uvr::load_dataset(write_partitioned(mesh, parts, dir)), parts);
            }
        }
    }
    SECTION("the reference renders the pieces of Blunt Fin and the torus as it renders the whole, bit for bit")
    {
        const std::string bf = "'" + uvr::test::data_path("vtk-data/bluntfinxyz.bin") + "' --q '" +
                               uvr::test::data_path("vtk-data/bluntfinq.bin") + "'";
        for (const auto& [input, name] :
             {std::pair<std::string, std::string>{bf, "bluntfinxyz"}, {"builtin:torus-small", "torus-small"}}) {
            TempDir dir("pvtu-render");
            const std::string view = " --algo reference --size 96x80 --view 30,25 --out ";
            REQUIRE(run_uvr("render " + input + view + "'" + dir.file("whole.npy") + "'").exit_code == 0);
            for (const std::string method : {"rcb", "metis"}) {
                INFO(name << " by " << method);
                const std::string parts = dir.file(method);
                REQUIRE(run_uvr("partition " + input + " --parts 3 --method " + method + " --out '" + parts + "'")
                            .exit_code == 0);
                REQUIRE(run_uvr("render '" + parts + "/" + name + ".pvtu'" + view + "'" + parts + ".npy'").exit_code ==
                        0);
                CHECK(file_bytes(dir.file("whole.npy")) == file_bytes(parts + ".npy"));
            }
        }
    }
}

TEST_CASE("uvr info gives each part of a .pvtu its tetrahedra, boundary faces and cut faces")
{
    TempDir dir("pvtu-info");
    REQUIRE(run_uvr("partition builtin:torus-small --parts 2 --out '" + dir.file("p") + "'").exit_code == 0);
    const CommandResult r = run_uvr("info '" + dir.file("p/torus-small.pvtu") + "' --json");
    REQUIRE(r.exit_code == 0);
    const nlohmann::json j = nlohmann::json::parse(r.out);
    REQUIRE(j["parts"].size() == 2);
    const nlohmann::json& a = j["parts"][0];
    const nlohmann::json& b = j["parts"][1];
    CHECK(a["tetrahedra"].get<std::size_t>() + b["tetrahedra"].get<std::size_t>() == 6904);
    CHECK(a["boundary_faces"].get<std::size_t>() + b["boundary_faces"].get<std::size_t>() ==
          j["faces"]["boundary"].get<std::size_t>());
    // A face cut between two parts is a cut face of both.
    CHECK(a["cut_faces"] == b["cut_faces"]);
    CHECK(a["cut_faces"].get<std::size_t>() > 0);
    CHECK(j["format"]["pieces"].size() == 2);
}

TEST_CASE("a .pvtu with a missing piece, or pieces with different fields, is refused naming the file")
{
    TempDir dir("pvtu-bad");
    const std::string pvtu = write_partitioned(uvr::load_builtin("builtin:torus-small"), 3, dir);
    SECTION("a missing piece")
    {
        std::filesystem::remove(dir.file("piece_1.vtu"));
        const CommandResult r = run_uvr("info '" + pvtu + "'");
        CHECK(r.exit_code == 1);
        CHECK_THAT(r.err,
                   Catch::Contains(pvtu) && Catch::Contains("piece 1: " + dir.file("piece_1.vtu") + " does not exist"));
    }
    SECTION("a piece with other fields")
    {
        const uvr::TetMesh cells = uvr::test::cell_data_box();
        uvr::write_vtu(dir.file("piece_2.vtu"), cells);
        const CommandResult r = run_uvr("info '" + pvtu + "'");
        CHECK(r.exit_code == 1);
        CHECK_THAT(r.err, Catch::Contains("every piece must hold the same fields"));
    }
}

TEST_CASE("uvr partition refuses parts it cannot make, an unknown method and a regular grid, and writes nothing")
{
    TempDir dir("partition-bad");
    for (const std::string parts : {"0", "6905"}) {
        const CommandResult r =
            run_uvr("partition builtin:torus-small --parts " + parts + " --out '" + dir.file("out") + "'");
        CHECK(r.exit_code == 1);
        CHECK_THAT(r.err, Catch::Contains("cannot split 6904 tetrahedra into " + parts + " parts"));
    }
    const CommandResult method =
        run_uvr("partition builtin:torus-small --parts 2 --method kd --out '" + dir.file("out") + "'");
    CHECK(method.exit_code == 1);
    CHECK_THAT(method.err, Catch::Contains("--method must be rcb or metis, not 'kd'"));
    const CommandResult grid = run_uvr("partition builtin:torus-volume --parts 2 --out '" + dir.file("out") + "'");
    CHECK(grid.exit_code == 1);
    CHECK_THAT(grid.err, Catch::Contains("splits tetrahedral meshes, not regular grids"));
    CHECK(!std::filesystem::exists(dir.file("out")));
}

TEST_CASE("the extent a .pvtu records is its pieces' joined, bit for bit, and a malformed record is refused")
{
    TempDir dir("pvtu-extent");
    // A box with a cell field and a point field of values no short decimal holds.
    uvr::TetMesh box = uvr::test::cell_data_box();
    uvr::ScalarField point{"point", {}};
    for (const glm::dvec3& p : box.points) point.values.push_back(std::sin(1.0 + p.x) * std::exp(0.3 * p.y) / 3.0);
    box.fields.push_back(point);
    uvr::write_vtu(dir.file("box.vtu"), box);
    REQUIRE(run_uvr("partition '" + dir.file("box.vtu") + "' --parts 3 --out '" + dir.file("p") + "'").exit_code == 0);
    const std::string pvtu = dir.file("p/box.pvtu");
    const std::optional<uvr::WholeExtent> w = uvr::read_pvtu_whole_extent(pvtu);
    REQUIRE(w);
    // What one process computes from the pieces joined: the record must be exactly that.
    const uvr::TetMesh joined = *uvr::load_dataset(pvtu).mesh;
    const uvr::Bounds b = uvr::mesh_bounds(joined);
    CHECK(w->bounds.lo == b.lo);
    CHECK(w->bounds.hi == b.hi);
    CHECK(w->longest_edge == uvr::gpu::longest_tet_edge(joined));
    REQUIRE(w->ranges.size() == joined.fields.size());
    for (const uvr::ScalarField& f : joined.fields) {
        const auto r =
            std::find_if(w->ranges.begin(), w->ranges.end(), [&](const auto& e) { return e.first == f.name; });
        REQUIRE(r != w->ranges.end());
        CHECK(r->second.lo == uvr::field_range(f).lo);
        CHECK(r->second.hi == uvr::field_range(f).hi);
    }

    // uvr info gives the record as it reads it.
    const CommandResult info = run_uvr("info '" + pvtu + "' --json");
    REQUIRE(info.exit_code == 0);
    const nlohmann::json recorded = nlohmann::json::parse(info.out)["format"]["whole_extent"];
    CHECK(recorded["bounds"][0].get<double>() == b.lo.x);
    CHECK(recorded["bounds"][5].get<double>() == b.hi.z);
    CHECK(recorded["longest_edge"].get<double>() == w->longest_edge);
    CHECK(recorded["ranges"]["point"][1].get<double>() ==
          uvr::field_range(joined.fields[uvr::find_field(joined, "point")]).hi);

    const std::string text = uvr::test::file_contents(pvtu);
    // The line of the DataArray named `name`; its opening tag; the file with that line replaced by `line`.
    const auto line_of = [&](const std::string& name) {
        const std::size_t at = text.find("Name=\"" + name + "\"");
        REQUIRE(at != std::string::npos);
        const std::size_t begin = text.rfind('\n', at) + 1;
        return text.substr(begin, text.find('\n', at) + 1 - begin);
    };
    const auto opening = [&](const std::string& name) {
        const std::string line = line_of(name);
        return line.substr(0, line.find('>') + 1);
    };
    const auto with = [&](const std::string& name, const std::string& line) {
        std::string t = text;
        const std::string old = line_of(name);
        return t.replace(t.find(old), old.size(), line);
    };
    const std::string bounds = uvr::kWholeBoundsArray, edge = uvr::kWholeLongestEdgeArray,
                      cell_range = uvr::kWholeRangePrefix + std::string("cell"),
                      point_range = uvr::kWholeRangePrefix + std::string("point");
    std::string binary = opening(bounds);
    binary.replace(binary.find("ascii"), 5, "binary");
    const struct {
        std::string what, text, message;
    } bad[] = {
        {"five bounds", with(bounds, opening(bounds) + "0 0 0 1 1</DataArray>\n"), "must be 6 finite numbers"},
        {"bounds not in ASCII", with(bounds, binary + "AAAA</DataArray>\n"), "must be format=\"ascii\""},
        {"no longest edge", with(edge, ""), "without 'uvr whole longest edge'"},
        {"no range of a field", with(point_range, ""), "no range of field 'point'"},
        {"a range that is not a number", with(cell_range, opening(cell_range) + "0 nan</DataArray>\n"),
         "must be 2 finite numbers"},
    };
    for (const auto& c : bad) {
        INFO(c.what);
        dir.write("p/box.pvtu", c.text);
        const CommandResult r = run_uvr("info '" + pvtu + "'");
        CHECK(r.exit_code == 1);
        CHECK_THAT(r.err, Catch::Contains(pvtu) && Catch::Contains(c.message));
    }
}
