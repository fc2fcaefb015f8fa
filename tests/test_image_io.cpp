// Image files: .npy round trip, PNG compositing, atomic writes.
#include <cmath>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>

#include <sys/resource.h>

#include "reference/image.h"
#include "test_support.h"

using namespace uvr;
using uvr::test::require_input_error;
using uvr::test::TempDir;

TEST_CASE("an image written as .npy reads back bit for bit with its shape")
{
    TempDir tmp("npy");
    Image img(3, 2);
    for (std::size_t i = 0; i < img.rgba.size(); ++i) img.rgba[i] = float(i) * 0.1f - 0.3f;
    img.pixel(2, 1)[3] = std::nextafter(1.0f, 0.0f);
    write_image(tmp.file("a.npy"), img);
    const Image back = read_npy(tmp.file("a.npy"));
    CHECK(back.width == 3);
    CHECK(back.height == 2);
    CHECK(back.rgba == img.rgba);
    // The header is what numpy expects: version 1.0, total header a multiple of 64 bytes.
    const std::string raw = uvr::test::file_contents(tmp.file("a.npy"));
    CHECK(raw.substr(0, 6) == "\x93NUMPY");
    CHECK((raw.size() - img.rgba.size() * 4) % 64 == 0);
    CHECK_THAT(raw, Catch::Contains("'shape': (2, 3, 4)"));
}

TEST_CASE("an image written as .exr reads back bit for bit, special values included")
{
    TempDir tmp("exr");
    Image img(5, 3);
    for (std::size_t i = 0; i < img.rgba.size(); ++i) img.rgba[i] = float(i) * 0.0173f - 0.2f;
    // Values a half-float file would round or lose: they must come back with their bits (FLOAT channels).
    img.pixel(0, 0)[0] = std::nextafter(1.0f, 0.0f);
    img.pixel(1, 0)[1] = 1e-42f;  // subnormal
    img.pixel(2, 0)[2] = -0.0f;
    img.pixel(3, 0)[3] = 3.0e30f;
    img.pixel(4, 2)[0] = 1.0f + 0x1p-23f;
    write_image(tmp.file("a.exr"), img);
    bool alpha = false;
    const Image back = read_exr(tmp.file("a.exr"), &alpha);
    CHECK(alpha);
    REQUIRE(back.width == 5);
    REQUIRE(back.height == 3);
    for (std::size_t i = 0; i < img.rgba.size(); ++i) {
        INFO("value " << i);
        CHECK(std::memcmp(&back.rgba[i], &img.rgba[i], 4) == 0);
    }
    const OutsideImage o = read_outside_image(tmp.file("a.exr"));
    CHECK(!o.colour_only);
    CHECK(o.image.rgba == img.rgba);
}

TEST_CASE("an .exr that is cut short or is not OpenEXR is an error naming the file")
{
    TempDir tmp("exr-bad");
    Image img(16, 16);
    for (std::size_t i = 0; i < img.rgba.size(); ++i) img.rgba[i] = float(i % 97) / 97.0f;
    write_image(tmp.file("whole.exr"), img);
    const std::string whole = uvr::test::file_contents(tmp.file("whole.exr"));
    std::ofstream(tmp.file("cut.exr"), std::ios::binary) << whole.substr(0, whole.size() / 2);
    std::ofstream(tmp.file("text.exr"), std::ios::binary) << "not an exr";
    require_input_error([&] { read_outside_image(tmp.file("cut.exr")); }, {"cut.exr"});
    require_input_error([&] { read_outside_image(tmp.file("text.exr")); }, {"not a readable OpenEXR image"});
}

TEST_CASE("an outside image holding a value that is not finite is refused, naming the pixel")
{
    TempDir tmp("nonfinite");
    Image img(4, 3);
    img.pixel(2, 1)[1] = std::numeric_limits<float>::quiet_NaN();
    write_npy(tmp.file("nan.npy"), img);
    require_input_error([&] { read_outside_image(tmp.file("nan.npy")); }, {"pixel (2, 1) channel 1 is not finite"});
    img.pixel(2, 1)[1] = 0.0f;
    img.pixel(0, 2)[3] = std::numeric_limits<float>::infinity();
    write_image(tmp.file("inf.exr"), img);
    require_input_error([&] { read_outside_image(tmp.file("inf.exr")); }, {"pixel (0, 2) channel 3 is not finite"});
}

