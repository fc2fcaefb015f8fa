// The CPU features the emulation assumes of llvmpipe, decided as Mesa 22.3 decides them (gpu/pipeline/llvmpipe_cpu.h):
// the rule against Mesa's table of GALLIUM_OVERRIDE_CPU_CAPS values, and whole frames of every algorithm, emulated and
// on GL, under the overrides a user may set: the same bits, where ignoring the override would fuse what llvmpipe no
// longer fuses.
#include <string>

#include <catch2/catch.hpp>

#include "gpu/pipeline/llvmpipe_cpu.h"
#include "test_support.h"

using namespace uvr;
using namespace uvr::gpu;

namespace {

constexpr CpuCaps kEveryFeature{true, true, true, true};

bool same(const CpuCaps& a, const CpuCaps& b)
{
    return a.ssse3 == b.ssse3 && a.sse4_1 == b.sse4_1 && a.avx == b.avx && a.fma == b.fma;
}

}  // namespace

TEST_CASE("llvmpipe's CPU features follow Mesa's rule for GALLIUM_OVERRIDE_CPU_CAPS and GALLIUM_NOSSE")
{
    // src/util/u_cpu_detect.c (Mesa 22.3): a value clears one feature and the cascade every later one.
    SECTION("values that take nothing the emulation models: unset, avx, unknown spellings")
    {
        for (const char* v : {static_cast<const char*>(nullptr), "avx", "AVX2", "nofma", "sse4_1", ""})
            CHECK(same(mesa_cpu_caps(kEveryFeature, v, nullptr), kEveryFeature));
    }
    SECTION("sse4.1 takes AVX and with it FMA")
    {
        CHECK(same(mesa_cpu_caps(kEveryFeature, "sse4.1", nullptr), CpuCaps{true, true, false, false}));
    }
    SECTION("ssse3 takes SSE4.1 and everything after it")
    {
        CHECK(same(mesa_cpu_caps(kEveryFeature, "ssse3", nullptr), CpuCaps{true, false, false, false}));
    }
    SECTION("sse3 and below take SSSE3 too")
    {
        for (const char* v : {"sse3", "sse2", "sse", "nosse"})
            CHECK(same(mesa_cpu_caps(kEveryFeature, v, nullptr), CpuCaps{}));
    }
    SECTION("GALLIUM_NOSSE as Mesa reads a boolean")
    {
        for (const char* v : {"1", "true", "yes", "y"})
            CHECK(same(mesa_cpu_caps(kEveryFeature, nullptr, v), CpuCaps{}));
        for (const char* v : {"0", "n", "no", "f", "F", "false", "FALSE"})
            CHECK(same(mesa_cpu_caps(kEveryFeature, nullptr, v), kEveryFeature));
    }
    SECTION("FMA counts only with AVX, as Mesa detects it")
    {
        CHECK(!mesa_cpu_caps(CpuCaps{true, true, false, true}, nullptr, nullptr).fma);
    }
}

TEST_CASE("frames under GALLIUM_OVERRIDE_CPU_CAPS and LP_NATIVE_VECTOR_WIDTH: emulated and GL the same bits")
{
    using test::run_uvr;
    test::TempDir tmp("cpu-caps");
    const auto frame = [&](const std::string& env, const std::string& algo, const std::string& backend) {
        const std::string source = algo == "raycast" ? "builtin:torus-volume" : "builtin:torus-small";
        const std::string out = tmp.file(algo + "-" + backend + "-" + std::to_string(env.size()) + ".npy");
        const test::CommandResult r = run_uvr("render " + source + " --size 96x80 --view 35,40 --no-cache --algo " +
                                                  algo + " --backend " + backend + " --out '" + out + "'",
                                              env);
        INFO(env << " " << algo << " " << backend << ": " << r.err);
        REQUIRE(r.exit_code == 0);
        return test::file_contents(out);
    };
    const bool host_fuses = llvmpipe_cpu_caps().fma;  // this process's environment sets no override
    for (const char* algo : {"havs", "vicp", "raycast"}) {
        INFO(algo);
        const std::string unfused = "GALLIUM_OVERRIDE_CPU_CAPS=sse4.1";
        CHECK(frame(unfused, algo, "emu") == frame(unfused, algo, "gl"));
        // Where the CPU fuses, taking FMA away changes the frame: an emulation that ignored the override would miss.
        if (host_fuses) CHECK(frame(unfused, algo, "emu") != frame("", algo, "emu"));
        const std::string narrow = "LP_NATIVE_VECTOR_WIDTH=128";
        CHECK(frame(narrow, algo, "emu") == frame(narrow, algo, "gl"));
    }
}

TEST_CASE("an override that takes SSSE3 or SSE4.1 from llvmpipe is refused by the emulation, named")
{
    test::TempDir tmp("cpu-caps-refused");
    for (const char* v : {"ssse3", "sse3", "sse2"}) {
        const test::CommandResult r =
            test::run_uvr("render builtin:torus-small --size 32x32 --algo havs --out '" + tmp.file("x.npy") + "'",
                          std::string("GALLIUM_OVERRIDE_CPU_CAPS=") + v);
        INFO(v << ": " << r.err);
        CHECK(r.exit_code == 1);
        CHECK_THAT(r.err,
                   Catch::Contains(std::string("GALLIUM_OVERRIDE_CPU_CAPS=") + v) && Catch::Contains("does not model"));
    }
    const test::CommandResult nosse = test::run_uvr(
        "render builtin:torus-small --size 32x32 --algo vicp --out '" + tmp.file("y.npy") + "'", "GALLIUM_NOSSE=1");
    CHECK(nosse.exit_code == 1);
    CHECK_THAT(nosse.err, Catch::Contains("GALLIUM_NOSSE"));
}
