#include "reference/write_vtk.h"

#include <cstdio>

#include "reference/io_util.h"

namespace uvr {

namespace {

template <class T>
void put_be(std::string& out, T v)
{
    v = byteswap_value(v);
    out.append(reinterpret_cast<const char*>(&v), sizeof v);
}

// VTK's legacy reader takes an array name up to whitespace: spaces would cut it.
std::string array_name(const std::string& name)
{
    std::string out = name.empty() ? "scalars" : name;
    for (char& c : out)
        if (c == ' ' || c == '\t') c = '_';
    return out;
}

std::string exact(double v)
{
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    return buf;
}

}  // namespace

void write_vtk_legacy(const std::string& path, const TetMesh& mesh, std::size_t field)
{
    const ScalarField& f = mesh.fields.at(field);
    std::string out = "# vtk DataFile Version 3.0\nuvr export of " + mesh.source + "\nBINARY\nDATASET UNSTRUCTURED_GRID\n";
    out += "POINTS " + std::to_string(mesh.points.size()) + " double\n";
    for (const auto& p : mesh.points) {
        put_be(out, p.x);
        put_be(out, p.y);
        put_be(out, p.z);
    }
    std::vector<const Tet*> real;
    for (const Tet& t : mesh.tets)
        if (!is_degenerate(mesh, t)) real.push_back(&t);
    out += "\nCELLS " + std::to_string(real.size()) + " " + std::to_string(real.size() * 5) + "\n";
    for (const Tet* t : real) {
        put_be(out, int32_t(4));
        for (uint32_t v : *t) put_be(out, int32_t(v));
    }
    out += "\nCELL_TYPES " + std::to_string(real.size()) + "\n";
    for (std::size_t i = 0; i < real.size(); ++i) put_be(out, int32_t(10));
    if (f.association == FieldAssociation::cell) {
        out += "\nCELL_DATA " + std::to_string(real.size()) + "\nSCALARS " + array_name(f.name) +
               " double 1\nLOOKUP_TABLE default\n";
        for (const Tet* t : real) put_be(out, f.values[std::size_t(t - mesh.tets.data())]);
    } else {
        out += "\nPOINT_DATA " + std::to_string(mesh.points.size()) + "\nSCALARS " + array_name(f.name) +
               " double 1\nLOOKUP_TABLE default\n";
        for (double v : f.values) put_be(out, v);
    }
    out += "\n";
    write_file_atomically(path, out);
}

void write_vtk_legacy(const std::string& path, const Volume& v)
{
    std::string out = "# vtk DataFile Version 3.0\nuvr export of " + v.source + "\nBINARY\nDATASET STRUCTURED_POINTS\n";
    out += "DIMENSIONS " + std::to_string(v.dims[0]) + " " + std::to_string(v.dims[1]) + " " + std::to_string(v.dims[2]);
    out += "\nORIGIN " + exact(v.origin.x) + " " + exact(v.origin.y) + " " + exact(v.origin.z);
    out += "\nSPACING " + exact(v.spacing.x) + " " + exact(v.spacing.y) + " " + exact(v.spacing.z);
    out += "\nPOINT_DATA " + std::to_string(v.values.size()) + "\nSCALARS " + array_name(v.name) +
           " float 1\nLOOKUP_TABLE default\n";
    out.reserve(out.size() + v.values.size() * sizeof(float) + 1);
    for (float x : v.values) put_be(out, x);
    out += "\n";
    write_file_atomically(path, out);
}

}  // namespace uvr
