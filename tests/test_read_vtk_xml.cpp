// VTK XML reader: the real .vtu/.vti files, a small .vtu written in every DataArray encoding, and bad input.
#include <algorithm>
#include <cstring>
#include <functional>

#include <catch2/catch.hpp>
#include <zlib.h>

#include "reference/dataset.h"
#include "reference/error.h"
#include "test_support.h"

namespace {

using uvr::test::data_path;
using uvr::test::file_contents;
using uvr::test::TempDir;

// Tetrahedron.vtu states the range of DistanceToCenter as 0..1.7320507765 (sqrt(3) in float32, printed to 11
// significant digits), so the stored float differs from the printed value by less than 1e-10.
constexpr double kPrintedRangeTolerance = 1e-9;

void require_input_error(const std::function<void()>& load, const std::string& file, const std::string& phrase)
{
    uvr::test::require_input_error(load, {file, phrase});
}

void require_xml_error(const std::string& path, const std::string& phrase)
{
    require_input_error([&] { uvr::read_vtk_xml(path); }, path, phrase);
}

std::string base64(const std::string& in)
{
    static const char* const kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (std::size_t i = 0; i < in.size(); i += 3) {
        uint32_t v = uint32_t(uint8_t(in[i])) << 16;
        if (i + 1 < in.size()) v |= uint32_t(uint8_t(in[i + 1])) << 8;
        if (i + 2 < in.size()) v |= uint32_t(uint8_t(in[i + 2]));
        out += kAlphabet[v >> 18 & 63];
        out += kAlphabet[v >> 12 & 63];
        out += i + 1 < in.size() ? kAlphabet[v >> 6 & 63] : '=';
        out += i + 2 < in.size() ? kAlphabet[v & 63] : '=';
    }
    return out;
}

// How the hand-written .vtu stores its arrays.
struct Encoding {
    std::string format = "ascii";      // ascii, binary, appended
    std::string appended = "raw";      // raw or base64, for format appended
    bool header64 = false;
    bool big_endian = false;
    bool zlib = false;
    std::size_t block_size = 16;       // small, so that arrays span several blocks and end in a partial one
};

template <class T>
std::string bytes_of(const std::vector<T>& values, bool big_endian)
{
    std::string out;
    for (T v : values) {
        char b[sizeof(T)];
        std::memcpy(b, &v, sizeof(T));
        if (big_endian) std::reverse(b, b + sizeof(T));
        out.append(b, sizeof(T));
    }
    return out;
}

std::string header_word(uint64_t v, const Encoding& e)
{
    return e.header64 ? bytes_of<uint64_t>({v}, e.big_endian) : bytes_of<uint32_t>({uint32_t(v)}, e.big_endian);
}

// The header and the (possibly compressed) data of one array, as separate byte strings.
std::pair<std::string, std::string> encode(const std::string& raw, const Encoding& e)
{
    if (!e.zlib) return {header_word(raw.size(), e), raw};
    const std::size_t blocks = (raw.size() + e.block_size - 1) / e.block_size;
    std::string header = header_word(blocks, e) + header_word(e.block_size, e) +
                         header_word(raw.size() % e.block_size, e);
    std::string data;
    for (std::size_t b = 0; b < blocks; ++b) {
        const std::string block = raw.substr(b * e.block_size, e.block_size);
        uLongf size = compressBound(block.size());
        std::string z(size, '\0');
        REQUIRE(compress2(reinterpret_cast<Bytef*>(z.data()), &size, reinterpret_cast<const Bytef*>(block.data()),
                          block.size(), 9) == Z_OK);
        header += header_word(size, e);
        data += z.substr(0, size);
    }
    return {header, data};
}

struct Array {
    std::string type, name;
    int components;
    std::string raw;    // binary values in the file's byte order
    std::string ascii;  // the same values as text
};

// A .vtu holding the small two-tetrahedron mesh with its arrays stored as `e` says.
std::string small_vtu(const Encoding& e)
{
    const std::vector<Array> point_data = {
        {"Float64", "temperature", 1, bytes_of<double>({0.5, 1, 2, 4, 8}, e.big_endian), "0.5 1 2 4 8"}};
    const std::vector<Array> points = {
        {"Float32", "Points", 3,
         bytes_of<float>({0, 0, 0, 1.5f, 0, 0, 0, 2.25f, 0, 0, 0, 3.125f, 1.5f, 2.25f, 3.125f}, e.big_endian),
         "0 0 0 1.5 0 0 0 2.25 0 0 0 3.125 1.5 2.25 3.125"}};
    const std::vector<Array> cells = {
        {"Int64", "connectivity", 1, bytes_of<int64_t>({0, 1, 2, 3, 1, 2, 3, 4}, e.big_endian), "0 1 2 3 1 2 3 4"},
        {"Int32", "offsets", 1, bytes_of<int32_t>({4, 8}, e.big_endian), "4 8"},
        {"UInt8", "types", 1, bytes_of<uint8_t>({10, 10}, e.big_endian), "10 10"}};
    std::string appended;
    auto element = [&](const Array& a) {
        std::string s = "<DataArray type=\"" + a.type + "\" Name=\"" + a.name + "\" NumberOfComponents=\"" +
                        std::to_string(a.components) + "\" format=\"" + e.format + "\"";
        const auto [header, data] = encode(a.raw, e);
        if (e.format == "ascii") return s + ">\n" + a.ascii + "\n</DataArray>\n";
        // VTK encodes a compressed array's header and data as two base64 runs, an uncompressed one as a single run.
        const std::string text = e.zlib ? base64(header) + base64(data) : base64(header + data);
        if (e.format == "binary") return s + ">\n" + text + "\n</DataArray>\n";
        s += " offset=\"" + std::to_string(appended.size()) + "\"/>\n";
        appended += e.appended == "raw" ? header + data : text;
        return s;
    };
    std::string xml = "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"" +
                      std::string(e.big_endian ? "BigEndian" : "LittleEndian") + "\" header_type=\"" +
                      (e.header64 ? "UInt64" : "UInt32") + "\"" +
                      (e.zlib ? " compressor=\"vtkZLibDataCompressor\"" : "") +
                      ">\n<UnstructuredGrid>\n<Piece NumberOfPoints=\"5\" NumberOfCells=\"2\">\n"
                      "<PointData Scalars=\"temperature\">\n";
    for (const Array& a : point_data) xml += element(a);
    xml += "</PointData>\n<Points>\n";
    for (const Array& a : points) xml += element(a);
    xml += "</Points>\n<Cells>\n";
    for (const Array& a : cells) xml += element(a);
    xml += "</Cells>\n</Piece>\n</UnstructuredGrid>\n";
    if (e.format == "appended")
        xml += "<AppendedData encoding=\"" + e.appended + "\">\n   _" + appended + "\n</AppendedData>\n";
    return xml + "</VTKFile>\n";
}

const std::vector<glm::dvec3> kPoints = {{0, 0, 0}, {1.5, 0, 0}, {0, 2.25, 0}, {0, 0, 3.125}, {1.5, 2.25, 3.125}};
const std::vector<uvr::Tet> kTets = {{0, 1, 2, 3}, {1, 2, 3, 4}};

void check_small_mesh(const uvr::Dataset& d)
{
    REQUIRE(d.mesh);
    CHECK(d.mesh->points == kPoints);
    CHECK(d.mesh->tets == kTets);
    REQUIRE(d.mesh->fields.size() == 1);
    CHECK(d.mesh->fields[0].name == "temperature");
    CHECK(d.mesh->fields[0].values == std::vector<double>{0.5, 1, 2, 4, 8});
}

std::string replaced(std::string s, const std::string& from, const std::string& to)
{
    const std::size_t at = s.find(from);
    REQUIRE(at != std::string::npos);
    return s.replace(at, from.size(), to);
}

}  // namespace

