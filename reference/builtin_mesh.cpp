#include "reference/builtin_mesh.h"

#include <cstdlib>

#include <cmath>
#include <vector>

#include <tetgen.h>

#include "reference/error.h"

namespace uvr {

namespace {
constexpr double kPi = 3.14159265358979323846;
}

double builtin_torus_field(const glm::dvec3& p)
{
    return 0.5 + 0.25 * std::sin(3.0 * p.x) * std::cos(2.0 * p.y) + 0.25 * p.z / kTorusMinorRadius;
}

TetMesh builtin_torus(std::size_t target_tets)
{
    const double R = kTorusMajorRadius, r = kTorusMinorRadius;
    const double volume = 2.0 * kPi * kPi * R * r * r;
    // Surface resolution follows the target so that the surface triangles are about as large as the cells.
    const double cell = std::cbrt(volume / double(target_tets) * 6.0 * std::sqrt(2.0));
    const int nu = std::max(12, int(std::lround(2.0 * kPi * R / cell)));
    const int nv = std::max(6, int(std::lround(2.0 * kPi * r / cell)));

    std::vector<double> pts;
    for (int a = 0; a < nu; ++a)
        for (int b = 0; b < nv; ++b) {
            const double u = 2.0 * kPi * a / nu, v = 2.0 * kPi * b / nv;
            pts.insert(pts.end(), {(R + r * std::cos(v)) * std::cos(u), (R + r * std::cos(v)) * std::sin(u),
                                   r * std::sin(v)});
        }
    std::vector<int> tris;
    auto idx = [&](int a, int b) { return ((a + nu) % nu) * nv + (b + nv) % nv; };
    for (int a = 0; a < nu; ++a)
        for (int b = 0; b < nv; ++b) {
            tris.insert(tris.end(), {idx(a, b), idx(a + 1, b), idx(a + 1, b + 1)});
            tris.insert(tris.end(), {idx(a, b), idx(a + 1, b + 1), idx(a, b + 1)});
        }

    tetgenio in, out;
    in.firstnumber = 0;
    in.numberofpoints = static_cast<int>(pts.size() / 3);
    in.pointlist = new REAL[pts.size()];
    std::copy(pts.begin(), pts.end(), in.pointlist);
    in.numberoffacets = static_cast<int>(tris.size() / 3);
    in.facetlist = new tetgenio::facet[in.numberoffacets];
    in.facetmarkerlist = nullptr;
    for (int f = 0; f < in.numberoffacets; ++f) {
        tetgenio::facet& facet = in.facetlist[f];
        tetgenio::init(&facet);
        facet.numberofpolygons = 1;
        facet.polygonlist = new tetgenio::polygon[1];
        tetgenio::init(&facet.polygonlist[0]);
        facet.polygonlist[0].numberofvertices = 3;
        facet.polygonlist[0].vertexlist = new int[3]{tris[f * 3], tris[f * 3 + 1], tris[f * 3 + 2]};
    }
    // p: tetrahedralize the surface; q1.4: radius-edge quality bound; a: volume bound; Y: keep the surface as given;
    // Q: quiet. The volume bound is the mean cell volume for the target count.
    char switches[64];
    std::snprintf(switches, sizeof switches, "pq1.4a%.3gYQ", volume / double(target_tets));
    try {
        tetrahedralize(switches, &in, &out);
    } catch (...) {
        throw InputError("builtin:torus", "TetGen failed to tetrahedralize the torus");
    }

    TetMesh mesh;
    mesh.source = "builtin:torus";
    mesh.points.resize(std::size_t(out.numberofpoints));
    for (int i = 0; i < out.numberofpoints; ++i)
        mesh.points[std::size_t(i)] = {out.pointlist[3 * i], out.pointlist[3 * i + 1], out.pointlist[3 * i + 2]};
    mesh.tets.resize(std::size_t(out.numberoftetrahedra));
    for (int t = 0; t < out.numberoftetrahedra; ++t)
        for (int k = 0; k < 4; ++k)
            mesh.tets[std::size_t(t)][std::size_t(k)] =
                static_cast<uint32_t>(out.tetrahedronlist[t * out.numberofcorners + k]);
    ScalarField field{"wave", {}};
    field.values.reserve(mesh.points.size());
    for (const auto& p : mesh.points) field.values.push_back(builtin_torus_field(p));
    mesh.fields.push_back(std::move(field));
    finalize_mesh(mesh);
    return mesh;
}

double builtin_grid_field(const glm::dvec3& p)
{
    return 0.5 + 0.25 * std::sin(3.0 * p.x) * std::cos(2.0 * p.y) + 0.25 * p.z;
}

TetMesh builtin_grid(int n, int z_begin, int z_end)
{
    const std::size_t side = std::size_t(n) + 1, layers = std::size_t(z_end - z_begin) + 1;
    TetMesh mesh;
    mesh.source = "builtin:grid-" + std::to_string(n);
    mesh.points.reserve(side * side * layers);
    ScalarField field{"wave", {}};
    field.values.reserve(side * side * layers);
    // Coordinates from the global index, so that two slabs meeting at a layer make the same points there.
    const auto coordinate = [n](int i) { return -1.0 + 2.0 * double(i) / double(n); };
    for (int k = z_begin; k <= z_end; ++k)
        for (int j = 0; j <= n; ++j)
            for (int i = 0; i <= n; ++i) {
                mesh.points.push_back({coordinate(i), coordinate(j), coordinate(k)});
                field.values.push_back(builtin_grid_field(mesh.points.back()));
            }
    // The six tetrahedra of a cube: from the lowest corner, one step along each axis in each of the six orders, to the
    // highest corner. Corner c of a cube is (c & 1, c >> 1 & 1, c >> 2 & 1). The paths in the axes' even orders (x y z,
    // y z x, z x y) make positive tetrahedra; the odd orders' list their last two corners swapped to be positive too.
    static constexpr int kPaths[6][4] = {{0, 1, 3, 7}, {0, 2, 6, 7}, {0, 4, 5, 7},
                                         {0, 2, 7, 3}, {0, 4, 7, 6}, {0, 1, 7, 5}};
    mesh.tets.reserve(6 * std::size_t(n) * std::size_t(n) * std::size_t(z_end - z_begin));
    for (int k = 0; k < z_end - z_begin; ++k)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const auto corner = [&](int c) {
                    return uint32_t((std::size_t(k + (c >> 2 & 1)) * side + std::size_t(j + (c >> 1 & 1))) * side +
                                    std::size_t(i + (c & 1)));
                };
                for (const auto& path : kPaths)
                    mesh.tets.push_back({corner(path[0]), corner(path[1]), corner(path[2]), corner(path[3])});
            }
    mesh.fields.push_back(std::move(field));
    finalize_mesh(mesh);
    return mesh;
}

