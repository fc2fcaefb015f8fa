// The built-in data set: a tetrahedralized torus carrying an analytic scalar field, made by TetGen from a triangulated
// surface with fixed switches (TetGen is deterministic for a given input, so every machine gets the same mesh from
// the same Debian package). It is non-convex in the way that matters to the GPU algorithms: rays through the hole and
// rays that cross the torus twice see gaps. `uvr demo` and the tests use it; nothing outside the repository is needed.
#pragma once

#include <string>

#include <glm/vec3.hpp>

#include "reference/mesh.h"
#include "reference/volume.h"

namespace uvr {

inline constexpr double kTorusMajorRadius = 1.0;
inline constexpr double kTorusMinorRadius = 0.4;

// The analytic field sampled at the points ("wave"): smooth, with several extrema across the torus.
double builtin_torus_field(const glm::dvec3& p);

// A torus of roughly `target_tets` tetrahedra (the exact count is whatever TetGen makes of the size constraint).
TetMesh builtin_torus(std::size_t target_tets);

// Pseudo-paths understood by load_dataset(): "builtin:torus" (the demo mesh, about 100 K tetrahedra),
// "builtin:torus-small" (about 5 K, for fast tests) and "builtin:torus-N" (about N, 100 <= N <= kBuiltinTorusMaxTets:
// the scaling study), "builtin:grid-N" (above).
bool is_builtin_path(const std::string& path);
TetMesh load_builtin(const std::string& path);

// "builtin:torus-volume": a regular grid for the ray caster (the demo's, and tests'), nothing to download: 64 x 64 x 32
// samples over the torus's box (margin 0.2) of a fuzzy torus, exp(-(d / r)^2) with d the distance to the tube's core
// circle and r the minor radius, times 0.75 + 0.25 sin(3x) cos(2y) so that the ring carries structure.
inline constexpr const char* kBuiltinVolumePath = "builtin:torus-volume";
Volume builtin_torus_volume();

// "builtin:grid-N": the cube [-1, 1]^3 cut into N^3 cubes, each into the six tetrahedra around its diagonal from its
// lowest to its highest corner (the split is conforming: neighbouring cubes cut their shared face alike), 6 N^3
// tetrahedra with the analytic field "wave" at the points. builtin_grid makes the z-slab of cubes [z_begin, z_end) on
// its own (a data-parallel run makes its part without a file); its points and scalars are those of the whole grid.
inline constexpr int kBuiltinGridMaxCubes = 400;  // 384 M tetrahedra, past what 24 GB holds in one process
double builtin_grid_field(const glm::dvec3& p);
TetMesh builtin_grid(int n, int z_begin, int z_end);
// N of "builtin:grid-N" (0 when `path` is not of that form; InputError naming `path` for an N out of range).
int builtin_grid_cubes(const std::string& path);

inline constexpr std::size_t kBuiltinTorusTets = 100000;
inline constexpr std::size_t kBuiltinTorusSmallTets = 5000;
inline constexpr std::size_t kBuiltinTorusMaxTets = 20000000;

}  // namespace uvr