TEST_CASE("VTK XML reader reproduces the real data files", "[vtk][xml]")
{
    SECTION("Tetrahedron.vtu: appended raw data with UInt64 headers")
    {
        const auto d = uvr::read_vtk_xml(data_path("vtk-data/Tetrahedron.vtu"));
        REQUIRE(d.mesh);
        CHECK(d.mesh->points.size() == 35);
        CHECK(d.mesh->tets.size() == 96);
        REQUIRE(d.mesh->fields.size() == 2);
        CHECK(d.mesh->fields[0].name == "DistanceToCenter");
        CHECK(d.mesh->fields[1].name == "Polynomial");
        const uvr::Range dist = uvr::field_range(d.mesh->fields[0]), poly = uvr::field_range(d.mesh->fields[1]);
        INFO("DistanceToCenter " << dist.lo << " .. " << dist.hi << ", Polynomial " << poly.lo << " .. " << poly.hi);
        CHECK(dist.lo == 0.0);
        CHECK(dist.hi == Approx(1.7320507765).margin(kPrintedRangeTolerance));
        CHECK(poly.lo == 1.0);
        CHECK(poly.hi == 7.0);
    }
    SECTION("hydrogen.vti: zlib-compressed base64 Float32 volume")
    {
        const auto d = uvr::read_vtk_xml(data_path("vtk-data/hydrogen.vti"));
        REQUIRE(d.volume);
        CHECK(d.volume->dims == std::array<int64_t, 3>{64, 64, 64});
        CHECK(d.volume->type == uvr::VoxelType::f32);
        CHECK(d.volume->name == "probability_density");
        const uvr::Range r = uvr::volume_range(*d.volume);
        INFO("range " << r.lo << " .. " << r.hi);
        CHECK(r.lo >= 0.0);
        CHECK(r.hi == 1.0);
        CHECK(d.volume->origin == glm::dvec3(0.0));
        CHECK(d.volume->spacing == glm::dvec3(1.0));
    }
    SECTION("vase.vti: zlib-compressed UInt8 volume")
    {
        const auto d = uvr::read_vtk_xml(data_path("vtk-data/vase.vti"));
        REQUIRE(d.volume);
        CHECK(d.volume->dims == std::array<int64_t, 3>{115, 101, 75});
        CHECK(d.volume->type == uvr::VoxelType::u8);
        CHECK(d.volume->name == "SLCImage");
        const uvr::Range r = uvr::volume_range(*d.volume);
        INFO("range " << r.lo << " .. " << r.hi);
        CHECK(r.lo == 0.0);
        CHECK(r.hi == 239.0);
    }
}

