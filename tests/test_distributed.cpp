// The data-parallel reference (docs/distributed.md): fragments of parts composited into the whole mesh's image, in one
// process and across MPI ranks under mpirun; the bands; every rank ending on any rank's failure.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <random>
#include <sstream>

#include <nlohmann/json.hpp>

#include "distributed/exchange.h"
#include "mesh_scenes.h"
#include "reference/builtin_mesh.h"
#include "reference/fragments.h"
#include "reference/partition.h"
#include "reference/reference_renderer.h"
#include "test_support.h"

using namespace uvr;
using test::CommandResult;
using test::TempDir;

namespace {

// docs/distributed.md's promise: the data-parallel image equals the one-process reference within 1e-6 in every
// channel. The parts' runs of a ray are disjoint, so only the order of the additions differs (about 1e-16 in double);
// the float32 images measured so far are identical.
constexpr double kDistributedTolerance = 1e-6;

// A data-parallel run that hangs instead of ending is stopped after this many seconds and fails; one that ends on a
// rank's failure takes about 0.3 s here (mpirun's start included).
constexpr int kHangSeconds = 60;

struct ImageDiff {
    double max = 0.0;
    std::size_t differing = 0, covered = 0;
};

ImageDiff diff(const Image& a, const Image& b)
{
    REQUIRE(a.width == b.width);
    REQUIRE(a.height == b.height);
    ImageDiff d;
    for (std::size_t p = 0; p < a.rgba.size() / 4; ++p) {
        bool differs = false;
        for (int c = 0; c < 4; ++c) {
            const double e = std::fabs(double(a.rgba[4 * p + std::size_t(c)]) - double(b.rgba[4 * p + std::size_t(c)]));
            d.max = std::max(d.max, e);
            differs |= e > 0.0;
        }
        d.differing += differs ? 1 : 0;
        d.covered += a.rgba[4 * p + 3] > 0.0f ? 1 : 0;
    }
    return d;
}

// The scene's parts traced on their own and composited, in one process.
Image composite_of_parts(const test::Scene& s, const std::vector<uint32_t>& part_of, uint32_t parts, const Camera& cam,
                         int w, int h, std::size_t& fragments)
{
    std::vector<Fragment> all;
    for (uint32_t p = 0; p < parts; ++p) {
        const TetMesh part = extract_part(s.mesh, part_of, p);
        const MeshTopology topo = build_topology(part);
        const RayIntegrator integrator(part, topo, s.field, s.tf);
        ReferenceStats st;
        const std::vector<Fragment> f = trace_fragments(integrator, cam, w, h, st);
        CHECK(st.failures == 0);
        all.insert(all.end(), f.begin(), f.end());
    }
    fragments = all.size();
    Image image(w, h);
    composite_fragments(all, image);
    return image;
}

Image reference_of(const test::Scene& s, const Camera& cam, int w, int h)
{
    const RayIntegrator integrator(s.mesh, s.topo, s.field, s.tf);
    ReferenceStats st;
    return render_reference(integrator, cam, w, h, st);
}

// odls_base_sigkill_timeout 0: once a rank has exited with an error, mpirun kills the ranks still running at once
// instead of waiting a second per signal (a failing run took 2.4 s instead of 0.3 s). A run whose ranks all wait
// in a collective has no rank exiting, so mpirun kills none: kHangSeconds still catches a hang.
std::string mpirun(int ranks)
{
    return "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 timeout " + std::to_string(kHangSeconds) + " '" +
           std::string(UVR_MPIEXEC) + "' --oversubscribe --mca odls_base_sigkill_timeout 0 -np " +
           std::to_string(ranks);
}

CommandResult run_ranks(int ranks, const std::string& args)
{
    return test::run_uvr(args, "", mpirun(ranks));
}

std::string quoted(const std::string& s)
{
    return "'" + s + "'";
}

// `uvr partition` of `input` (the data's options) into `parts` by `method`; returns the .pvtu's path.
std::string partition(const std::string& input, const std::string& name, int parts, const std::string& method,
                      const TempDir& dir)
{
    const std::string out = dir.file(name);
    const CommandResult r = test::run_uvr("partition " + input + " --parts " + std::to_string(parts) + " --method " +
                                          method + " --out " + quoted(out));
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    for (const auto& e : std::filesystem::directory_iterator(out))
        if (e.path().extension() == ".pvtu") return e.path().string();
    FAIL("no .pvtu in " << out);
    return "";
}

}  // namespace

