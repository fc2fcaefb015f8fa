#include "reference/write_vtk_xml.h"

#include <cstdio>
#include <cstring>

#include "reference/io_util.h"

namespace uvr {

namespace {

// Appended raw data: each array is a UInt64 byte count followed by its bytes (the machine is little-endian,
// io_util.cpp), and its DataArray element gives its offset into the block.
class AppendedBlock {
public:
    template <class T>
    std::string add(const char* type, const std::string& name, int components, const std::vector<T>& values)
    {
        const std::string element = "<DataArray type=\"" + std::string(type) + "\" Name=\"" + escape_markup(name) +
                                    "\" NumberOfComponents=\"" + std::to_string(components) +
                                    "\" format=\"appended\" offset=\"" + std::to_string(bytes_.size()) + "\"/>\n";
        const uint64_t size = values.size() * sizeof(T);
        bytes_.append(reinterpret_cast<const char*>(&size), sizeof size);
        bytes_.append(reinterpret_cast<const char*>(values.data()), size);
        return element;
    }
    const std::string& bytes() const { return bytes_; }

private:
    std::string bytes_;
};

std::string field_arrays(AppendedBlock& block, const TetMesh& mesh, FieldAssociation association,
                         const std::vector<uint32_t>& kept_cells)
{
    std::string xml;
    for (const ScalarField& f : mesh.fields) {
        if (f.association != association) continue;
        if (association == FieldAssociation::point) {
            xml += block.add("Float64", f.name, 1, f.values);
        } else {
            std::vector<double> values;
            for (uint32_t c : kept_cells) values.push_back(f.values[c]);
            xml += block.add("Float64", f.name, 1, values);
        }
    }
    return xml;
}

}  // namespace

void write_vtu(const std::string& path, const TetMesh& mesh)
{
    std::vector<uint32_t> kept;
    for (uint32_t c = 0; c < mesh.tets.size(); ++c)
        if (!is_degenerate(mesh, mesh.tets[c])) kept.push_back(c);
    std::vector<double> xyz;
    for (const glm::dvec3& p : mesh.points) xyz.insert(xyz.end(), {p.x, p.y, p.z});
    std::vector<int64_t> connectivity, offsets;
    for (uint32_t c : kept) {
        for (uint32_t v : mesh.tets[c]) connectivity.push_back(v);
        offsets.push_back(int64_t(connectivity.size()));
    }
    const std::vector<uint8_t> types(kept.size(), 10);  // VTK_TETRA

    AppendedBlock block;
    std::string xml =
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" "
        "byte_order=\"LittleEndian\" header_type=\"UInt64\">\n<UnstructuredGrid>\n<Piece "
        "NumberOfPoints=\"" +
        std::to_string(mesh.points.size()) + "\" NumberOfCells=\"" + std::to_string(kept.size()) + "\">\n";
    xml += "<PointData>\n" + field_arrays(block, mesh, FieldAssociation::point, kept) + "</PointData>\n";
    xml += "<CellData>\n" + field_arrays(block, mesh, FieldAssociation::cell, kept) + "</CellData>\n";
    xml += "<Points>\n" + block.add("Float64", "Points", 3, xyz) + "</Points>\n";
    xml += "<Cells>\n" + block.add("Int64", "connectivity", 1, connectivity) +
           block.add("Int64", "offsets", 1, offsets) + block.add("UInt8", "types", 1, types) + "</Cells>\n";
    xml += "</Piece>\n</UnstructuredGrid>\n<AppendedData encoding=\"raw\">\n_";
    xml += block.bytes();
    xml += "\n</AppendedData>\n</VTKFile>\n";
    write_file_atomically(path, xml);
}

namespace {

// One tuple of `values` as an ASCII DataArray of FieldData; 17 significant digits give every double back exactly.
std::string ascii_array(const std::string& name, const std::vector<double>& values)
{
    std::string text;
    char number[32];
    for (double v : values) {
        std::snprintf(number, sizeof number, "%.17g", v);
        text += (text.empty() ? "" : " ") + std::string(number);
    }
    return "<DataArray type=\"Float64\" Name=\"" + escape_markup(name) +
           "\" NumberOfTuples=\"1\" NumberOfComponents=\"" + std::to_string(values.size()) + "\" format=\"ascii\">" +
           text + "</DataArray>\n";
}

std::string whole_extent_xml(const WholeExtent& whole)
{
    const Bounds& b = whole.bounds;
    std::string xml = "<FieldData>\n" +
                      ascii_array(kWholeBoundsArray, {b.lo.x, b.lo.y, b.lo.z, b.hi.x, b.hi.y, b.hi.z}) +
                      ascii_array(kWholeLongestEdgeArray, {whole.longest_edge});
    for (const auto& [name, range] : whole.ranges) xml += ascii_array(kWholeRangePrefix + name, {range.lo, range.hi});
    return xml + "</FieldData>\n";
}

}  // namespace

void write_pvtu(const std::string& path, const TetMesh& like, const std::vector<std::string>& pieces,
                const WholeExtent* whole)
{
    auto declarations = [&](FieldAssociation association) {
        std::string xml;
        for (const ScalarField& f : like.fields)
            if (f.association == association)
                xml +=
                    "<PDataArray type=\"Float64\" Name=\"" + escape_markup(f.name) + "\" NumberOfComponents=\"1\"/>\n";
        return xml;
    };
    std::string xml =
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"PUnstructuredGrid\" version=\"1.0\" "
        "byte_order=\"LittleEndian\" header_type=\"UInt64\">\n<PUnstructuredGrid GhostLevel=\"0\">\n";
    if (whole) xml += whole_extent_xml(*whole);
    xml += "<PPointData>\n" + declarations(FieldAssociation::point) + "</PPointData>\n";
    xml += "<PCellData>\n" + declarations(FieldAssociation::cell) + "</PCellData>\n";
    xml += "<PPoints>\n<PDataArray type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\"/>\n</PPoints>\n";
    for (const std::string& piece : pieces) xml += "<Piece Source=\"" + escape_markup(piece) + "\"/>\n";
    xml += "</PUnstructuredGrid>\n</VTKFile>\n";
    write_file_atomically(path, xml);
}

}  // namespace uvr
