// Partitions that balance weights rather than counts, and the weights of a view's ray work (reference/partition.h,
// docs/distributed.md, "Balanced for a view").
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numeric>
#include <vector>

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <tbb/task_arena.h>

#include "mesh_scenes.h"
#include "reference/fragments.h"
#include "reference/partition.h"
#include "reference/reference_renderer.h"
#include "test_support.h"

using namespace uvr;
using test::CommandResult;
using test::run_uvr;
using test::TempDir;

namespace {

// Per part, the sum of `weights` over its cells.
std::vector<uint64_t> part_sums(const std::vector<uint32_t>& part_of, const std::vector<uint64_t>& weights,
                                uint32_t parts)
{
    std::vector<uint64_t> sum(parts, 0);
    for (std::size_t c = 0; c < part_of.size(); ++c) sum[part_of[c]] += weights[c];
    return sum;
}

// A view that sees the torus unevenly: close to one side, so that the near half's cells cover far more pixels.
Camera near_one_side(const TetMesh& mesh)
{
    const Bounds b = mesh_bounds(mesh);
    const glm::dvec3 target = b.center() + glm::dvec3(0.35 * b.extent().x, 0.0, 0.0);
    return test::looking(target + glm::dvec3(0.2 * b.extent().x, 0.3 * b.extent().y, 0.45 * b.extent().z), target,
                         70.0);
}

// The small torus, its reference and the view close to one side.
struct CloseView {
    test::Scene s = test::make_scene(load_builtin("builtin:torus-small"), 0);
    RayIntegrator integrator{s.mesh, s.topo, s.field, s.tf};
    Camera cam = near_one_side(s.mesh);
    std::vector<uint64_t> steps(int width, int height) const
    {
        return view_steps(integrator, s.mesh.tets.size(), cam, width, height);
    }
};

}  // namespace

TEST_CASE("rcb weighing every cell alike makes the parts rcb by count makes")
{
    const TetMesh mesh = load_builtin("builtin:torus-small");
    const std::vector<uint64_t> ones(mesh.tets.size(), 1);
    // Halving a share of whole cells rounds as the count does for parts that are powers of two.
    for (uint32_t parts : {2u, 4u, 8u}) {
        INFO(parts << " parts");
        CHECK(partition_rcb(mesh, parts, &ones) == partition_rcb(mesh, parts));
    }
}

TEST_CASE("rcb with weights cuts where the weights balance, and keeps its parts in boxes")
{
    const TetMesh mesh = load_builtin("builtin:torus-small");
    // Cells left of x = 0 weigh nine times the others: the cut normal to x moves left of the middle.
    constexpr uint64_t kHeavy = 9;
    std::vector<uint64_t> w(mesh.tets.size());
    for (std::size_t c = 0; c < w.size(); ++c) {
        const Tet& t = mesh.tets[c];
        w[c] = mesh.points[t[0]].x + mesh.points[t[1]].x + mesh.points[t[2]].x + mesh.points[t[3]].x < 0.0 ? kHeavy : 1;
    }
    const uint64_t total = std::accumulate(w.begin(), w.end(), uint64_t(0));
    for (uint32_t parts = 2; parts <= 5; ++parts) {
        INFO(parts << " parts");
        const std::vector<uint32_t> part_of = partition_rcb(mesh, parts, &w);
        CHECK(partition_rcb(mesh, parts, &w) == part_of);
        // Each level's cut is the nearest to its share, within half a cell's weight; its error is then split again
        // below it: a part's weight is off its share by at most one heaviest cell per level.
        const double levels = std::ceil(std::log2(double(parts)));
        for (uint64_t s : part_sums(part_of, w, parts))
            CHECK(std::fabs(double(s) - double(total) / parts) <= levels * double(kHeavy));
    }
    const std::vector<uint32_t> halves = partition_rcb(mesh, 2, &w);
    const std::size_t left = std::size_t(std::count(halves.begin(), halves.end(), 0u));
    CHECK(left < mesh.tets.size() / 3);  // the heavy side holds fewer cells
}

TEST_CASE("a view's steps are the steps its rays take through each cell, as the reference counts them")
{
    const CloseView v;
    constexpr int kW = 48, kH = 40;
    const std::vector<uint64_t> steps = v.steps(kW, kH);
    ReferenceStats st;
    render_reference(v.integrator, v.cam, kW, kH, st);
    REQUIRE(st.segments > 0);
    CHECK(std::accumulate(steps.begin(), steps.end(), uint64_t(0)) == st.segments);
    CHECK(std::count(steps.begin(), steps.end(), 0u) > 0);  // the view does not see the far side's cells
    // Counted in integers: the same on one thread as on every thread.
    tbb::task_arena one(1);
    one.execute([&] { CHECK(v.steps(kW, kH) == steps); });
}