TEST_CASE("the parts of a mesh traced on their own and composited give the whole mesh's reference")
{
    const test::Scene fin = test::blunt_fin();
    const test::Scene torus = test::make_scene(load_builtin("builtin:torus-small"), 0);
    for (const test::Scene* s : {&fin, &torus})
        for (PartitionMethod method : {PartitionMethod::rcb, PartitionMethod::metis})
            for (const auto& [az, el] : {std::pair{0.0, 0.0}, {-40.0, 70.0}}) {
                const Camera cam = default_camera(mesh_bounds(s->mesh), 1.0, az, el);
                const std::vector<uint32_t> part_of = partition_mesh(s->mesh, 5, method);
                std::size_t fragments = 0;
                const Image parts = composite_of_parts(*s, part_of, 5, cam, 96, 96, fragments);
                const ImageDiff d = diff(parts, reference_of(*s, cam, 96, 96));
                INFO(s->mesh.source << ", view " << az << "," << el << ": " << fragments << " fragments, "
                                    << d.differing << " of " << d.covered << " covered pixels differ, by at most "
                                    << d.max);
                CHECK(d.covered > 1000);
                CHECK(fragments > d.covered);  // rays cross parts: more fragments than covered pixels
                CHECK(d.max <= kDistributedTolerance);
            }
}

TEST_CASE("compositing fragments does not depend on the order they arrive in")
{
    const test::Scene torus = test::make_scene(load_builtin("builtin:torus-small"), 0);
    const Camera cam = default_camera(mesh_bounds(torus.mesh), 1.0, 30.0, 20.0);
    std::size_t fragments = 0;
    const std::vector<uint32_t> part_of = partition_rcb(torus.mesh, 4);
    const Image sorted = composite_of_parts(torus, part_of, 4, cam, 64, 64, fragments);
    std::vector<Fragment> all;
    for (uint32_t p = 0; p < 4; ++p) {
        const TetMesh part = extract_part(torus.mesh, part_of, p);
        const MeshTopology topo = build_topology(part);
        ReferenceStats st;
        const std::vector<Fragment> f = trace_fragments(RayIntegrator(part, topo, 0, torus.tf), cam, 64, 64, st);
        all.insert(all.end(), f.begin(), f.end());
    }
    std::shuffle(all.begin(), all.end(), std::mt19937(7));
    Image shuffled(64, 64);
    composite_fragments(all, shuffled);
    CHECK(shuffled.rgba == sorted.rgba);
}

TEST_CASE("pixel bands hold about equal shares of the fragments")
{
    CHECK(mpi::balanced_bands({0, 0, 10, 0, 10, 0}, 2) == std::vector<int>{0, 3, 6});
    // A row with more than a share: the band after it is empty.
    CHECK(mpi::balanced_bands({0, 100, 0, 0}, 3) == std::vector<int>{0, 2, 2, 4});
    // No fragments at all: the rows split evenly.
    CHECK(mpi::balanced_bands({0, 0, 0, 0, 0}, 2) == std::vector<int>{0, 2, 5});
    CHECK(mpi::balanced_bands({5, 5, 5, 5}, 1) == std::vector<int>{0, 4});
}

