// The reports as a reader sees them: Debian's chromium loads each page headless from the file system, and every image
// must load with no script error; a screenshot is taken as a person would look at it.
#include <cstdlib>
#include <filesystem>

#include "test_support.h"

using uvr::test::run_uvr;
using uvr::test::TempDir;

namespace {

struct BrowserResult {
    int exit_code = -1;
    std::string dom, log;
};

// Loads `page` in headless chromium (flags as this workplace's closed network needs them), dumps the DOM after the
// load event, and writes a screenshot.
BrowserResult load_page(const TempDir& tmp, const std::string& page, const std::string& screenshot)
{
    const std::string flags = "--headless --no-sandbox --disable-gpu --disable-quic --no-first-run "
                              "--disable-background-networking --disable-component-update --disable-sync "
                              "--allow-file-access-from-files --virtual-time-budget=10000 --user-data-dir='" +
                              tmp.file("profile") + "'";
    const std::string url = "file://" + page;
    BrowserResult r;
    const std::string dom = tmp.file("dom.html"), log = tmp.file("browser.log");
    r.exit_code = std::system(("chromium " + flags + " --enable-logging=stderr --v=0 --dump-dom '" + url + "' > '" +
                               dom + "' 2> '" + log + "'").c_str());
    r.dom = uvr::test::file_contents(dom);
    r.log = uvr::test::file_contents(log);
    std::system(("chromium " + flags + " --window-size=1400,1000 --screenshot='" + screenshot + "' '" + url +
                 "' > /dev/null 2>&1").c_str());
    return r;
}

void check_page(const TempDir& tmp, const std::string& page, const std::string& shot)
{
    INFO(page);
    REQUIRE(std::system("command -v chromium > /dev/null") == 0);  // installed by scripts/install-deps.sh
    const BrowserResult r = load_page(tmp, page, shot);
    INFO("browser log:\n" << r.log);
    CHECK(r.exit_code == 0);
    CHECK_THAT(r.dom, Catch::Contains("data-loaded=\"yes\""));
    CHECK_THAT(r.dom, Catch::Contains("data-broken=\"\""));
    CHECK_THAT(r.dom, !Catch::Contains("data-images=\"0\""));
    CHECK_THAT(r.log, !Catch::Contains("Uncaught"));
    CHECK(std::filesystem::exists(shot));
    CHECK(std::filesystem::file_size(shot) > 10000);
}

}  // namespace

TEST_CASE("the compare and sweep pages load in a real browser with every image and no script error")
{
    TempDir tmp("browser");
    setenv("UVR_CACHE_DIR", tmp.file("cache").c_str(), 1);
    const auto c = run_uvr("compare builtin:torus-small --algos reference,havs --size 96x96 --report '" +
                           tmp.file("compare") + "'");
    REQUIRE(c.exit_code == 0);
    const auto s = run_uvr("sweep builtin:torus-small --k 1,4 --size 64x64 --report '" + tmp.file("sweep") + "'");
    INFO(s.err);
    REQUIRE(s.exit_code == 0);
    SECTION("compare") { check_page(tmp, tmp.file("compare/index.html"), tmp.file("compare.png")); }
    SECTION("sweep (with its matplotlib plots)") { check_page(tmp, tmp.file("sweep/index.html"), tmp.file("sweep.png")); }
    SECTION("a page whose image is missing is caught")
    {
        std::filesystem::remove(tmp.file("compare/havs-emu-k6-error.png"));
        const BrowserResult r = load_page(tmp, tmp.file("compare/index.html"), tmp.file("broken.png"));
        CHECK_THAT(r.dom, Catch::Contains("havs-emu-k6-error.png\""));
        CHECK_THAT(r.dom, !Catch::Contains("data-broken=\"\""));
    }
    unsetenv("UVR_CACHE_DIR");
}

TEST_CASE("the budget page loads in a real browser with its chart, every error map and no script error")
{
    TempDir tmp("browser-budget");
    setenv("UVR_CACHE_DIR", tmp.file("cache").c_str(), 1);
    const auto b = run_uvr("budget builtin:torus-small --algo vicp --size 64x64 --report '" + tmp.file("budget") + "'");
    INFO(b.err);
    REQUIRE(b.exit_code == 0);
    REQUIRE(std::filesystem::exists(tmp.file("budget/budget.svg")));
    check_page(tmp, tmp.file("budget/index.html"), tmp.file("budget.png"));
    // The table, the chart, and the error map and image of every run: baseline, five factors, total.
    const std::string html = uvr::test::file_contents(tmp.file("budget/index.html"));
    CHECK_THAT(html, Catch::Contains("src=\"budget.svg\""));
    for (const char* run : {"baseline", "sort", "table", "interpolation", "coverage", "termination", "total"}) {
        INFO(run);
        CHECK_THAT(html, Catch::Contains(std::string("src=\"runs/") + run + "-error.png\""));
        CHECK_THAT(html, Catch::Contains(std::string("src=\"runs/") + run + ".png\""));
    }
    unsetenv("UVR_CACHE_DIR");
}

TEST_CASE("uvr demo's landing page loads in a real browser with every link's page and every image present")
{
    TempDir tmp("browser-demo");
    setenv("UVR_CACHE_DIR", tmp.file("cache").c_str(), 1);
    const auto d = run_uvr("demo --size 96x96 --out '" + tmp.file("demo") + "'");
    INFO(d.out << d.err);
    REQUIRE(d.exit_code == 0);
    check_page(tmp, tmp.file("demo/index.html"), tmp.file("demo.png"));
    // Every link of the landing page leads to a file that exists.
    const std::string html = uvr::test::file_contents(tmp.file("demo/index.html"));
    std::size_t links = 0;
    for (std::size_t at = html.find("href=\""); at != std::string::npos; at = html.find("href=\"", at + 1)) {
        const std::size_t from = at + 6, to = html.find('"', from);
        const std::string target = html.substr(from, to - from);
        INFO("link " << target);
        CHECK(std::filesystem::exists(tmp.file("demo/" + target)));
        ++links;
    }
    CHECK(links >= 20);
    unsetenv("UVR_CACHE_DIR");
}