int builtin_grid_cubes(const std::string& path)
{
    const std::string prefix = "builtin:grid-";
    if (path.rfind(prefix, 0) != 0) return 0;
    const std::string digits = path.substr(prefix.size());
    char* end = nullptr;
    const unsigned long n = std::strtoul(digits.c_str(), &end, 10);
    if (digits.empty() || *end != 0 || n < 1 || n > unsigned(kBuiltinGridMaxCubes))
        throw InputError(path, "builtin:grid-N takes a number of cubes along each axis N from 1 to " +
                                   std::to_string(kBuiltinGridMaxCubes));
    return int(n);
}

bool is_builtin_path(const std::string& path) { return path.rfind("builtin:", 0) == 0; }

Volume builtin_torus_volume()
{
    Volume v;
    v.source = kBuiltinVolumePath;
    v.name = "fuzzy torus";
    v.dims = {64, 64, 32};
    const double R = kTorusMajorRadius, r = kTorusMinorRadius, margin = 0.2;
    const glm::dvec3 lo(-(R + r + margin), -(R + r + margin), -(r + margin));
    v.origin = lo;
    v.spacing = glm::dvec3(-2.0 * lo.x / double(v.dims[0] - 1), -2.0 * lo.y / double(v.dims[1] - 1),
                           -2.0 * lo.z / double(v.dims[2] - 1));
    v.type = VoxelType::f32;
    v.values.resize(std::size_t(v.dims[0] * v.dims[1] * v.dims[2]));
    std::size_t i = 0;
    for (int64_t z = 0; z < v.dims[2]; ++z)
        for (int64_t y = 0; y < v.dims[1]; ++y)
            for (int64_t x = 0; x < v.dims[0]; ++x) {
                const glm::dvec3 p = lo + glm::dvec3(double(x), double(y), double(z)) * v.spacing;
                const double d = std::hypot(std::hypot(p.x, p.y) - R, p.z);
                const double wave = 0.75 + 0.25 * std::sin(3.0 * p.x) * std::cos(2.0 * p.y);
                v.values[i++] = float(std::exp(-(d / r) * (d / r)) * wave);
            }
    finalize_volume(v);
    return v;
}

TetMesh load_builtin(const std::string& path)
{
    if (path == "builtin:torus") return builtin_torus(kBuiltinTorusTets);
    if (path == "builtin:torus-small") return builtin_torus(kBuiltinTorusSmallTets);
    // builtin:torus-N: about N tetrahedra (the scaling study's meshes).
    const std::string prefix = "builtin:torus-";
    if (path.rfind(prefix, 0) == 0) {
        const std::string digits = path.substr(prefix.size());
        char* end = nullptr;
        const unsigned long long n = std::strtoull(digits.c_str(), &end, 10);
        if (!digits.empty() && *end == 0 && n >= 100 && n <= kBuiltinTorusMaxTets) return builtin_torus(std::size_t(n));
        throw InputError(path, "builtin:torus-N takes a tetrahedron count N from 100 to " +
                                   std::to_string(kBuiltinTorusMaxTets));
    }
    if (const int n = builtin_grid_cubes(path)) return builtin_grid(n, 0, n);
    throw InputError(path,
                     "unknown built-in data set (known: builtin:torus, builtin:torus-small, builtin:torus-N, "
                     "builtin:torus-volume, builtin:grid-N)");
}

}  // namespace uvr
