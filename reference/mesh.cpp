#include "reference/mesh.h"

#include <algorithm>
#include <charconv>
#include <cmath>

#include <glm/common.hpp>

#include "reference/error.h"

namespace uvr {

double signed_volume6(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d)
{
    const glm::dvec3 u = b - a, v = c - a, w = d - a;
    return u.x * (v.y * w.z - v.z * w.y) - u.y * (v.x * w.z - v.z * w.x) + u.z * (v.x * w.y - v.y * w.x);
}

namespace {

std::string fmt_point(const glm::dvec3& p)
{
    char buf[128];
    std::snprintf(buf, sizeof buf, "(%.9g, %.9g, %.9g)", p.x, p.y, p.z);
    return buf;
}

}  // namespace

namespace {

// |6V| and the longest edge cubed, for the degeneracy criterion.
void volume_and_scale(const TetMesh& mesh, const Tet& tet, double& v6, double& l3)
{
    const glm::dvec3* p[4] = {&mesh.points[tet[0]], &mesh.points[tet[1]], &mesh.points[tet[2]], &mesh.points[tet[3]]};
    v6 = signed_volume6(*p[0], *p[1], *p[2], *p[3]);
    double l2 = 0.0;
    for (int a = 0; a < 4; ++a)
        for (int b = a + 1; b < 4; ++b) {
            const glm::dvec3 e = *p[b] - *p[a];
            l2 = std::max(l2, e.x * e.x + e.y * e.y + e.z * e.z);
        }
    l3 = l2 * std::sqrt(l2);
}

}  // namespace

bool is_degenerate(const TetMesh& mesh, const Tet& t)
{
    double v6, l3;
    volume_and_scale(mesh, t, v6, l3);
    return !(std::fabs(v6) > kDegenerateRelativeVolume * l3);
}

std::size_t count_degenerate(const TetMesh& mesh)
{
    std::size_t n = 0;
    for (const Tet& t : mesh.tets) n += is_degenerate(mesh, t) ? 1 : 0;
    return n;
}

void check_tetrahedron_count(const std::string& source, std::size_t count)
{
    if (count >= kMaxTetrahedra)
        throw InputError(source, std::to_string(count) + " tetrahedra: uvr takes fewer than 2^29 (" +
                                     std::to_string(kMaxTetrahedra) +
                                     "), since the reference walk packs a tetrahedron's index into 29 bits");
}

std::size_t finalize_mesh(TetMesh& mesh, DegenerateCells degenerate)
{
    const std::string& file = mesh.source;
    if (mesh.tets.empty()) throw InputError(file, "the mesh has no tetrahedron");
    check_tetrahedron_count(file, mesh.tets.size());
    const std::size_t np = mesh.points.size();
    for (std::size_t i = 0; i < np; ++i) {
        const glm::dvec3& p = mesh.points[i];
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
            throw InputError(file, "point " + std::to_string(i) + " has a non-finite coordinate " + fmt_point(p));
    }
    for (const ScalarField& f : mesh.fields) {
        const bool cell = f.association == FieldAssociation::cell;
        const std::size_t n = cell ? mesh.tets.size() : np;
        const char* what = cell ? "tetrahedra" : "points";
        if (f.values.size() != n)
            throw InputError(file, "field '" + f.name + "' has " + std::to_string(f.values.size()) +
                                       " values for " + std::to_string(n) + " " + what);
        for (std::size_t i = 0; i < n; ++i)
            if (!std::isfinite(f.values[i]))
                throw InputError(file, "field '" + f.name + "' is not finite at " + (cell ? "tetrahedron " : "point ") +
                                           std::to_string(i) + " (" + std::to_string(f.values[i]) + ")");
    }
    std::size_t flipped = 0;
    for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
        Tet& tet = mesh.tets[t];
        for (int k = 0; k < 4; ++k)
            if (tet[k] >= np)
                throw InputError(file, "tetrahedron " + std::to_string(t) + " uses point " + std::to_string(tet[k]) +
                                           ", but the mesh has only " + std::to_string(np) + " points");
        for (int a = 0; a < 4; ++a)
            for (int b = a + 1; b < 4; ++b)
                if (tet[a] == tet[b])
                    throw InputError(file, "tetrahedron " + std::to_string(t) + " repeats point " +
                                               std::to_string(tet[a]) + " (a degenerate cell)");
        double v6, l3;
        volume_and_scale(mesh, tet, v6, l3);
        if (!(std::fabs(v6) > kDegenerateRelativeVolume * l3)) {
            if (degenerate == DegenerateCells::keep) continue;
            throw InputError(file, "tetrahedron " + std::to_string(t) + " (points " + std::to_string(tet[0]) + " " +
                                       std::to_string(tet[1]) + " " + std::to_string(tet[2]) + " " +
                                       std::to_string(tet[3]) + ") has zero volume (a degenerate cell)");
        }
        if (v6 < 0.0) {
            std::swap(tet[2], tet[3]);
            ++flipped;
        }
    }
    return flipped;
}

Bounds mesh_bounds(const TetMesh& mesh)
{
    Bounds b;
    if (mesh.points.empty()) return b;
    b.lo = b.hi = mesh.points[0];
    for (const glm::dvec3& p : mesh.points) {
        b.lo = glm::min(b.lo, p);
        b.hi = glm::max(b.hi, p);
    }
    return b;
}

std::size_t find_field(const TetMesh& mesh, const std::string& name)
{
    auto available = [&] {
        std::string s;
        for (std::size_t i = 0; i < mesh.fields.size(); ++i)
            s += (i ? ", " : "") + std::to_string(i) + " '" + mesh.fields[i].name + "'";
        return s.empty() ? std::string("none") : s;
    };
    if (mesh.fields.empty())
        throw InputError(mesh.source, "the mesh has no scalar field (a renderer needs one)");
    if (name.empty()) return 0;
    for (std::size_t i = 0; i < mesh.fields.size(); ++i)
        if (mesh.fields[i].name == name) return i;
    std::size_t index = 0;
    auto [p, ec] = std::from_chars(name.data(), name.data() + name.size(), index);
    if (ec == std::errc() && p == name.data() + name.size() && index < mesh.fields.size()) return index;
    throw InputError(mesh.source, "no field '" + name + "'; available: " + available());
}

Range field_range(const ScalarField& field)
{
    Range r;
    if (field.values.empty()) return r;
    auto [lo, hi] = std::minmax_element(field.values.begin(), field.values.end());
    r.lo = *lo;
    r.hi = *hi;
    return r;
}

}  // namespace uvr
