// Observed order of accuracy (docs/verification.md): how fast an error falls as a discretization parameter h is
// refined, against the order the discretization promises, and the verdict.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/algorithms.h"
#include "bench/scene.h"
#include "reference/choice.h"

namespace uvr::cli {

// An observed order matches the expected one when it is at most this much lower (higher is faster convergence, which
// passes). Sized from uvr's own refinements (docs/verification.md, "The verdict"): the isolated ones reach RMSE
// orders of 1.86 to 2.42 where 2 is derived, and the stalled ones fall short by more than 1.
inline constexpr double kOrderTolerance = 0.25;
// The ray caster's table refinement with --isolate marches at the step divided by this, so that the march's own error
// (first or second order in the step, docs/verification.md) stays below the table's at the sizes refined.
inline constexpr double kTableRefinementStepDivisor = 16.0;

// An observed order above the derived one by more than this still passes, but the verdict says "faster than
// derived": the derivation or the measurement is wrong. uvr's own renderers are tested within [expected -
// kOrderTolerance, expected + kFasterThanDerived] (tests/test_verify.cpp).
inline constexpr double kFasterThanDerived = 0.75;

// The orders of one error measure over the levels.
struct OrderStudy {
    std::vector<double> h, errors;
    std::vector<double> orders;  // between levels i and i + 1: log(e_i / e_{i+1}) / log(h_i / h_{i+1})
    double fitted = 0.0;         // the least-squares slope of log e against log h over every level
    double expected = 0.0;
    bool pass = false;  // fitted >= expected - kOrderTolerance
};

// `h` strictly decreasing and positive, `errors` positive and finite, at least `min_levels` levels (InputError
// otherwise; `what` names the errors' source in the message).
OrderStudy observed_order(const std::vector<double>& h, const std::vector<double>& errors, double expected,
                          const std::string& what, std::size_t min_levels = 3);

// What a render verification refines.
enum class Refinement { step, table, mesh, size };
inline constexpr Choices<Refinement, 4> kRefinements{
    {{Refinement::step, "step", "the ray caster's sampling distance"},
     {Refinement::table, "table", "the pre-integration table's size n, h = 1/n"},
     {Refinement::mesh, "mesh", "builtin:grid-N, against its analytic field's integral"},
     {Refinement::size, "size", "the image's resolution, each pixel against the mean of its four children"}}};

// What a refinement of an algorithm converges at, per measure (NaN: no order to expect, so no verdict on that
// measure), and why (docs/verification.md derives each).
struct Expectation {
    double rmse, max_abs;
    std::string derivation;
    // The largest error's order is only a worst case (a kink the worst ray may or may not meet): faster is no sign of
    // a wrong derivation.
    bool max_abs_at_least = false;
};
// `clear_ends`: the ray caster's rays start and end where the transfer function has no extinction (box_faces_clear).
Expectation expected_order(const std::string& algo, Refinement refine, const AlgoOptions& o, bool clear_ends = false);

// Whether every scalar on the volume's six faces (bilinear between the faces' samples, so within their range) lies
// where `tf` has no extinction: then every ray through the box starts and ends where the integrand is zero.
bool box_faces_clear(const Volume& v, const TransferFunction& tf);

// What `uvr verify` renders: `algo` at `levels` refinements of `refine` from `from` (0: the default), with `options` as
// given or, with `isolate`, every other switch exact.
struct VerifyRequest {
    std::string algo;
    std::optional<Refinement> refine;
    int levels = 4;
    double from = 0.0;
    bool isolate = false;
    AlgoOptions options;
    std::string images_dir;  // --refine mesh: where the exact image, the levels' images, tf.json and camera.json go
};

// The levels rendered and measured against the reference (step, table), the analytic field's integral (mesh, on
// builtin:grid-N named by `scene`) or the next level's mean of four pixels (size); their orders, the expected ones and
// the verdict: docs/verification.md's JSON.
nlohmann::json verify_refinement(const SceneOptions& scene, const VerifyRequest& r);
// step, table and size on a scene made already (size renders it at larger sizes and gives it its own back).
nlohmann::json verify_refinement(Scene& s, const VerifyRequest& r);

// Images at decreasing `h` against `reference`, or (null) their successive differences; `channels` 3 compares colour
// only. `expected` NaN: no verdict.
nlohmann::json verify_images(const std::vector<Image>& images, const std::vector<double>& h, const Image* reference,
                             int channels, double expected);

// A refinement sequence's h: `levels` values from `coarsest`, each half the one before.
std::vector<double> halving(double coarsest, int levels);

}  // namespace uvr::cli
