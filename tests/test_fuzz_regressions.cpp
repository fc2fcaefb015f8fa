// Regression tests for what fuzzing the readers found (tests/fuzz/, scripts/fuzz.sh, docs/robustness.md): each input is
// the smallest form of the finding, written by the test, and each test checks that the reader now fails with an
// InputError (and nothing worse: under -DUVR_SANITIZE=ON a sanitizer report fails the test).
#include <cmath>

#include <catch2/catch.hpp>

#include "reference/camera.h"
#include "reference/dataset.h"
#include "reference/transfer_function.h"
#include "test_support.h"

using namespace uvr;
using uvr::test::require_input_error;
using uvr::test::TempDir;

// A .vti WholeExtent of "inf inf": inf - inf is NaN, which passed the range check and was then converted to an
// integer dimension (undefined behaviour, reported by UBSan as "-nan is outside the range of representable values").
TEST_CASE("fuzz: a .vti WholeExtent with infinite bounds is refused", "[fuzz]")
{
    TempDir dir("fuzz-vti");
    for (const char* extent : {"inf inf 0 0 0 0", "0 0 -inf -inf 0 0", "0 0 0 0 nan nan", "-inf inf 0 0 0 0"}) {
        const std::string path = dir.write("inf.vti", std::string("<VTKFile type=\"ImageData\"><ImageData WholeExtent=\"") +
                                                          extent + "\"><Piece><PointData><DataArray type=\"UInt8\" "
                                                                   "format=\"ascii\">1</DataArray></PointData></Piece>"
                                                                   "</ImageData></VTKFile>");
        INFO("WholeExtent " << extent);
        require_input_error([&] { read_vtk_xml(path); }, {"WholeExtent must hold integer ranges"});
    }
}

// A camera whose eye and target are so far apart that |target - eye| overflows: validate_camera accepted it (the NaN
// cross product compared false with the parallel threshold) and camera_frame gave a NaN frame.
TEST_CASE("fuzz: a camera whose eye-target distance overflows is refused", "[fuzz]")
{
    require_input_error([] { parse_camera(R"({"eye": [1e308, 0, 0], "target": [-1e308, 0, 0]})", "c.json"); },
                        {"c.json", "too far apart"});
    require_input_error([] { parse_camera(R"({"eye": [0, 0, 1e200], "target": [0, 0, -1e200]})", "c.json"); },
                        {"too far apart"});
    // Far, but not overflowing: still a usable camera.
    const Camera cam = parse_camera(R"({"eye": [0, 0, 1e150], "target": [0, 0, -1e150]})", "c.json");
    const CameraFrame fr = camera_frame(cam);
    CHECK(std::isfinite(fr.r.x));
    CHECK(fr.f.z == Approx(-1.0));
}

// An opacity node with a tiny unit_distance: -ln(1 - a) / u overflowed to an infinite extinction that was accepted.
TEST_CASE("fuzz: an opacity transfer function whose extinction overflows is refused", "[fuzz]")
{
    require_input_error(
        [] {
            parse_transfer_function(R"({"color": [[0, 1, 1, 1]], "opacity": [[0, 0.5]], "unit_distance": 1e-310})",
                                    "tf.json");
        },
        {"tf.json", "infinite extinction"});
    const TransferFunction tf =
        parse_transfer_function(R"({"color": [[0, 1, 1, 1]], "opacity": [[0, 0.5]], "unit_distance": 1e-300})", "t");
    CHECK(std::isfinite(tf.tau_at(0.0)));
}

// A NRRD "data file" series was expanded into one name per file before anything was read, so a 40-byte header made the
// reader build 10^8 strings (gigabytes, seconds) before it found that the first file does not exist. The names are now
// made one at a time as the files are read.
TEST_CASE("fuzz: a NRRD data file series of 10^8 files fails fast", "[fuzz]")
{
    TempDir dir("fuzz-nrrd");
    const std::string path = dir.write("series.nrrd", "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 1000 1000 1000\n"
                                                      "encoding: raw\ndata file: a%d 1 100000000 1\n");
    require_input_error([&] { read_nrrd(path); }, {"a1"});
}

// A JSON number too large for a double ("1e400"): nlohmann::json throws out_of_range (406), not parse_error, so the
// exception escaped parse_camera and parse_transfer_function as something other than an InputError.
TEST_CASE("fuzz: a JSON number that overflows a double is an InputError", "[fuzz]")
{
    require_input_error([] { parse_camera("1e316", "c.json"); }, {"c.json", "invalid JSON", "number overflow"});
    require_input_error([] { parse_camera(R"({"eye": [1e400, 0, 0], "target": [0, 0, 0]})", "c.json"); },
                        {"invalid JSON"});
    require_input_error([] { parse_transfer_function("1e316", "tf.json"); }, {"tf.json", "invalid JSON"});
    require_input_error(
        [] { parse_transfer_function(R"({"color": [[0, 1, 1, 1]], "extinction": [[0, 9.1e400]]})", "tf.json"); },
        {"invalid JSON"});
}
