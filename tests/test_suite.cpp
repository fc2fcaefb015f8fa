// The test programs themselves: they run the `uvr` program of their own build, and they know whether the sanitizers
// run (the sanitized build links the normal build's test objects, so neither can be fixed when they are compiled).
#include <catch2/catch.hpp>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "test_support.h"

namespace fs = std::filesystem;

TEST_CASE("a test program runs the uvr program of its own build directory")
{
    const fs::path uvr = uvr::test::uvr_binary();
    CHECK(fs::is_regular_file(uvr));
    const uvr::test::CommandResult r = uvr::test::run_uvr("--help");
    CHECK(r.exit_code == 0);
}

TEST_CASE("a test program knows whether it runs with the sanitizers, as its build says")
{
    // ctest states the build's setting (tests/CMakeLists.txt); the program finds out from what it is linked with.
    const char* build = std::getenv("UVR_SANITIZED_BUILD");
    REQUIRE(build != nullptr);
    CHECK(uvr::test::sanitized() == (std::string(build) == "ON"));
}