TEST_CASE("VTK XML reader reads every DataArray encoding exactly", "[vtk][xml]")
{
    TempDir dir("vtk-xml");
    Encoding e;
    SECTION("ascii") {}
    SECTION("binary base64, UInt32 header") { e.format = "binary"; }
    SECTION("binary base64, UInt64 header")
    {
        e.format = "binary";
        e.header64 = true;
    }
    SECTION("appended raw") { e.format = "appended"; }
    SECTION("appended base64")
    {
        e.format = "appended";
        e.appended = "base64";
    }
    SECTION("binary base64, zlib blocks")
    {
        e.format = "binary";
        e.zlib = true;
    }
    SECTION("appended raw, zlib blocks, UInt64 header")
    {
        e.format = "appended";
        e.zlib = true;
        e.header64 = true;
    }
    SECTION("appended base64, zlib blocks")
    {
        e.format = "appended";
        e.appended = "base64";
        e.zlib = true;
    }
    SECTION("BigEndian, binary base64")
    {
        e.format = "binary";
        e.big_endian = true;
    }
    SECTION("BigEndian, appended raw, zlib blocks")
    {
        e.format = "appended";
        e.big_endian = true;
        e.zlib = true;
    }
    INFO("format " << e.format << " (" << e.appended << "), header " << (e.header64 ? 64 : 32) << ", "
                   << (e.big_endian ? "big" : "little") << "-endian, zlib " << e.zlib);
    check_small_mesh(uvr::read_vtk_xml(dir.write("small.vtu", small_vtu(e))));
}

