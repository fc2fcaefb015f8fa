// The random source of the stage tests' case generators (test_*_gl_stage.cpp): a fixed seed, so every run draws the
// same cases, and the draws the generators share.
#pragma once

#include <cstdint>
#include <random>

#include <glm/vec3.hpp>

namespace uvr::test {

struct CaseRng {
    std::mt19937_64 rng;
    explicit CaseRng(uint64_t seed) : rng(seed) {}
    double uni(double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); }
    float unif(float a, float b) { return std::uniform_real_distribution<float>(a, b)(rng); }
    int pick(int n) { return int(rng() % uint64_t(n)); }
    glm::dvec3 vec(double r) { return {uni(-r, r), uni(-r, r), uni(-r, r)}; }
};

}  // namespace uvr::test
