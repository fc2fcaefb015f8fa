// Transfer-function files (docs/spec.md §1) and their evaluation.
#include <cmath>

#include "reference/transfer_function.h"
#include "test_support.h"

using namespace uvr;
using uvr::test::require_input_error;

TEST_CASE("colour and extinction are piecewise linear and constant beyond the end nodes")
{
    const TransferFunction tf = parse_transfer_function(
        R"({"color": [[0, 0, 0, 0], [1, 1, 0.5, 0], [3, 0, 1, 1]], "extinction": [[1, 2], [2, 4]]})", "tf.json");
    CHECK(tf.color_at(-5.0).x == 0.0);
    CHECK(tf.color_at(0.5).x == 0.5);
    CHECK(tf.color_at(0.5).y == 0.25);
    CHECK(tf.color_at(2.0).x == 0.5);
    CHECK(tf.color_at(2.0).z == 0.5);
    CHECK(tf.color_at(9.0).z == 1.0);
    CHECK(tf.tau_at(0.0) == 2.0);
    CHECK(tf.tau_at(1.5) == 3.0);
    CHECK(tf.tau_at(7.0) == 4.0);
    CHECK(tf.breakpoints() == std::vector<double>{0.0, 1.0, 2.0, 3.0});
}

TEST_CASE("opacity with a unit distance converts to extinction per node")
{
    const TransferFunction tf =
        parse_transfer_function(R"({"color": [[0, 1, 1, 1]], "opacity": [[0, 0], [1, 0.5]], "unit_distance": 2})",
                                "tf.json");
    CHECK(tf.tau_at(0.0) == 0.0);
    CHECK(tf.tau_at(1.0) == Approx(std::log(2.0) / 2.0).epsilon(1e-15));
}

TEST_CASE("a ParaView RGBPoints preset is accepted for the colour")
{
    const TransferFunction tf = parse_transfer_function(
        R"({"color": [{"Name": "x", "RGBPoints": [0, 0, 0, 0, 10, 1, 1, 1]}], "extinction": [[0, 1]]})", "tf.json");
    CHECK(tf.color.size() == 2);
    CHECK(tf.color_at(5.0).y == 0.5);
    const TransferFunction tf2 =
        parse_transfer_function(R"({"RGBPoints": [0, 0, 0, 0, 10, 1, 1, 1], "extinction": [[0, 1]]})", "tf.json");
    CHECK(tf2.color_at(10.0).z == 1.0);
}

TEST_CASE("malformed transfer functions are errors that name the file and the problem")
{
    SECTION("JSON syntax error gives the line")
    {
        require_input_error([] { parse_transfer_function("{\n\"color\": [[0,1,1,1]],\n oops }", "tf.json"); },
                            {"tf.json:3", "invalid JSON"});
    }
    SECTION("unsorted nodes")
    {
        require_input_error(
            [] { parse_transfer_function(R"({"color": [[1,0,0,0],[0,1,1,1]], "extinction": [[0,1]]})", "tf.json"); },
            {"tf.json", "out of order"});
    }
    SECTION("negative extinction")
    {
        require_input_error(
            [] { parse_transfer_function(R"({"color": [[0,0,0,0]], "extinction": [[0,-1]]})", "tf.json"); },
            {"tf.json", "extinction must be >= 0"});
    }
    SECTION("colour outside [0, 1]")
    {
        require_input_error(
            [] { parse_transfer_function(R"({"color": [[0,2,0,0]], "extinction": [[0,1]]})", "tf.json"); },
            {"tf.json", "outside [0, 1]"});
    }
    SECTION("opacity of 1 would be infinite extinction")
    {
        require_input_error(
            [] {
                parse_transfer_function(R"({"color": [[0,0,0,0]], "opacity": [[0,1]], "unit_distance": 1})",
                                        "tf.json");
            },
            {"tf.json", "opacity must be in [0, 1)"});
    }
    SECTION("missing extinction")
    {
        require_input_error([] { parse_transfer_function(R"({"color": [[0,0,0,0]]})", "tf.json"); },
                            {"tf.json", "missing \"extinction\""});
    }
    SECTION("missing file")
    {
        require_input_error([] { load_transfer_function("/nonexistent/tf.json"); },
                            {"/nonexistent/tf.json", "cannot open"});
    }
}