TEST_CASE("VTK XML reader joins pieces and shifts image extents and skips unused arrays", "[vtk][xml]")
{
    TempDir dir("vtk-xml-layout");
    SECTION("two pieces are joined, their point indices shifted")
    {
        Encoding e;
        const std::string one = small_vtu(e);
        const std::size_t begin = one.find("<Piece"), end = one.find("</Piece>") + 8;
        const std::string piece = one.substr(begin, end - begin);
        const std::string text = one.substr(0, end) + piece + one.substr(end);
        const auto d = uvr::read_vtk_xml(dir.write("pieces.vtu", text));
        REQUIRE(d.mesh);
        CHECK(d.mesh->points.size() == 10);
        REQUIRE(d.mesh->tets.size() == 4);
        CHECK(d.mesh->tets[3] == uvr::Tet{6, 7, 8, 9});
        REQUIRE(d.mesh->fields.size() == 1);
        CHECK(d.mesh->fields[0].values.size() == 10);
    }
    SECTION("multi-component point arrays are skipped with a warning; cell data is read as a cell field")
    {
        Encoding e;
        std::string text = replaced(small_vtu(e), "</PointData>",
                                    "<DataArray type=\"Float32\" Name=\"velocity\" NumberOfComponents=\"3\" "
                                    "format=\"ascii\">0 0 0 0 0 0 0 0 0 0 0 0 0 0 0</DataArray>\n</PointData>\n"
                                    "<CellData><DataArray type=\"Int32\" Name=\"id\" format=\"ascii\">1 2</DataArray>"
                                    "</CellData>");
        const auto d = uvr::read_vtk_xml(dir.write("extra.vtu", text));
        REQUIRE(d.mesh);
        CHECK(d.mesh->tets == kTets);
        CHECK(d.mesh->fields[0].values == std::vector<double>{0.5, 1, 2, 4, 8});
        const auto mentions = [&](const std::string& s) {
            return std::any_of(d.warnings.begin(), d.warnings.end(),
                               [&](const std::string& w) { return w.find(s) != std::string::npos; });
        };
        CHECK(mentions("'velocity'"));
        REQUIRE(d.mesh->fields.size() == 2);
        CHECK(d.mesh->fields[1].name == "id");
        CHECK(d.mesh->fields[1].association == uvr::FieldAssociation::cell);
        CHECK(d.mesh->fields[1].values == std::vector<double>{1, 2});
    }
    SECTION("an ImageData extent that does not start at 0 shifts the origin")
    {
        const std::string text =
            "<?xml version=\"1.0\"?>\n<VTKFile type=\"ImageData\" version=\"1.0\" byte_order=\"LittleEndian\">\n"
            "<ImageData WholeExtent=\"2 3 0 1 -1 0\" Origin=\"1 2 3\" Spacing=\"0.5 1 2\">\n"
            "<Piece Extent=\"2 3 0 1 -1 0\"><PointData>\n"
            "<DataArray type=\"Float32\" Name=\"vec\" NumberOfComponents=\"2\" format=\"ascii\">"
            "0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0</DataArray>\n"
            "<DataArray type=\"Int16\" Name=\"density\" format=\"ascii\">0 1 2 3 4 5 6 -7</DataArray>\n"
            "</PointData></Piece></ImageData></VTKFile>\n";
        const auto d = uvr::read_vtk_xml(dir.write("image.vti", text));
        REQUIRE(d.volume);
        CHECK(d.volume->dims == std::array<int64_t, 3>{2, 2, 2});
        CHECK(d.volume->origin == glm::dvec3(2, 2, 1));
        CHECK(d.volume->spacing == glm::dvec3(0.5, 1, 2));
        CHECK(d.volume->type == uvr::VoxelType::i16);
        CHECK(d.volume->name == "density");
        CHECK(d.volume->values == std::vector<float>{0, 1, 2, 3, 4, 5, 6, -7});
    }
}