TEST_CASE("parts balanced for a view share its work evenly, where parts of equal counts do not")
{
    const CloseView v;
    const test::Scene& s = v.s;
    constexpr int kW = 64, kH = 64;
    const std::vector<uint64_t> steps = v.steps(kW, kH);
    struct Part {
        uint64_t steps = 0, cells = 0;
    };
    // Each part traced on its own, as a rank traces it.
    auto parts_of = [&](const std::vector<uint32_t>& part_of) {
        std::vector<Part> parts;
        for (uint32_t p = 0; p < 2; ++p) {
            const TetMesh part = extract_part(s.mesh, part_of, p);
            const MeshTopology topo = build_topology(part);
            ReferenceStats st;
            trace_fragments(RayIntegrator(part, topo, s.field, s.tf), v.cam, kW, kH, st);
            parts.push_back({st.segments, part.tets.size()});
        }
        return parts;
    };
    const auto ratio = [](uint64_t a, uint64_t b) { return double(std::max(a, b)) / double(std::min(a, b)); };
    // The bound the weights are cut to (rcb: within one cell; METIS: each part within kMetisImbalance of the average,
    // so within 1.03 / 0.97 of each other), plus what tracing a part alone changes: its rays' steps round the cut's
    // edges, a few in a thousand.
    constexpr double kBalanced = kMetisImbalance / (2.0 - kMetisImbalance) + 0.01;
    for (PartitionMethod method : {PartitionMethod::rcb, PartitionMethod::metis}) {
        INFO(choice_name(kPartitionMethods, method));
        const std::vector<Part> by_count = parts_of(partition_mesh(s.mesh, 2, method));
        const std::vector<Part> by_view = parts_of(partition_mesh(s.mesh, 2, method, &steps));
        INFO("steps and cells by count " << by_count[0].steps << ", " << by_count[0].cells << "; " << by_count[1].steps
                                         << ", " << by_count[1].cells << "; by view " << by_view[0].steps << ", "
                                         << by_view[0].cells << "; " << by_view[1].steps << ", " << by_view[1].cells);
        // This view gives one half of the cells far more of the steps (measured 5.7 and 3.3 times the other's).
        CHECK(ratio(by_count[0].steps, by_count[1].steps) > 2.0);
        if (method == PartitionMethod::rcb) {
            // One weight: the steps plus each cell's share (measured 1.0003).
            const auto work = [](const Part& p) { return p.steps + kCellWorkInSteps * p.cells; };
            CHECK(ratio(work(by_view[0]), work(by_view[1])) < kBalanced);
        } else {
            // Two constraints, each balanced (measured 1.06 in steps and 1.05 in cells).
            CHECK(ratio(by_view[0].steps, by_view[1].steps) < kBalanced);
            CHECK(ratio(by_view[0].cells, by_view[1].cells) < kBalanced);
        }
    }
}

TEST_CASE("uvr partition --balance view writes parts of equal ray work, and the view's options only with it")
{
    TempDir dir("partition-view");
    const std::string out = dir.file("out");
    const CommandResult r = run_uvr(
        "partition builtin:torus-small --parts 2 --balance view --view 60,20 --size 48x48 "
        "--json --out '" +
        out + "'");
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    const nlohmann::json j = nlohmann::json::parse(r.out);
    CHECK(j["balance"] == "view");
    REQUIRE(j["parts"].size() == 2);
    CHECK(j["parts"][0]["tetrahedra"] != j["parts"][1]["tetrahedra"]);
    for (const std::string option : {"--view 60,20", "--size 48x48", "--camera cam.json", "--tf preset:jet"}) {
        const CommandResult bad =
            run_uvr("partition builtin:torus-small --parts 2 " + option + " --out '" + dir.file("never") + "'");
        INFO(option);
        CHECK(bad.exit_code == 1);
        CHECK_THAT(bad.err, Catch::Contains("sets the view that --balance view balances for"));
    }
    const CommandResult unknown =
        run_uvr("partition builtin:torus-small --parts 2 --balance time --out '" + dir.file("never") + "'");
    CHECK(unknown.exit_code == 1);
    CHECK_THAT(unknown.err, Catch::Contains("--balance must be cells or view, not 'time'"));
    CHECK_FALSE(std::filesystem::exists(dir.file("never")));
}