TEST_CASE("the default transfer function spans the range and scales with the mesh size")
{
    const TransferFunction a = default_transfer_function({2.0, 4.0}, 1.0);
    const TransferFunction b = default_transfer_function({2.0, 4.0}, 10.0);
    CHECK(a.color.front().s == 2.0);
    CHECK(a.color.back().s == 4.0);
    double max_a = 0.0;
    for (const auto& n : a.extinction) max_a = std::max(max_a, n.tau);
    CHECK(max_a == Approx(kDefaultOpticalDepth));
    CHECK(b.tau_at(3.0) == Approx(a.tau_at(3.0) / 10.0));
    // It round-trips through its own JSON.
    const TransferFunction c = parse_transfer_function(transfer_function_json(a), "roundtrip");
    CHECK(c.tau_at(2.7) == a.tau_at(2.7));
}

TEST_CASE("the default transfer function of a regular grid is transparent around its dominant background value")
{
    const uvr::Range range{0.0, 100.0};
    const double diagonal = 10.0;
    const uvr::TransferFunction plain = uvr::default_transfer_function(range, diagonal);
    SECTION("background at the bottom of the range (air around a scan)")
    {
        std::vector<float> values(9000, 2.0f);  // 90 % background in the bin [1.95, 2.34)
        for (int i = 0; i < 1000; ++i) values.push_back(float(10 + i % 90));
        const uvr::TransferFunction tf = uvr::default_volume_transfer_function(values, range, diagonal);
        // The background bin and kBackgroundMargin (2 of 100) beyond it on each side: no extinction.
        for (double s : {0.0, 1.0, 2.0, 2.3, 4.2}) {
            INFO("s = " << s);
            CHECK(tf.tau_at(s) == 0.0);
        }
        // Beyond the ramp (another 2) the default's extinction, at the default's own nodes and on the sampled grid,
        // raised by f^(-1/3): the 1,000 values at 10 and above are all fully visible, so f = 1000 / 10000.
        const double boost = std::cbrt(10000.0 / 1000.0);
        for (double s : {10.0, 30.0, 55.0, 80.0, 100.0}) {
            INFO("s = " << s);
            CHECK(tf.tau_at(s) == Approx(plain.tau_at(s) * boost).epsilon(1e-12));
            CHECK(tf.tau_at(s) > 0.0);
        }
        // The colours: the default's ramp without its near-black first node, over the whole range.
        REQUIRE(tf.color.size() == plain.color.size() - 1);
        CHECK(tf.color_at(0.0) == plain.color_at(25.0));
        CHECK(tf.color_at(100.0) == plain.color_at(100.0));
    }
    SECTION("a few specks in the background: the boost stops at kMinVisibleFraction")
    {
        std::vector<float> values(19950, 2.0f);  // 0.25 % visible, below 1/64
        for (int i = 0; i < 50; ++i) values.push_back(float(40 + i));
        const uvr::TransferFunction tf = uvr::default_volume_transfer_function(values, range, diagonal);
        const double most = std::cbrt(1.0 / uvr::kMinVisibleFraction);
        CHECK(most == Approx(4.0));
        CHECK(tf.tau_at(55.0) == Approx(plain.tau_at(55.0) * most).epsilon(1e-12));
    }
    SECTION("background at the top of the range (an inverted scan)")
    {
        std::vector<float> values(9000, 99.5f);
        for (int i = 0; i < 1000; ++i) values.push_back(float(i % 90));
        const uvr::TransferFunction tf = uvr::default_volume_transfer_function(values, range, diagonal);
        CHECK(tf.tau_at(99.5) == 0.0);
        CHECK(tf.tau_at(100.0) == 0.0);
        CHECK(tf.tau_at(30.0) == Approx(plain.tau_at(30.0) * std::cbrt(10.0)).epsilon(1e-12));
    }
}

