// `uvr export` and the VTK legacy writers behind it (reference/write_vtk.h): what a peer renders must be exactly what
// uvr renders, so each written file is read back with uvr's own reader and compared value for value.
#include <cmath>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "reference/builtin_mesh.h"
#include "reference/dataset.h"
#include "reference/write_vtk.h"
#include "test_support.h"
#include "volume_scenes.h"

using namespace uvr;
using test::data_path;
using test::run_uvr;
using test::TempDir;

TEST_CASE("an exported volume reads back as the same samples, origin and spacing")
{
    TempDir tmp("export-volume");
    SECTION("a float grid of odd spacing and negative values")
    {
        // Spacings and an origin that print with 17 digits, values that no decimal text would keep.
        const Volume v = test::grid({5, 4, 3}, {-1.0 / 3.0, 0.1, 1e-7}, {0.7, 1.0 / 7.0, 2.5},
                                    [](const glm::dvec3& p) { return std::sin(p.x * 3.0) - p.y * p.z / 3.0; });
        write_vtk_legacy(tmp.file("v.vtk"), v);
        const Dataset d = load_dataset(tmp.file("v.vtk"));
        REQUIRE(d.volume);
        CHECK(d.volume->dims == v.dims);
        CHECK(d.volume->origin == v.origin);
        CHECK(d.volume->spacing == v.spacing);
        CHECK(d.volume->values == v.values);
    }
    SECTION("neghip, 8-bit in its file")
    {
        const Volume v = *load_dataset(data_path("vtk-data/neghip.slc")).volume;
        write_vtk_legacy(tmp.file("n.vtk"), v);
        const Dataset d = load_dataset(tmp.file("n.vtk"));
        REQUIRE(d.volume);
        CHECK(d.volume->dims == v.dims);
        CHECK(d.volume->values == v.values);
    }
}

TEST_CASE("an exported mesh reads back as the same points, tetrahedra and field")
{
    TempDir tmp("export-mesh");
    const TetMesh m = load_builtin("builtin:torus-small");
    write_vtk_legacy(tmp.file("m.vtk"), m, 0);
    const Dataset d = load_dataset(tmp.file("m.vtk"));
    REQUIRE(d.mesh);
    CHECK(d.mesh->points == m.points);
    CHECK(d.mesh->tets == m.tets);
    REQUIRE(!d.mesh->fields.empty());
    CHECK(d.mesh->fields[0].values == m.fields[0].values);
}

TEST_CASE("uvr export writes a volume's scene for the peers")
{
    TempDir tmp("export-cli");
    const test::CommandResult r =
        run_uvr("export '" + data_path("vtk-data/hydrogen.vti") + "' --size 64x48 --out '" + tmp.file("scene") + "'");
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    for (const char* f : {"volume.vtk", "tf.json", "camera.json", "scene.json"})
        CHECK(std::filesystem::exists(tmp.file(std::string("scene/") + f)));
    CHECK(!std::filesystem::exists(tmp.file("scene/mesh.vtk")));
    const auto j = nlohmann::json::parse(test::file_contents(tmp.file("scene/scene.json")));
    CHECK(j["kind"] == "volume");
    CHECK(j["width"] == 64);
    CHECK(j["height"] == 48);
    CHECK(j["voxels"] == 64 * 64 * 64);
    CHECK(j["default_step"] == 0.5);  // half of hydrogen's unit spacing
}