TEST_CASE("mpirun: the data-parallel reference equals the one-process reference, rcb and metis parts, 1 to 4 ranks")
{
    TempDir dir("mpi");
    const std::string fin = quoted(test::data_path("vtk-data/bluntfinxyz.bin")) + " --q " +
                            quoted(test::data_path("vtk-data/bluntfinq.bin"));
    const std::string post = quoted(test::data_path("vtk-data/postxyz.bin")) + " --q " +
                             quoted(test::data_path("vtk-data/postq.bin")) + " --field StagnationEnergy";
    // A camera inside the Oxygen Post's flow region, and one whose image plane cuts it.
    const std::string inside =
        dir.write("inside.json", R"({"eye": [0, 1.5, 0.5], "target": [5, 0, 2], "up": [0, 0, 1], "fovy_deg": 100})");
    const std::string cut =
        dir.write("cut.json", R"({"eye": [2, -3, 2.4], "target": [-5, 5, 2], "up": [0, 0, 1], "fovy_deg": 80})");
    struct Case {
        std::string name, input, method;
        int parts;
        std::vector<int> ranks;
        std::vector<std::string> views;
    };
    const std::vector<Case> cases = {
        {"torus", "builtin:torus-small", "rcb", 4, {1, 3}, {"--view 30,20"}},
        {"fin", fin, "rcb", 4, {2, 4}, {"--view 0,0", "--view -40,70"}},
        {"fin-metis", fin, "metis", 5, {2, 3}, {"--view -40,70"}},
        {"post", post, "rcb", 3, {3}, {"--camera " + quoted(inside), "--camera " + quoted(cut)}},
        {"post-metis", post, "metis", 4, {4}, {"--camera " + quoted(inside)}}};
    // Under the sanitizers the first two cases: they take the exchange's and the agreement's code paths as the others
    // do (the sanitizers check those paths; the other cases check the images).
    const std::size_t count = test::sanitized() ? 2 : cases.size();
    for (const Case& c : std::vector<Case>(cases.begin(), cases.begin() + std::ptrdiff_t(count))) {
        const std::string pvtu = partition(c.input, c.name, c.parts, c.method, dir);
        const std::string field = c.name.rfind("post", 0) == 0 ? " --field StagnationEnergy" : "";
        for (const std::string& view : c.views) {
            const std::string common = " --size 96x80 " + view + " --no-cache --out ";
            const std::string one = dir.file(c.name + "-one.npy");
            REQUIRE(test::run_uvr("render " + c.input + common + quoted(one)).exit_code == 0);
            // The .pvtu read in one process renders as the original mesh.
            const std::string joined = dir.file(c.name + "-joined.npy");
            REQUIRE(test::run_uvr("render " + quoted(pvtu) + field + common + quoted(joined)).exit_code == 0);
            CHECK(diff(read_npy(joined), read_npy(one)).max <= kDistributedTolerance);
            for (int n : c.ranks) {
                const std::string out = dir.file(c.name + "-" + std::to_string(n) + ".npy");
                const CommandResult r =
                    run_ranks(n, "render " + quoted(pvtu) + field + common + quoted(out) + " --json");
                INFO(c.name << " (" << c.parts << " " << c.method << " parts) on " << n << " ranks, " << view << "\n"
                            << r.err);
                REQUIRE(r.exit_code == 0);
                const ImageDiff d = diff(read_npy(out), read_npy(one));
                INFO(d.differing << " of " << d.covered << " covered pixels differ, by at most " << d.max);
                CHECK(d.covered > 500);
                CHECK(d.max <= kDistributedTolerance);
                // Every rank reports its part; the fragments sent are the fragments received.
                const nlohmann::json j = nlohmann::json::parse(r.out);
                REQUIRE(j["ranks"].size() == std::size_t(n));
                uint64_t sent = 0, received = 0, cells = 0;
                for (const auto& rank : j["ranks"]) {
                    sent += rank["fragments_sent"].get<uint64_t>();
                    received += rank["fragments_received"].get<uint64_t>();
                    cells += rank["cells"].get<uint64_t>();
                    CHECK(rank["peak_memory_bytes"].get<uint64_t>() > 0);
                }
                CHECK(sent == received);
                CHECK(j["failures"] == 0);
                CHECK(cells > 0);
            }
        }
    }
}

TEST_CASE("mpirun: sort-last HAVS and VICP over the pieces equal the one-process sort-last over the same parts")
{
    // The torus's pieces are its rcb parts exactly (it has no flat cells to leave out), so every rank renders the
    // parts the one-process run renders, with the same camera and transfer function (the whole mesh's), and rank 0
    // blends them in the same order: the same bits.
    TempDir dir("mpi-sort-last");
    const std::string pvtu = partition("builtin:torus-small", "torus", 4, "rcb", dir);
    for (const std::string algo : {"havs", "vicp"}) {
        const std::string common = " --algo " + algo + " --size 80x64 --view 30,20 --out ";
        const std::string one = dir.file(algo + "-one.npy"), ranks = dir.file(algo + "-ranks.npy");
        const CommandResult o =
            test::run_uvr("render builtin:torus-small --parts 4" + common + quoted(one) + " --json");
        REQUIRE(o.exit_code == 0);
        const CommandResult r = run_ranks(3, "render " + quoted(pvtu) + common + quoted(ranks) + " --json");
        INFO(algo << "\n" << r.err);
        REQUIRE(r.exit_code == 0);
        const nlohmann::json j = nlohmann::json::parse(r.out), j_one = nlohmann::json::parse(o.out);
        CHECK(j["sort_last"]["parts"] == 4);
        CHECK(j["sort_last"]["separated"] == true);
        CHECK(j["ranks"].size() == 3u);
        // The parts' counts merged as the one-process run merges them: the same parts, the same fragments.
        CHECK(j["sort_last"]["part_stats"].size() == 4u);
        CHECK(j["fragments"] == j_one["fragments"]);
        CHECK(j["max_fragments_per_pixel"] == j_one["max_fragments_per_pixel"]);
        if (algo == "vicp") CHECK(j["cells"] == j_one["cells"]);
        const Image a = read_npy(one), b = read_npy(ranks);
        CHECK(diff(a, b).covered > 500);
        CHECK(a.rgba == b.rgba);
    }
}