TEST_CASE("the default transfer function of a regular grid has a node only where its extinction bends")
{
    // Every node is a breakpoint the reference and the exact segments split at, so a node between two collinear ones
    // costs time and changes nothing. Slopes of consecutive intervals are compared to 1e-9 of the larger: the nodes'
    // values carry double rounding (1e-16), a kink of the default or of the window changes the slope by order one.
    constexpr double kSameSlope = 1e-9;
    const uvr::Range range{0.0, 100.0};
    const double diagonal = 10.0;
    const uvr::TransferFunction plain = uvr::default_transfer_function(range, diagonal);
    for (const float background : {2.0f, 47.3f, 99.5f}) {
        std::vector<float> values(9000, background);
        for (int i = 0; i < 1000; ++i) values.push_back(float(i % 100));
        const uvr::TransferFunction tf = uvr::default_volume_transfer_function(values, range, diagonal);
        const auto& n = tf.extinction;
        std::size_t collinear = 0;
        for (std::size_t i = 1; i + 1 < n.size(); ++i) {
            if (!(n[i - 1].s < n[i].s && n[i].s < n[i + 1].s)) continue;  // a jump's two nodes
            const double before = (n[i].tau - n[i - 1].tau) / (n[i].s - n[i - 1].s);
            const double after = (n[i + 1].tau - n[i].tau) / (n[i + 1].s - n[i].s);
            if (std::abs(before - after) <= kSameSlope * std::max(std::abs(before), std::abs(after))) ++collinear;
        }
        INFO("background " << background << ": " << n.size() << " nodes, " << collinear << " between collinear ones");
        CHECK(collinear == 0);
        // Away from the window's ramps the extinction is the default's times the boost, between the nodes too.
        const double boost = tf.tau_at(30.0) / plain.tau_at(30.0);
        for (double s = 0.0; s <= 100.0; s += 0.25)
            if (std::abs(s - background) > 5.0) {
                INFO("s = " << s);
                CHECK(tf.tau_at(s) == Approx(plain.tau_at(s) * boost).epsilon(1e-12));
            }
    }
}

TEST_CASE("a colour preset (--tf preset:NAME) puts a ParaView colour map on the default extinction, by either name")
{
    const uvr::Range range{-1.0, 3.0};
    const uvr::TransferFunction plain = uvr::default_transfer_function(range, 2.0);
    const uvr::TransferFunction gray = uvr::with_colour_preset(plain, range, "Grayscale");
    CHECK(gray.color_at(-1.0) == glm::dvec3(0.0));
    CHECK(gray.color_at(3.0) == glm::dvec3(1.0));
    CHECK(gray.color_at(1.0).x == Approx(0.5));
    CHECK(gray.tau_at(0.2) == plain.tau_at(0.2));  // the extinction is untouched
    const uvr::TransferFunction warm = uvr::with_colour_preset(plain, range, "cool-to-warm");
    const uvr::TransferFunction warm_pv = uvr::with_colour_preset(plain, range, "COOL TO WARM");
    CHECK(warm.color_at(0.7) == warm_pv.color_at(0.7));
    CHECK(warm.color_at(1.0).x == Approx(0.865));  // Moreland's map is grey in the middle
    CHECK(uvr::colour_preset_names().size() == 6);
    CHECK_THROWS_WITH(uvr::with_colour_preset(plain, range, "rainbowish"),
                      Catch::Matchers::Contains("unknown colour preset 'rainbowish'") &&
                          Catch::Matchers::Contains("viridis"));
}
