// Meshes with known geometry for analytic and degenerate-geometry tests, and the chord of a ray through a box.
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>

#include <glm/vec3.hpp>

#include "reference/camera.h"

#include "reference/cells.h"
#include "reference/mesh.h"

namespace uvr::test {

// A box [0, n]^3 of unit cells split into tetrahedra, the scalar given by `field` at each point.
inline TetMesh box_mesh(int n, const std::function<double(const glm::dvec3&)>& field, double jitter = 0.0, unsigned seed = 1)
{
    StructuredGrid g;
    g.source = "box";
    g.dims = {n + 1, n + 1, n + 1};
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> U(-jitter, jitter);
    for (int k = 0; k <= n; ++k)
        for (int j = 0; j <= n; ++j)
            for (int i = 0; i <= n; ++i) {
                const bool inner = i > 0 && i < n && j > 0 && j < n && k > 0 && k < n;
                // z first: the statements fix the order of the draws, not the compiler.
                const double dz = inner ? U(rng) : 0.0, dy = inner ? U(rng) : 0.0, dx = inner ? U(rng) : 0.0;
                const glm::dvec3 p(i + dx, j + dy, k + dz);
                g.points.push_back(p);
            }
    ScalarField f{"f", {}};
    for (const auto& p : g.points) f.values.push_back(field(p));
    g.point_fields.push_back(f);
    return tetrahedralize_structured(g);
}

// Length of the ray's path inside the axis-aligned box [lo, hi] (slab method), and the entry parameter.
inline bool box_chord(const Ray& r, glm::dvec3 lo, glm::dvec3 hi, double& t0, double& t1)
{
    t0 = 0.0;
    t1 = INFINITY;
    for (int a = 0; a < 3; ++a) {
        if (r.dir[a] == 0.0) {
            if (r.origin[a] < lo[a] || r.origin[a] > hi[a]) return false;
            continue;
        }
        double ta = (lo[a] - r.origin[a]) / r.dir[a], tb = (hi[a] - r.origin[a]) / r.dir[a];
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
    }
    return t1 > t0;
}

}  // namespace uvr::test