TEST_CASE("builtin:grid-N's slabs, made on their own, are the whole grid's cells, points and scalars")
{
    constexpr int n = 5;
    const TetMesh whole = builtin_grid(n, 0, n);
    REQUIRE(whole.tets.size() == 6u * n * n * n);
    REQUIRE(whole.points.size() == std::size_t(n + 1) * (n + 1) * (n + 1));
    // The six tetrahedra of a cube fill it: the volumes add up to the box's, 8, and every one is positive.
    double volume = 0.0;
    for (const Tet& t : whole.tets) {
        const double v6 =
            signed_volume6(whole.points[t[0]], whole.points[t[1]], whole.points[t[2]], whole.points[t[3]]);
        REQUIRE(v6 > 0.0);
        volume += v6 / 6.0;
    }
    CHECK(std::fabs(volume - 8.0) < 1e-12);
    // Conforming: every internal face is shared by exactly two tetrahedra, and the boundary is the box's six sides
    // of n x n squares, two triangles each.
    const MeshTopology topo = build_topology(whole);
    std::size_t boundary = 0;
    for (const Face& f : topo.faces) boundary += f.boundary() ? 1 : 0;
    CHECK(boundary == 6u * 2 * n * n);
    // A slab's cells, in order, are the whole grid's cells of those layers, point for point and scalar for scalar.
    const TetMesh slab = builtin_grid(n, 2, 4);
    REQUIRE(slab.tets.size() == 6u * n * n * 2);
    const std::size_t first = 6u * n * n * 2;
    for (std::size_t t = 0; t < slab.tets.size(); ++t)
        for (int k = 0; k < 4; ++k) {
            const uint32_t a = slab.tets[t][std::size_t(k)], b = whole.tets[first + t][std::size_t(k)];
            REQUIRE(slab.points[a] == whole.points[b]);
            REQUIRE(slab.fields[0].values[a] == whole.fields[0].values[b]);
        }
}

TEST_CASE("mpirun: the ranks make builtin:grid-N's slabs without a file and render the one-process grid's image")
{
    TempDir dir("mpi-grid");
    const std::string inside = dir.write(
        "inside.json", R"({"eye": [0.2, -0.3, 0.1], "target": [1, 1, 0.5], "up": [0, 0, 1], "fovy_deg": 90})");
    for (const std::string& view : {std::string("--view 30,20"), "--camera " + quoted(inside)}) {
        const std::string common = " --size 96x80 " + view + " --no-cache --out ";
        const std::string one = dir.file("one.npy"), ranks = dir.file("ranks.npy");
        REQUIRE(test::run_uvr("render builtin:grid-10" + common + quoted(one)).exit_code == 0);
        // 10 layers of cubes on 3 ranks: 3, 3 and 4 layers.
        const CommandResult r = run_ranks(3, "render builtin:grid-10" + common + quoted(ranks) + " --json");
        INFO(view << "\n" << r.err);
        REQUIRE(r.exit_code == 0);
        const ImageDiff d = diff(read_npy(ranks), read_npy(one));
        INFO(d.differing << " of " << d.covered << " covered pixels differ, by at most " << d.max);
        CHECK(d.covered > 2000);
        CHECK(d.max <= kDistributedTolerance);
        const nlohmann::json j = nlohmann::json::parse(r.out);
        REQUIRE(j["ranks"].size() == 3u);
        CHECK(j["ranks"][0]["cells"] == 1800);
        CHECK(j["ranks"][1]["cells"] == 1800);
        CHECK(j["ranks"][2]["cells"] == 2400);
    }
}