TEST_CASE("a PNG composites premultiplied colour over the background")
{
    TempDir tmp("png");
    Image img(1, 1);
    float* p = img.pixel(0, 0);
    p[0] = 0.25f;  // premultiplied red, alpha one half
    p[3] = 0.5f;
    write_image(tmp.file("a.png"), img, glm::dvec3(1.0, 0.0, 0.0));
    const std::string raw = uvr::test::file_contents(tmp.file("a.png"));
    CHECK(raw.substr(1, 3) == "PNG");
    // Red = 0.25 + 0.5 * 1 = 0.75 -> 191; decode by re-encoding the expected pixel and comparing the files.
    std::vector<unsigned char> expected{191, 0, 0};
    write_png_rgb8(tmp.file("b.png"), 1, 1, expected);
    CHECK(raw == uvr::test::file_contents(tmp.file("b.png")));
}

TEST_CASE("an output that cannot be written is an error and leaves nothing behind")
{
    TempDir tmp("unwritable");
    Image img(2, 2);
    require_input_error([&] { write_image(tmp.file("missing-dir/a.npy"), img); }, {"missing-dir/a.npy", "cannot write"});
    require_input_error([&] { write_image(tmp.file("a.tiff"), img); }, {"a.tiff", "unsupported image extension"});
    CHECK(std::filesystem::is_empty(tmp.file("")));
}

TEST_CASE("a write that runs out of space is an error, leaves nothing behind and keeps the old file")
{
    // A full disk, simulated by a file-size limit: past it write() fails (EFBIG once SIGXFSZ is ignored), the same
    // failure path as ENOSPC in write_file_atomically (fwrite or fclose fails, the temporary file is removed).
    TempDir tmp("full");
    Image small(2, 2), large(64, 64);
    small.pixel(0, 0)[0] = 0.5f;
    write_image(tmp.file("a.npy"), small);
    const std::string before = uvr::test::file_contents(tmp.file("a.npy"));
    rlimit old{};
    REQUIRE(getrlimit(RLIMIT_FSIZE, &old) == 0);
    auto* previous = std::signal(SIGXFSZ, SIG_IGN);
    rlimit tight = old;
    tight.rlim_cur = 4096;  // the large image's .npy is 65,664 bytes
    REQUIRE(setrlimit(RLIMIT_FSIZE, &tight) == 0);
    bool threw = false;
    std::string what;
    try {
        write_image(tmp.file("a.npy"), large);
    } catch (const InputError& e) {
        threw = true;
        what = e.what();
    }
    setrlimit(RLIMIT_FSIZE, &old);
    std::signal(SIGXFSZ, previous);
    INFO(what);
    CHECK(threw);
    CHECK(what.find("cannot write") != std::string::npos);
    CHECK(uvr::test::file_contents(tmp.file("a.npy")) == before);  // the old file is whole
    std::size_t files = 0;
    for (const auto& e : std::filesystem::directory_iterator(tmp.file(""))) files += e.is_regular_file() ? 1 : 0;
    CHECK(files == 1);  // no temporary left behind
}

TEST_CASE("a .npy that is not float32 RGBA is rejected")
{
    TempDir tmp("badnpy");
    require_input_error([&] { read_npy(tmp.write("x.npy", "not numpy at all")); }, {"x.npy", "not a .npy file"});
    Image img(2, 2);
    write_npy(tmp.file("t.npy"), img);
    const std::string whole = uvr::test::file_contents(tmp.file("t.npy"));
    require_input_error([&] { read_npy(tmp.write("cut.npy", whole.substr(0, whole.size() - 5))); },
                        {"cut.npy", "data bytes"});
}

TEST_CASE("the size option parses WxH and rejects anything else")
{
    int w = 0, h = 0;
    parse_size("640x480", w, h);
    CHECK(w == 640);
    CHECK(h == 480);
    require_input_error([&] { parse_size("640", w, h); }, {"--size must be WxH"});
    require_input_error([&] { parse_size("0x10", w, h); }, {"--size must be WxH"});
    require_input_error([&] { parse_size("10x10x", w, h); }, {"--size must be WxH"});
}
