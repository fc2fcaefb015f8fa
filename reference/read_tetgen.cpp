// TetGen .node + .ele files (the format of TetGen's own output).
//
// .node: "<points> <dimension=3> <attributes> <boundary markers 0|1>", then per point "<index> x y z [attributes]
// [marker]". .ele: "<tetrahedra> <nodes per tet> <region attribute 0|1>", then "<index> a b c d [region]". '#' starts a
// comment. Point numbering starts at 0 or 1 as the first point's index says, and the .ele refers to points by those
// numbers. Point attributes become fields attribute0, attribute1, ...; boundary markers and regions carry no meaning
// for rendering and are skipped. Quadratic (10-node) tetrahedra are refused rather than silently linearised.
#include <string>

#include "reference/dataset.h"
#include "reference/error.h"
#include "reference/io_util.h"

namespace uvr {

namespace {

// Every record needs at least `tokens` whitespace-separated tokens of at least one character each; a header claiming
// more records than the file's bytes can hold is refused before anything is allocated from it.
void check_count_fits(TextScanner& sc, int64_t count, int64_t tokens, std::size_t bytes, const char* what)
{
    if (count < 0) sc.fail(std::string("negative number of ") + what + ": " + std::to_string(count));
    if (count > 0 && uint64_t(count) > bytes / (2 * uint64_t(tokens)) + 1)
        sc.fail("the header claims " + std::to_string(count) + " " + what + ", but the file (" + std::to_string(bytes) +
                " bytes) is far too small to hold them");
}

// A header integer that must lie in [lo, hi].
int64_t header_value(TextScanner& sc, const char* what, int64_t lo, int64_t hi)
{
    int64_t v = sc.integer(what);
    if (v < lo || v > hi)
        sc.fail(std::string(what) + " must be " + (lo == hi ? std::to_string(lo) : std::to_string(lo) + " to " +
                                                                                     std::to_string(hi)) +
                ", found " + std::to_string(v));
    return v;
}

// Reads the .node file into mesh.points and mesh.fields; returns the number of the first point (0 or 1).
int64_t read_node(const std::string& path, TetMesh& mesh)
{
    std::string text = read_file_bytes(path);
    TextScanner sc(text, path, true);
    if (sc.at_end()) throw InputError(path, "empty file: expected a TetGen .node header");
    int64_t count = sc.integer("number of points");
    header_value(sc, "dimension", 3, 3);
    int64_t attributes = header_value(sc, "number of attributes", 0, 1000);
    int64_t markers = header_value(sc, "boundary marker flag", 0, 1);
    check_count_fits(sc, count, 4 + attributes + markers, text.size(), "points");

    mesh.points.resize(count);
    for (int64_t a = 0; a < attributes; ++a) mesh.fields.push_back({"attribute" + std::to_string(a), {}});
    for (auto& f : mesh.fields) f.values.resize(count);
    int64_t base = 0;
    for (int64_t p = 0; p < count; ++p) {
        if (sc.at_end())
            sc.fail("the header declares " + std::to_string(count) + " points, but the file ends after " +
                    std::to_string(p));
        int64_t index = sc.integer("point index");
        if (p == 0) {
            if (index != 0 && index != 1)
                sc.fail("the first point must be numbered 0 or 1, found " + std::to_string(index));
            base = index;
        } else if (index != base + p) {
            sc.fail("points must be numbered consecutively: expected point " + std::to_string(base + p) + ", found " +
                    std::to_string(index));
        }
        for (int axis = 0; axis < 3; ++axis) mesh.points[p][axis] = sc.real("coordinate");
        for (auto& f : mesh.fields) f.values[p] = sc.real("point attribute");
        if (markers) sc.integer("boundary marker");
    }
    if (!sc.at_end()) {
        sc.token("");
        sc.fail("unexpected data after the " + std::to_string(count) + " declared points (is the count wrong?)");
    }
    return base;
}

void read_ele(const std::string& path, int64_t base, TetMesh& mesh)
{
    std::string text = read_file_bytes(path);
    TextScanner sc(text, path, true);
    if (sc.at_end()) throw InputError(path, "empty file: expected a TetGen .ele header");
    int64_t count = sc.integer("number of tetrahedra");
    int64_t corners = sc.integer("nodes per tetrahedron");
    if (corners == 10) sc.fail("10-node (quadratic) tetrahedra are not supported; write linear 4-node tetrahedra");
    if (corners != 4) sc.fail("nodes per tetrahedron must be 4, found " + std::to_string(corners));
    int64_t regions = header_value(sc, "region attribute flag", 0, 1);
    if (count > 0) check_tetrahedron_count(path, static_cast<std::size_t>(count));
    check_count_fits(sc, count, 5 + regions, text.size(), "tetrahedra");

    const int64_t points = static_cast<int64_t>(mesh.points.size());
    mesh.tets.resize(count);
    for (int64_t t = 0; t < count; ++t) {
        if (sc.at_end())
            sc.fail("the header declares " + std::to_string(count) + " tetrahedra, but the file ends after " +
                    std::to_string(t));
        sc.integer("tetrahedron index");
        for (int c = 0; c < 4; ++c) {
            int64_t v = sc.integer("point index");
            if (v < base || v >= base + points)
                sc.fail("tetrahedron " + std::to_string(t + base) + " refers to point " + std::to_string(v) +
                        ", but the points are numbered " + std::to_string(base) + " to " +
                        std::to_string(base + points - 1));
            mesh.tets[t][c] = static_cast<uint32_t>(v - base);
        }
        if (regions) sc.real("region attribute");
    }
    if (!sc.at_end()) {
        sc.token("");
        sc.fail("unexpected data after the " + std::to_string(count) + " declared tetrahedra (is the count wrong?)");
    }
}

}  // namespace

Dataset read_tetgen(const std::string& path)
{
    std::string ext = file_extension(path);
    std::string stem = (ext == ".node" || ext == ".ele") ? path.substr(0, path.size() - ext.size()) : path;
    const std::string node_path = stem + ".node", ele_path = stem + ".ele";

    Dataset result;
    TetMesh mesh;
    mesh.source = node_path;
    int64_t base = read_node(node_path, mesh);
    read_ele(ele_path, base, mesh);
    std::size_t flipped = finalize_mesh(mesh);
    if (flipped)
        result.warnings.push_back(ele_path + ": re-oriented " + std::to_string(flipped) + " inverted tetrahedra");
    result.mesh = std::move(mesh);
    return result;
}

}  // namespace uvr