namespace {

// sweep.csv without its last column, `ms`: the wall time of each run, which differs between any two sweeps (two in one
// process too).
std::string csv_without_times(const std::string& path)
{
    std::istringstream in(test::file_contents(path));
    std::string line, out;
    while (std::getline(in, line)) out += line.substr(0, line.rfind(',')) + "\n";
    return out;
}

// sweep.json without the runs' times and the count of runs taken from disk.
nlohmann::json sweep_without_times(const std::string& path)
{
    nlohmann::json j = nlohmann::json::parse(test::file_contents(path));
    for (const char* rows : {"rows", "table_rows"})
        for (auto& r : j[rows]) r.erase("ms");
    j.erase("resumed_runs");
    return j;
}

}  // namespace

TEST_CASE("mpirun: a sweep spread over the ranks writes the one-process sweep's report, resumed runs included")
{
    TempDir dir("mpi-sweep");
    const std::string args = "sweep builtin:torus-small --k 1,6 --views 2 --table-sizes 16 --size 64x48 --report ";
    const std::string one = dir.file("one"), ranks = dir.file("ranks");
    REQUIRE(test::run_uvr(args + quoted(one)).exit_code == 0);
    for (const int n : {3, 2}) {
        // The second time, two runs are missing and the others are taken from disk.
        if (n == 2)
            for (const char* tag : {"v0-k6-exact", "v1-k1-table"})
                std::filesystem::remove(ranks + "/runs/" + tag + ".npy");
        const CommandResult r = run_ranks(n, args + quoted(ranks) + " --json");
        INFO(n << " ranks\n" << r.err);
        REQUIRE(r.exit_code == 0);
        CHECK(nlohmann::json::parse(r.out)["resumed_runs"] == (n == 2 ? 8 : 0));
        const std::string csv = csv_without_times(one + "/sweep.csv");
        CHECK(std::count(csv.begin(), csv.end(), '\n') == 11);  // the header, 2 views x (2 k x 2 modes + 1 table size)
        CHECK(csv_without_times(ranks + "/sweep.csv") == csv);
        CHECK(sweep_without_times(ranks + "/sweep.json") == sweep_without_times(one + "/sweep.json"));
        std::size_t images = 0;
        for (const auto& e : std::filesystem::directory_iterator(one + "/runs"))
            if (e.path().extension() == ".npy") {
                INFO(e.path().filename());
                CHECK(test::file_contents(e.path()) ==
                      test::file_contents(ranks + "/runs/" + e.path().filename().string()));
                ++images;
            }
        CHECK(images == 12);  // the 10 runs and the 2 views' references
    }
}

TEST_CASE("mpirun: a rank that cannot read its piece ends every rank, with the piece named and no image")
{
    TempDir dir("mpi-fail");
    const std::string pvtu = partition("builtin:torus-small", "torus", 4, "rcb", dir);
    const std::string piece = std::filesystem::path(pvtu).parent_path() / "torus-small_2.vtu";
    REQUIRE(std::filesystem::exists(piece));
    for (const bool missing : {true, false}) {
        if (missing)
            std::filesystem::remove(piece);
        else
            dir.write("torus/torus-small_2.vtu", "<VTKFile type=\"UnstructuredGrid\">");
        const std::string out = dir.file("never.npy");
        const auto t0 = std::chrono::steady_clock::now();
        const CommandResult r = run_ranks(4, "render " + quoted(pvtu) + " --size 32x32 --out " + quoted(out));
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        INFO((missing ? "missing" : "truncated") << " piece: " << r.err);
        CHECK(r.exit_code != 0);
        CHECK(r.exit_code != 124);  // `timeout` ended a hang
        CHECK(seconds < kHangSeconds);
        CHECK_THAT(r.err, Catch::Contains("rank 2") && Catch::Contains("torus-small_2.vtu"));
        CHECK_FALSE(std::filesystem::exists(out));
    }
}

