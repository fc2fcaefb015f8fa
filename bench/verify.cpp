#include "bench/verify.h"

#include <cmath>
#include <filesystem>

#include <glm/geometric.hpp>

#include "bench/budget.h"
#include "gpu/raycast/raycast_setup.h"
#include "reference/analytic_field.h"
#include "reference/builtin_mesh.h"
#include "reference/error.h"
#include "reference/error_measures.h"
#include "reference/io_util.h"

namespace uvr::cli {

OrderStudy observed_order(const std::vector<double>& h, const std::vector<double>& errors, double expected,
                          const std::string& what, std::size_t min_levels)
{
    if (h.size() != errors.size())
        throw InputError(
            what, "has " + std::to_string(errors.size()) + " levels for " + std::to_string(h.size()) + " values of h");
    if (h.size() < min_levels)
        throw InputError(what,
                         "needs at least " + std::to_string(min_levels) + " levels, found " + std::to_string(h.size()));
    for (std::size_t i = 0; i < h.size(); ++i) {
        if (!(h[i] > 0.0) || !std::isfinite(h[i]))
            throw InputError(what, "h must be positive and finite, found " + std::to_string(h[i]));
        if (i > 0 && !(h[i] < h[i - 1]))
            throw InputError(what, "h must decrease from level to level, found " + std::to_string(h[i - 1]) + " then " +
                                       std::to_string(h[i]));
        if (!(errors[i] > 0.0) || !std::isfinite(errors[i]))
            throw InputError(what, "level " + std::to_string(i + 1) + "'s error is " + std::to_string(errors[i]) +
                                       ": an order needs positive, finite errors (an exact level has no order)");
    }
    OrderStudy s{h, errors, {}, 0.0, expected, false};
    double mx = 0.0, my = 0.0;
    for (std::size_t i = 0; i < h.size(); ++i) {
        mx += std::log(h[i]);
        my += std::log(errors[i]);
        if (i + 1 < h.size()) s.orders.push_back(std::log(errors[i] / errors[i + 1]) / std::log(h[i] / h[i + 1]));
    }
    mx /= double(h.size());
    my /= double(h.size());
    double sxy = 0.0, sxx = 0.0;
    for (std::size_t i = 0; i < h.size(); ++i) {
        const double dx = std::log(h[i]) - mx;
        sxy += dx * (std::log(errors[i]) - my);
        sxx += dx * dx;
    }
    s.fitted = sxy / sxx;
    s.pass = s.fitted >= expected - kOrderTolerance;
    return s;
}

// The largest error is one pixel's, whose ray may meet a kink of the integrand (a voxel face of the trilinear field, a
// table's end, a breakpoint of the transfer function) at a place that moves with h: first order at worst, where the
// derivation does not say more.
Expectation expected_order(const std::string& algo, Refinement refine, const AlgoOptions& o, bool clear_ends)
{
    if (refine == Refinement::step) {
        if (algo != "raycast")
            throw InputError("", "--refine step refines the ray caster's sampling distance (--algo raycast); " + algo +
                                     " has no step");
        if (!o.preintegrate && clear_ends)
            return {2.0, 2.0,
                    "post-classification samples at the ray's entry and every step after it, each sample standing for "
                    "a whole step: the exact integral of the field shifted by half a step, over a last step that "
                    "overshoots the exit; both first-order terms are the integrand at the ray's ends (Euler-Maclaurin), "
                    "and the transfer function is clear on every face of the box, so they vanish on every ray: second "
                    "order"};
        if (!o.preintegrate)
            return {1.0, 1.0,
                    "post-classification samples at the ray's entry and every step after it, each sample standing for "
                    "a whole step: the exact integral of the field shifted by half a step, over a last step that "
                    "overshoots the exit; both first-order terms are the integrand at the ray's ends "
                    "(Euler-Maclaurin), which the transfer function does not clear on the box's faces: first order"};
        return {2.0, 1.0,
                "pre-integration takes the scalar linear between samples, an error of the second order in the "
                "step (the trilinear field's curvature along the ray)",
                true};
    }
    if (refine == Refinement::table) {
        if (algo != "havs" && algo != "vicp" && algo != "raycast")
            throw InputError("", "--refine table refines HAVS's, VICP's or the pre-integrated ray caster's table; " +
                                     algo + " has none");
        if (algo == "raycast" && !o.preintegrate)
            throw InputError("", "--refine table: the ray caster's table is pre-integration's (--preintegrate)");
        const std::string interior =
            "the table is interpolated linearly between texel centres, and the pre-integral "
            "of a piecewise-linear transfer function has bounded second derivatives: an "
            "error of the second order in the texel spacing 1/n";
        if (algo == "raycast") return {2.0, 1.0, interior + " (the table's range is widened by half a texel)", true};
        return {2.0, 1.0,
                interior +
                    "; scalars within half a texel of the range's ends read the end texel, a first-order "
                    "error there",
                true};
    }
    if (refine == Refinement::size)
        return {0.5, std::nan(""),
                "a pixel is its centre's ray, compared with the mean of its four children: O(h^2) where the image is "
                "smooth, but a mesh's image has jumps at pixel scale (a boundary face seen edge-on ends a long path "
                "abruptly; a field that jumps across a face): O(1) on the O(1/h) of the O(1/h^2) pixels along them, "
                "RMSE O(h^(1/2)); the largest error is bounded by a jump's height and need not fall, so it has no "
                "order and no verdict"};
    return {2.0, 2.0,
            "the mesh samples the analytic field at its points and interpolates it linearly in each tetrahedron: "
            "an error of the second order in the cubes' edge at every point of a smooth field, so in every pixel"};
}

bool box_faces_clear(const Volume& v, const TransferFunction& tf)
{
    const int64_t nx = v.dims[0], ny = v.dims[1], nz = v.dims[2];
    double lo = INFINITY, hi = -INFINITY;
    const auto take = [&](int64_t i, int64_t j, int64_t k) {
        const double s = v.values[std::size_t(i + nx * (j + ny * k))];
        lo = std::min(lo, s);
        hi = std::max(hi, s);
    };
    for (int64_t k = 0; k < nz; ++k)
        for (int64_t j = 0; j < ny; ++j)
            for (int64_t i = 0; i < nx; ++i)
                if (i == 0 || j == 0 || k == 0 || i == nx - 1 || j == ny - 1 || k == nz - 1) take(i, j, k);
    return tf.clear_between(lo, hi);
}

namespace {

// The options of each level: the user's, or with --isolate every other switch exact (uvr budget's baseline), and the
// refined parameter at h.
std::vector<AlgoOptions> level_options(const VerifyRequest& a, const Scene& s, const std::vector<double>& h)
{
    if (a.refine == Refinement::step && a.options.step > 0.0)
        throw InputError("", "--refine step sets the step of each level: give the first with --from, not --step");
    AlgoOptions base = a.options;
    if (a.isolate) {
        if (a.algo == "raycast" && base.step <= 0.0) base.step = gpu::default_raycast_step(s.volume());
        base = budget_baseline(a.algo, base);
        if (a.refine == Refinement::step) {
            base.preintegrate = a.options.preintegrate;
            if (!base.preintegrate) base.segment = a.options.segment;  // no segments to integrate exactly
        }
        if (a.refine == Refinement::table) base.segment = "table";
        if (a.refine == Refinement::table && a.algo == "raycast") base.step /= kTableRefinementStepDivisor;
    }
    std::vector<AlgoOptions> out;
    for (double x : h) {
        AlgoOptions o = base;
        if (a.refine == Refinement::step) o.step = x;
        if (a.refine == Refinement::table) o.table_size = int(std::lround(1.0 / x));
        find_algorithm(a.algo).check_options(o);
        out.push_back(o);
    }
    return out;
}

// The refinement's h: steps in world units halving from --from, or 1/n for table sizes n doubling from --from (default
// 16). The default first step is twice the default step (a voxel spacing) for post-classification; pre-integrated, a
// quarter of the spacing: the trilinear field's kinks at voxel faces keep the order below 2 while a segment often holds
// one (docs/verification.md).
std::vector<double> refinement(const VerifyRequest& a, const Scene& s)
{
    if (a.refine == Refinement::step) {
        const double from = a.from > 0.0             ? a.from
                            : a.options.preintegrate ? 0.5 * gpu::default_raycast_step(s.volume())
                                                     : 2.0 * gpu::default_raycast_step(s.volume());
        return halving(from, a.levels);
    }
    const int n0 = a.from > 0.0 ? int(std::lround(a.from)) : 16;
    if (n0 < 2 || (int64_t(n0) << (a.levels - 1)) > 1024)
        throw InputError("", "--refine table: table sizes from " + std::to_string(n0) + " over " +
                                 std::to_string(a.levels) + " levels leave 2 to 1024");
    return halving(1.0 / double(n0), a.levels);
}

// One measure's orders and verdict; unjudged (no expected order), a null verdict. A pass far above the derivation
// says so (kFasterThanDerived), unless the derivation is only a worst case (`at_least`).
nlohmann::json study_json(const OrderStudy& st, bool judged, bool at_least)
{
    nlohmann::json j = {{"errors", st.errors}, {"orders", st.orders}, {"order", st.fitted}};
    const bool faster = !at_least && st.fitted > st.expected + kFasterThanDerived;
    j["verdict"] = !judged    ? nlohmann::json(nullptr)
                   : !st.pass ? nlohmann::json("fail")
                   : faster   ? nlohmann::json("pass: faster than derived")
                              : nlohmann::json("pass");
    return j;
}

// The orders of both measures, the expected orders and the verdict: "fail" when a judged measure fails, "pass: faster
// than derived" when one passes far above its derivation, "pass" otherwise. A measure whose expected order is NaN is
// not judged (its expected order null); with neither judged, no verdict.
nlohmann::json orders_json(const std::vector<double>& h, const std::vector<ErrorMeasures>& e, double expected_rmse,
                           double expected_max, const std::string& what, std::size_t min_levels = 3,
                           bool max_at_least = false)
{
    std::vector<double> rmse, max_abs;
    for (const ErrorMeasures& m : e) {
        rmse.push_back(m.rmse);
        max_abs.push_back(m.max_abs);
    }
    const bool judged_rmse = std::isfinite(expected_rmse), judged_max = std::isfinite(expected_max);
    const OrderStudy r = observed_order(h, rmse, judged_rmse ? expected_rmse : 0.0, what, min_levels);
    const OrderStudy m = observed_order(h, max_abs, judged_max ? expected_max : 0.0, what, min_levels);
    const auto expected = [](bool judged, double x) { return judged ? nlohmann::json(x) : nlohmann::json(nullptr); };
    nlohmann::json j;
    j["h"] = h;
    j["measures"] = {{"rmse", study_json(r, judged_rmse, false)}, {"max_abs", study_json(m, judged_max, max_at_least)}};
    j["expected_order"] = judged_rmse || judged_max ? nlohmann::json({{"rmse", expected(judged_rmse, expected_rmse)},
                                                                      {"max_abs", expected(judged_max, expected_max)}})
                                                    : nlohmann::json(nullptr);
    if (judged_max && max_at_least) j["expected_order"]["max_abs_at_least"] = true;
    j["tolerance"] = kOrderTolerance;
    const bool failed = (judged_rmse && !r.pass) || (judged_max && !m.pass);
    const bool faster = (judged_rmse && r.fitted > expected_rmse + kFasterThanDerived) ||
                        (judged_max && !max_at_least && m.fitted > expected_max + kFasterThanDerived);
    j["verdict"] = !(judged_rmse || judged_max) ? nlohmann::json(nullptr)
                   : failed                     ? nlohmann::json("fail")
                   : faster                     ? nlohmann::json("pass: faster than derived")
                                                : nlohmann::json("pass");
    return j;
}

// With a.images_dir: `image` as NAME.npy there, and with `scene` its transfer function and camera (tf.json,
// camera.json), so that another renderer can draw the same levels (bench/peers/verify_vtk_mesh.sh).
void keep_scene(const VerifyRequest& a, const std::string& name, const Image& image, const Scene* scene)
{
    if (a.images_dir.empty()) return;
    std::error_code ec;
    std::filesystem::create_directories(a.images_dir, ec);
    if (ec) throw InputError(a.images_dir, "cannot create the directory: " + ec.message());
    write_npy(a.images_dir + "/" + name + ".npy", image);
    if (!scene) return;
    write_file_atomically(a.images_dir + "/tf.json", transfer_function_json(scene->tf) + "\n");
    write_file_atomically(a.images_dir + "/camera.json", camera_json(scene->camera) + "\n");
}

std::string refinement_name(const VerifyRequest& a)
{
    return a.refine ? std::string(choice_name(kRefinements, *a.refine)) : std::string();
}

void check_levels(const VerifyRequest& a)
{
    if (a.levels < 3 || a.levels > 12) throw InputError("", "--levels takes 3 to 12 levels");
}

// What every render verification says of itself.
void describe(nlohmann::json& j, const VerifyRequest& a, const Expectation& ex)
{
    j["mode"] = "render";
    j["algo"] = a.algo;
    j["refine"] = refinement_name(a);
    j["isolate"] = a.isolate;
    j["derivation"] = ex.derivation;
}

// The ray integral of the analytic field is computed to this error per channel (analytic_field.h): 1/300 of the
// finest default level's RMSE (builtin:grid-32 from grid-4: 3.0e-4 measured, docs/verification.md), so that it moves
// the observed orders by under 0.01.
constexpr double kAnalyticTolerance = 1e-6;

// --refine mesh: builtin:grid-N refined 1:8 per level, each measured against the ray integral of its analytic field.
nlohmann::json mesh_levels(const SceneOptions& scene, const VerifyRequest& a, const Expectation& ex)
{
    const int n0 = builtin_grid_cubes(scene.input.path);
    if (n0 == 0)
        throw InputError(scene.input.path,
                         "--refine mesh refines builtin:grid-N (N cubes along each axis, doubled "
                         "at each level), whose field is analytic");
    if ((int64_t(n0) << (a.levels - 1)) > kBuiltinGridMaxCubes)
        throw InputError(scene.input.path, "--refine mesh: " + std::to_string(a.levels) + " levels from " +
                                               std::to_string(n0) + " cubes pass " +
                                               std::to_string(kBuiltinGridMaxCubes));
    // One transfer function for every level: the default over the analytic field's range, [0, 1], unless given.
    SceneOptions so = scene;
    const Bounds box{glm::dvec3(-1.0), glm::dvec3(1.0)};
    if (so.tf_path.empty() && !so.tf) so.tf = default_transfer_function(Range{0.0, 1.0}, glm::length(box.extent()));
    std::vector<double> h;
    std::vector<ErrorMeasures> e;
    nlohmann::json levels = nlohmann::json::array();
    Image exact;
    for (int i = 0; i < a.levels; ++i) {
        const int n = n0 << i;
        so.input.path = "builtin:grid-" + std::to_string(n);
        const Scene s = setup_scene(so);
        if (i == 0) {
            exact = render_analytic(builtin_grid_field, box, s.tf, s.camera, s.width, s.height, kAnalyticTolerance);
            keep_scene(a, "exact", exact, &s);
        }
        const AlgoResult r = run_algorithm(s, a.algo, a.options);
        keep_scene(a, "level" + std::to_string(i), r.image, nullptr);
        h.push_back(2.0 / double(n));
        e.push_back(measure_errors(r.image, exact));
        levels.push_back({{"h", h.back()},
                          {"cubes", n},
                          {"tetrahedra", s.mesh().tets.size()},
                          {"rmse", e.back().rmse},
                          {"max_abs", e.back().max_abs},
                          {"ms", r.ms}});
    }
    nlohmann::json j = orders_json(h, e, ex.rmse, ex.max_abs, a.algo + " --refine mesh", 3, ex.max_abs_at_least);
    j["levels"] = levels;
    j["analytic_tolerance"] = kAnalyticTolerance;
    describe(j, a, ex);
    return j;
}

// The mean of each 2 x 2 block of `fine` (of even size): the coarse pixel's box average.
Image box_average(const Image& fine)
{
    Image out(fine.width / 2, fine.height / 2);
    for (int j = 0; j < out.height; ++j)
        for (int i = 0; i < out.width; ++i)
            for (int c = 0; c < 4; ++c)
                out.pixel(i, j)[c] = float(
                    0.25 * (double(fine.pixel(2 * i, 2 * j)[c]) + double(fine.pixel(2 * i + 1, 2 * j)[c]) +
                            double(fine.pixel(2 * i, 2 * j + 1)[c]) + double(fine.pixel(2 * i + 1, 2 * j + 1)[c])));
    return out;
}

// --refine size: the scene at its size times 1, 2, 4, ... (h the pixel's side relative to the first level's); level i
// against the box average of level i + 1, so `levels` images give levels - 1 errors.
nlohmann::json size_levels(Scene& s, const VerifyRequest& a, const Expectation& ex)
{
    check_algorithm_scene(s, a.algo);
    const int w0 = s.width, h0 = s.height;
    if ((int64_t(std::max(w0, h0)) << (a.levels - 1)) > 16384)
        throw InputError("", "--refine size: " + std::to_string(w0) + "x" + std::to_string(h0) + " doubled " +
                                 std::to_string(a.levels - 1) + " times passes 16384 pixels");
    std::vector<Image> images;
    nlohmann::json levels = nlohmann::json::array();
    // The scene's own size again however the levels end (a Python scene outlives the call).
    struct Restore {
        Scene& s;
        int w, h;
        ~Restore()
        {
            s.width = w;
            s.height = h;
        }
    } restore{s, w0, h0};
    for (int i = 0; i < a.levels; ++i) {
        s.width = w0 << i;
        s.height = h0 << i;
        AlgoResult r = run_algorithm(s, a.algo, a.options);
        levels.push_back({{"h", std::ldexp(1.0, -i)}, {"width", s.width}, {"height", s.height}, {"ms", r.ms}});
        images.push_back(std::move(r.image));
    }
    std::vector<double> h;
    std::vector<ErrorMeasures> e;
    for (int i = 0; i + 1 < a.levels; ++i) {
        h.push_back(std::ldexp(1.0, -i));
        e.push_back(measure_errors(images[std::size_t(i)], box_average(images[std::size_t(i) + 1])));
    }
    nlohmann::json j = orders_json(h, e, ex.rmse, ex.max_abs, a.algo + " --refine size", 2, ex.max_abs_at_least);
    j["levels"] = levels;
    describe(j, a, ex);
    return j;
}

}  // namespace

nlohmann::json verify_refinement(const SceneOptions& scene, const VerifyRequest& a)
{
    check_levels(a);
    if (a.algo.empty()) throw InputError("", "--algo names the renderer whose order is verified");
    if (!a.refine) throw InputError("", "--refine says what is refined: " + choice_names(kRefinements));
    const Expectation ex = expected_order(a.algo, *a.refine, a.options);
    nlohmann::json j;
    if (a.refine == Refinement::mesh) {
        j = mesh_levels(scene, a, ex);
    } else {
        Scene s = setup_scene(scene);
        j = verify_refinement(s, a);
    }
    j["input"] = scene.input.path;
    return j;
}

nlohmann::json verify_refinement(Scene& s, const VerifyRequest& a)
{
    check_levels(a);
    if (a.refine == Refinement::mesh)
        throw InputError("",
                         "--refine mesh makes its own scenes, builtin:grid-N at each level: verify it from the "
                         "scene's options (uvr verify builtin:grid-N)");
    if (!a.refine) throw InputError("", "--refine says what is refined: " + choice_names(kRefinements));
    const bool clear_ends = a.algo == "raycast" && s.is_volume() && box_faces_clear(s.volume(), s.tf);
    const Expectation ex = expected_order(a.algo, *a.refine, a.options, clear_ends);
    if (a.refine == Refinement::size) return size_levels(s, a, ex);
    check_algorithm_scene(s, a.algo);
    const std::vector<double> h = refinement(a, s);
    const std::vector<AlgoOptions> opts = level_options(a, s, h);
    const Image ref = run_algorithm(s, "reference", a.options).image;
    std::vector<ErrorMeasures> e;
    nlohmann::json levels = nlohmann::json::array();
    for (std::size_t i = 0; i < h.size(); ++i) {
        const AlgoResult r = run_algorithm(s, a.algo, opts[i]);
        e.push_back(measure_errors(r.image, ref));
        nlohmann::json l = {{"h", h[i]}, {"rmse", e.back().rmse}, {"max_abs", e.back().max_abs}, {"ms", r.ms}};
        l[a.refine == Refinement::step ? "step" : "table_size"] =
            a.refine == Refinement::step ? opts[i].step : double(opts[i].table_size);
        levels.push_back(l);
    }
    nlohmann::json j =
        orders_json(h, e, ex.rmse, ex.max_abs, a.algo + " --refine " + refinement_name(a), 3, ex.max_abs_at_least);
    j["levels"] = levels;
    describe(j, a, ex);
    return j;
}

nlohmann::json verify_images(const std::vector<Image>& images, const std::vector<double>& h, const Image* reference,
                             int channels, double expected)
{
    if (images.size() != h.size())
        throw InputError("", "--images has " + std::to_string(images.size()) + " images and --h " +
                                 std::to_string(h.size()) + " values: one h per image");
    if (reference) {
        std::vector<ErrorMeasures> e;
        for (const Image& im : images) e.push_back(measure_errors(im, *reference, channels));
        return orders_json(h, e, expected, expected, "--images");
    }
    // Successive differences d_i = |I_i - I_{i+1}| fall as h_i^p where h shrinks by one ratio from level to level.
    for (std::size_t i = 2; i < h.size(); ++i)
        if (std::fabs(std::log(h[i - 1] / h[i]) / std::log(h[i - 2] / h[i - 1]) - 1.0) > 1e-9)
            throw InputError("", "--images without a reference: h must shrink by one ratio from level to level");
    std::vector<ErrorMeasures> d;
    for (std::size_t i = 0; i + 1 < images.size(); ++i) d.push_back(measure_errors(images[i], images[i + 1], channels));
    nlohmann::json j = orders_json(std::vector<double>(h.begin(), h.end() - std::ptrdiff_t(h.empty() ? 0 : 1)), d,
                                   expected, expected, "--images", 2);
    j["h"] = h;
    return j;
}

std::vector<double> halving(double coarsest, int levels)
{
    std::vector<double> h;
    for (int i = 0; i < levels; ++i) h.push_back(std::ldexp(coarsest, -i));
    return h;
}

}  // namespace uvr::cli
