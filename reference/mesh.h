// The data model: a tetrahedral mesh with scalar fields on its points or on its cells.
//
// A TetMesh is what every reader produces and every renderer consumes. It holds only primary data; everything derived
// (unique faces, adjacency, bounds, ranges, convexity) is computed on demand by topology.h and the functions below, so
// there is no cached state that can go stale.
//
// Invariants after finalize_mesh(): every index is in range, every coordinate and scalar is finite, every tetrahedron
// has four distinct points and strictly positive signed volume (vertex 3 on the positive side of the plane through 0,
// 1, 2 with normal (p1-p0)x(p2-p0)) unless it is a degenerate cell kept from a structured grid (see DegenerateCells),
// and each field has one value per point (FieldAssociation::point) or per tetrahedron (FieldAssociation::cell).
// Points are kept as the file wrote them: coincident points are not merged, so a point field whose coincident points
// carry different values is per-cell vertex data (reference/field.h, docs/data-model.md "Fields").
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

namespace uvr {

// Where a field's values live: at the points (linear in each tetrahedron) or one per tetrahedron (constant in it).
enum class FieldAssociation : uint8_t { point, cell };

struct ScalarField {
    std::string name;
    std::vector<double> values;  // one per point, or one per tetrahedron (association)
    FieldAssociation association = FieldAssociation::point;
};

struct Bounds {
    glm::dvec3 lo{0.0}, hi{0.0};
    glm::dvec3 center() const { return 0.5 * (lo + hi); }
    glm::dvec3 extent() const { return hi - lo; }
};

using Tet = std::array<uint32_t, 4>;

struct TetMesh {
    std::string source;  // the file it came from (or a description of a generated mesh), for messages
    std::vector<glm::dvec3> points;
    std::vector<Tet> tets;
    std::vector<ScalarField> fields;
};

// A mesh holds fewer than kMaxTetrahedra tetrahedra: the reference walk packs a neighbour as (tetrahedron << 3) |
// jump << 2 | face into 32 bits (reference/ray_integrator.h), and index 2^29 - 1 with the jump bit and face 3 would be
// the no-neighbour value 0xFFFFFFFF, so 2^29 itself is refused too.
inline constexpr std::size_t kMaxTetrahedra = std::size_t(1) << 29;

// Throws InputError naming `source` when `count` tetrahedra would reach kMaxTetrahedra. Readers call it with the count
// a header or the cells imply, before allocating the tetrahedra.
void check_tetrahedron_count(const std::string& source, std::size_t count);

// Six times the signed volume of tetrahedron (a, b, c, d): positive when d lies on the side of plane (a, b, c) that
// (b-a)x(c-a) points to.
double signed_volume6(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d);

// A tetrahedron counts as degenerate (zero volume) when |6V| <= kDegenerateRelativeVolume * L^3, L its longest edge.
// The determinant of the edge vectors is computed in double with a relative rounding error of a few 1e-16 of L^3, so
// 1e-14 is two orders of magnitude above what rounding alone can produce for a truly flat tetrahedron, while a sliver
// of relative volume 1e-12 (the case) is still accepted as a real cell.
inline constexpr double kDegenerateRelativeVolume = 1e-14;

// What finalize_mesh does with a zero-volume tetrahedron. Files of unstructured cells reject it (a broken cell). The
// split of a structured grid keeps it: curvilinear grids collapse hexahedra on purpose (Blunt Fin's 39 cells along
// its symmetry line have coincident points), the classic tetrahedral meshes of those grids keep the cells (187,395
// tetrahedra for Blunt Fin, of which 77 are flat), and a flat cell covers no volume, so it changes no image.
enum class DegenerateCells { reject, keep };

// True when the tetrahedron is degenerate by the criterion above.
bool is_degenerate(const TetMesh& mesh, const Tet& t);
std::size_t count_degenerate(const TetMesh& mesh);

// Checks the invariants above and re-orients inverted tetrahedra (swaps vertices 2 and 3). Throws InputError naming
// mesh.source and the offending cell or point: index out of range, a repeated vertex, a degenerate tetrahedron (unless
// kept), a non-finite coordinate or scalar, a field of the wrong length, a mesh with no tetrahedron. Kept degenerate
// tetrahedra are left as they are (they have no orientation). Returns the number of tetrahedra re-oriented.
std::size_t finalize_mesh(TetMesh& mesh, DegenerateCells degenerate = DegenerateCells::reject);

Bounds mesh_bounds(const TetMesh& mesh);

// Index of the field called `name`, or of the field at that index when `name` is a number; the first field when
// `name` is empty. Throws InputError listing the available fields when there is no match.
std::size_t find_field(const TetMesh& mesh, const std::string& name);

struct Range {
    double lo = 0.0, hi = 0.0;
};
Range field_range(const ScalarField& field);

}  // namespace uvr