TEST_CASE("VTK XML reader rejects bad input with a message naming the file", "[vtk][xml][errors]")
{
    TempDir dir("vtk-xml-bad");
    SECTION("truncated copies of Tetrahedron.vtu (appended raw)")
    {
        const std::string full = file_contents(data_path("vtk-data/Tetrahedron.vtu"));
        const std::size_t data = full.find('_', full.find("<AppendedData")) + 1;
        for (std::size_t cut : {std::size_t(700), full.find("<AppendedData") + 10, data, data + 100, data + 800,
                                data + 3000, data + 4600}) {
            INFO("cut at byte " << cut);
            require_xml_error(dir.write("tetra-cut.vtu", full.substr(0, cut)), "truncated");
        }
    }
    SECTION("truncated copies of hydrogen.vti (zlib, base64)")
    {
        const std::string full = file_contents(data_path("vtk-data/hydrogen.vti"));
        for (std::size_t cut : {std::size_t(300), std::size_t(1000), full.size() / 2, full.size() - 40}) {
            INFO("cut at byte " << cut);
            require_xml_error(dir.write("hydrogen-cut.vti", full.substr(0, cut)), "truncated");
        }
    }
    SECTION("hydrogen.vti with compressed data missing from the middle of its base64 text")
    {
        std::string text = file_contents(data_path("vtk-data/hydrogen.vti"));
        for (std::size_t removed : {std::size_t(4000), std::size_t(40000)}) {
            INFO(removed << " base64 characters removed");
            const std::string cut = std::string(text).erase(text.size() / 2, removed);
            require_xml_error(dir.write("hydrogen-short.vti", cut), "truncated");
        }
    }
    SECTION("XML that does not parse")
    {
        const std::string text = replaced(small_vtu(Encoding{}), "<Points>", "<Points <");
        require_xml_error(dir.write("bad.vtu", text), "XML does not parse at line");
    }
    SECTION("a missing required array")
    {
        const std::string text = replaced(small_vtu(Encoding{}), "Name=\"connectivity\"", "Name=\"conn\"");
        require_xml_error(dir.write("missing.vtu", text), "missing required array 'connectivity'");
    }
    SECTION("an array with fewer values than the piece needs")
    {
        const std::string text = replaced(small_vtu(Encoding{}), "0.5 1 2 4 8", "0.5 1 2 4");
        require_xml_error(dir.write("short.vtu", text), "holds 4 values, expected 5");
    }
    SECTION("an unknown DataArray type")
    {
        const std::string text =
            replaced(small_vtu(Encoding{}), "\"Float32\" Name=\"Points\"", "\"Float16\" Name=\"Points\"");
        require_xml_error(dir.write("type.vtu", text), "unknown type 'Float16'");
    }
    SECTION("a negative point index")
    {
        const std::string text = replaced(small_vtu(Encoding{}), "0 1 2 3 1 2 3 4", "0 1 2 3 1 -2 3 4");
        require_xml_error(dir.write("negative.vtu", text), "uses point -2");
    }
    SECTION("a point index out of range")
    {
        const std::string text = replaced(small_vtu(Encoding{}), "0 1 2 3 1 2 3 4", "0 1 2 3 1 2 3 5");
        require_xml_error(dir.write("range.vtu", text), "uses point 5");
    }
    SECTION("an unknown cell type")
    {
        const std::string text = replaced(small_vtu(Encoding{}), "10 10", "10 99");
        require_xml_error(dir.write("celltype.vtu", text), "unknown cell type 99");
    }
    SECTION("a root element other than VTKFile")
    {
        require_xml_error(dir.write("root.vtu", "<?xml version=\"1.0\"?>\n<Mesh/>\n"), "not a VTK XML file");
    }
    SECTION("an unsupported file type")
    {
        require_xml_error(dir.write("poly.vtp", "<VTKFile type=\"PolyData\"><PolyData/></VTKFile>"),
                          "unsupported VTK XML file type 'PolyData'");
    }
    SECTION("an empty file")
    {
        require_xml_error(dir.write("empty.vtu", ""), "empty file");
    }
    SECTION("a header claiming 10^12 points in a tiny file fails before allocating")
    {
        const char* const kBinaryPhrase = "3000000000000 Float32 values need 12000000000000";
        const std::pair<const char*, const char*> cases[] = {
            {"ascii", "needs 3000000000000 values"}, {"binary", kBinaryPhrase}, {"appended", kBinaryPhrase}};
        for (const auto& [format, phrase] : cases) {
            INFO(format);
            Encoding e;
            e.format = format;
            const std::string text =
                replaced(small_vtu(e), "NumberOfPoints=\"5\"", "NumberOfPoints=\"1000000000000\"");
            require_xml_error(dir.write("huge.vtu", text), phrase);
        }
    }
    SECTION("a zlib block table claiming an impossible expansion")
    {
        Encoding e;
        e.format = "appended";
        e.zlib = true;
        std::string text = replaced(small_vtu(e), "NumberOfPoints=\"5\"", "NumberOfPoints=\"1000000000\"");
        // The Points array then needs 12 GB: make its block table describe exactly that as 3 blocks of 4 GB, each
        // from the few compressed bytes that are really there.
        const std::size_t offset_attr = text.find("offset=\"", text.find("Name=\"Points\"")) + 8;
        const std::size_t points =
            text.find('_', text.find("<AppendedData")) + 1 + std::stoul(text.substr(offset_attr));
        const uint32_t words[3] = {3, 4000000000u, 0};
        std::memcpy(&text[points], words, sizeof words);
        require_xml_error(dir.write("bomb.vtu", text), "claims 4000000000 bytes from only");
    }
}
