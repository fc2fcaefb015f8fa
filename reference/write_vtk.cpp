#include "reference/write_vtk.h"

#include "reference/io_util.h"

namespace uvr {

namespace {

template <class T>
void put_be(std::string& out, T v)
{
    v = byteswap_value(v);
    out.append(reinterpret_cast<const char*>(&v), sizeof v);
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
    // VTK's legacy reader takes the array name up to whitespace: spaces would cut it.
    std::string name = f.name.empty() ? "scalars" : f.name;
    for (char& c : name)
        if (c == ' ' || c == '\t') c = '_';
    out += "\nPOINT_DATA " + std::to_string(mesh.points.size()) + "\nSCALARS " + name + " double 1\nLOOKUP_TABLE default\n";
    for (double v : f.values) put_be(out, v);
    out += "\n";
    write_file_atomically(path, out);
}

}  // namespace uvr