TEST_CASE("mpirun: a .pvtu that records no extent renders the same image, one whose record is wrong is refused")
{
    TempDir dir("mpi-extent");
    const std::string pvtu = partition("builtin:torus-small", "torus", 3, "rcb", dir);
    const std::string text = test::file_contents(pvtu);
    const std::size_t begin = text.find("<FieldData>"), end = text.find("</FieldData>\n");
    REQUIRE(begin != std::string::npos);
    REQUIRE(end != std::string::npos);
    const std::string common = " --size 64x48 --view 30,20 --no-cache --out ";
    const std::string one = dir.file("one.npy");
    REQUIRE(test::run_uvr("render builtin:torus-small" + common + quoted(one)).exit_code == 0);
    SECTION("without the record (as other tools write a .pvtu) the ranks agree on the extent and render the same")
    {
        dir.write("torus/torus-small.pvtu", text.substr(0, begin) + text.substr(end + 13));
        const std::string out = dir.file("bare.npy");
        const CommandResult r = run_ranks(3, "render " + quoted(pvtu) + common + quoted(out));
        INFO(r.err);
        REQUIRE(r.exit_code == 0);
        CHECK(diff(read_npy(out), read_npy(one)).max <= kDistributedTolerance);
        // Sort-last takes the same way: HAVS over the pieces gives the one-process sort-last's bits.
        const std::string havs = " --algo havs --size 64x48 --view 30,20 --out ";
        const std::string one_havs = dir.file("one-havs.npy"), bare_havs = dir.file("bare-havs.npy");
        REQUIRE(test::run_uvr("render builtin:torus-small --parts 3" + havs + quoted(one_havs)).exit_code == 0);
        const CommandResult h = run_ranks(3, "render " + quoted(pvtu) + havs + quoted(bare_havs));
        INFO(h.err);
        REQUIRE(h.exit_code == 0);
        CHECK(read_npy(one_havs).rgba == read_npy(bare_havs).rgba);
    }
    SECTION("a record its pieces do not have (a bound moved) ends every rank, the file named, no image")
    {
        const std::string bounds = "Name=\"uvr whole bounds\"";
        const std::size_t first = text.find('>', text.find(bounds)) + 1;
        std::string moved = text;
        moved.replace(first, text.find(' ', first) - first, "-100");  // the lowest x, far below the torus's -1.4
        dir.write("torus/torus-small.pvtu", moved);
        const std::string out = dir.file("never.npy");
        const CommandResult r = run_ranks(3, "render " + quoted(pvtu) + common + quoted(out));
        INFO(r.err);
        CHECK(r.exit_code != 0);
        CHECK(r.exit_code != 124);
        CHECK_THAT(r.err, Catch::Contains(pvtu) && Catch::Contains("records a whole extent"));
        CHECK_FALSE(std::filesystem::exists(out));
    }
}

TEST_CASE("mpirun: what the data-parallel run cannot do is refused on every rank")
{
    TempDir dir("mpi-refuse");
    const std::string pvtu = partition("builtin:torus-small", "torus", 2, "rcb", dir);
    const std::string out = " --size 16x16 --out " + quoted(dir.file("never.npy"));
    const struct {
        int ranks;
        std::string args, message;
    } cases[] = {{2, "render builtin:torus-small" + out, "reads a .pvtu of pieces"},
                 {3, "render " + quoted(pvtu) + out, "has 2 pieces for 3 ranks"},
                 {2, "render " + quoted(pvtu) + " --algo raycast" + out, "runs --algo reference, havs or vicp"},
                 {2, "render " + quoted(pvtu) + " --algo havs --parts 2" + out, "the .pvtu's pieces are the parts"},
                 {2, "info " + quoted(pvtu), "runs render and sweep only"},
                 {3, "render builtin:grid-2" + out, "has 2 layers of cubes for 3 ranks"},
                 {2, "sweep builtin:torus-volume --report " + quoted(dir.file("never")), "runs in one process"},
                 {2, "render " + quoted(pvtu) + " --size 16x16 --out " + quoted(dir.file("never.pfm")),
                  "never.pfm: unsupported image extension"}};
    for (const auto& c : cases) {
        const CommandResult r = run_ranks(c.ranks, c.args);
        INFO(c.args << "\n" << r.err);
        CHECK(r.exit_code != 0);
        CHECK(r.exit_code != 124);
        CHECK_THAT(r.err, Catch::Contains(c.message));
        // Refused by agreement (rank 0 says why, every rank exits 1), not by an abort of the job.
        CHECK_THAT(r.err, !Catch::Contains("MPI_ABORT"));
        CHECK_FALSE(std::filesystem::exists(dir.file("never.npy")));
        CHECK_FALSE(std::filesystem::exists(dir.file("never")));
    }
}
