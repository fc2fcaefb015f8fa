// Tetrahedral OFF: the OFF surface format with tetrahedra in place of faces.
//
// The accepted dialect, line by line ('#' starts a comment; blank lines are skipped):
//   OFF [nverts ncells [nedges]]      the keyword, optionally followed by the counts on the same line
//   nverts ncells [nedges]            the counts, when they were not on the keyword's line (nedges is ignored)
//   x y z [scalar]                    nverts lines; the optional fourth column becomes the point field "scalar" and
//                                     must then be present on every vertex line
//   4 a b c d [...]                   ncells lines; 0-based vertex indices; anything after the four indices (a
//                                     colour, as surface OFF allows) is ignored
// A file whose cells all have 3 vertices is a surface OFF and is refused as such; any other cell that is not a
// tetrahedron is an error naming its line. The format is read line by line because a missing or extra column would
// otherwise shift every later value into the wrong place without any error.
#include <charconv>
#include <cstdlib>
#include <string>
#include <string_view>
#include <vector>

#include "reference/dataset.h"
#include "reference/error.h"
#include "reference/io_util.h"

namespace uvr {

namespace {

class LineReader {
public:
    LineReader(std::string_view text, const std::string& file) : sc_(text, file, false) {}

    // The next line that holds something other than blanks and a comment, split into tokens; false at end of file.
    bool next(std::vector<std::string_view>& tokens)
    {
        while (!sc_.at_end()) {
            std::string_view line = sc_.line_rest();
            line = line.substr(0, line.find('#'));
            tokens.clear();
            std::size_t pos = 0;
            while ((pos = line.find_first_not_of(" \t\r\f\v", pos)) != std::string_view::npos) {
                std::size_t end = line.find_first_of(" \t\r\f\v", pos);
                tokens.push_back(line.substr(pos, end - pos));
                pos = end;
            }
            if (!tokens.empty()) return true;
        }
        return false;
    }
    [[noreturn]] void fail(const std::string& what) const { sc_.fail(what); }

    int64_t integer(std::string_view tok, const char* what) const
    {
        int64_t v = 0;
        auto [p, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), v);
        if (ec != std::errc() || p != tok.data() + tok.size())
            fail(std::string("expected ") + what + " (an integer), found '" + std::string(tok.substr(0, 40)) + "'");
        return v;
    }
    double real(std::string_view tok, const char* what) const
    {
        std::string s(tok);
        char* end = nullptr;
        double v = std::strtod(s.c_str(), &end);
        if (end != s.c_str() + s.size())
            fail(std::string("expected ") + what + " (a number), found '" + s.substr(0, 40) + "'");
        return v;  // nan and inf pass, so that finalize_mesh can name the point
    }

private:
    TextScanner sc_;
};

// The keyword and the counts (on its line or the next), checked against the file's size.
void read_counts(LineReader& lr, std::vector<std::string_view>& tok, const std::string& path, const std::string& text,
                 int64_t& nverts, int64_t& ncells)
{
    if (!lr.next(tok)) throw InputError(path, "empty file: expected the OFF keyword");
    if (tok[0] != "OFF")
        lr.fail("not an OFF file: expected the keyword 'OFF' on the first line, found '" +
                std::string(tok[0].substr(0, 40)) + "'");
    tok.erase(tok.begin());
    if (tok.empty() && !lr.next(tok)) lr.fail("unexpected end of file, expected the vertex and cell counts");
    if (tok.size() < 2 || tok.size() > 3) lr.fail("expected the counts 'nverts ncells [nedges]'");
    nverts = lr.integer(tok[0], "number of vertices");
    ncells = lr.integer(tok[1], "number of cells");
    if (nverts < 0 || ncells < 0) lr.fail("negative vertex or cell count");
    // Each vertex line holds at least "x y z\n" (6 bytes) and each cell line "4 a b c d\n" (10 bytes).
    if (uint64_t(nverts) > text.size() / 6 || uint64_t(ncells) > text.size() / 10 ||
        uint64_t(nverts) * 6 + uint64_t(ncells) * 10 > text.size())
        lr.fail("the counts declare " + std::to_string(nverts) + " vertices and " + std::to_string(ncells) +
                " cells, but the file (" + std::to_string(text.size()) + " bytes) is too small to hold them");
}

// The vertex lines: the points, and the field "scalar" when they have a fourth column.
void read_vertices(LineReader& lr, std::vector<std::string_view>& tok, int64_t nverts, TetMesh& mesh)
{
    mesh.points.resize(nverts);
    ScalarField scalar{"scalar", {}};
    for (int64_t v = 0; v < nverts; ++v) {
        if (!lr.next(tok))
            lr.fail("the counts declare " + std::to_string(nverts) + " vertices, but the file ends after " +
                    std::to_string(v));
        if (tok.size() != 3 && tok.size() != 4)
            lr.fail("vertex " + std::to_string(v) + " has " + std::to_string(tok.size()) +
                    " values; expected x y z or x y z scalar");
        bool has_scalar = tok.size() == 4;
        if (v == 0 && has_scalar) scalar.values.resize(nverts);
        if (has_scalar != !scalar.values.empty())
            lr.fail("vertex " + std::to_string(v) + (has_scalar ? " has" : " lacks") +
                    " a scalar column, unlike vertex 0; every vertex line must have the same columns");
        for (int axis = 0; axis < 3; ++axis) mesh.points[v][axis] = lr.real(tok[axis], "coordinate");
        if (has_scalar) scalar.values[v] = lr.real(tok[3], "scalar");
    }
    if (!scalar.values.empty()) mesh.fields.push_back(std::move(scalar));
}

// The cell lines: the tetrahedra. Returns how many cells were triangles: a surface OFF is told apart from a broken
// tetrahedral one only once every cell has been seen to be a triangle (then none is stored).
int64_t read_cells(LineReader& lr, std::vector<std::string_view>& tok, int64_t nverts, int64_t ncells, TetMesh& mesh)
{
    mesh.tets.reserve(ncells);
    int64_t triangles = 0;
    for (int64_t c = 0; c < ncells; ++c) {
        if (!lr.next(tok))
            lr.fail("the counts declare " + std::to_string(ncells) + " cells, but the file ends after " +
                    std::to_string(c));
        int64_t corners = lr.integer(tok[0], "number of cell vertices");
        if (corners == 3 && triangles == c) {
            ++triangles;
            continue;
        }
        if (triangles > 0)
            lr.fail("cell " + std::to_string(c) + " has " + std::to_string(corners) + " vertices, but cells 0 to " +
                    std::to_string(c - 1) + " are triangles; a tetrahedral OFF needs 4 vertices per cell");
        if (corners != 4)
            lr.fail("cell " + std::to_string(c) + " has " + std::to_string(corners) +
                    " vertices; a tetrahedral OFF needs 4 per cell");
        if (tok.size() < 5) lr.fail("cell " + std::to_string(c) + " lists fewer than 4 vertex indices");
        Tet t{};
        for (int k = 0; k < 4; ++k) {
            int64_t v = lr.integer(tok[1 + k], "vertex index");
            if (v < 0 || v >= nverts)
                lr.fail("cell " + std::to_string(c) + " refers to vertex " + std::to_string(v) +
                        ", but the vertices are numbered 0 to " + std::to_string(nverts - 1));
            t[k] = static_cast<uint32_t>(v);
        }
        mesh.tets.push_back(t);
    }
    return triangles;
}

}  // namespace

Dataset read_off(const std::string& path)
{
    std::string text = read_file_bytes(path);
    LineReader lr(text, path);
    std::vector<std::string_view> tok;
    int64_t nverts = 0, ncells = 0;
    read_counts(lr, tok, path, text, nverts, ncells);

    Dataset result;
    TetMesh mesh;
    mesh.source = path;
    read_vertices(lr, tok, nverts, mesh);
    const int64_t triangles = read_cells(lr, tok, nverts, ncells, mesh);
    if (triangles > 0)
        throw InputError(path, "no 3D cell: all " + std::to_string(triangles) +
                                   " cells are triangles, so this is a surface OFF; uvr needs tetrahedra");
    if (lr.next(tok))
        lr.fail("unexpected data after the " + std::to_string(ncells) + " declared cells (is the cell count wrong?)");

    std::size_t flipped = finalize_mesh(mesh);
    if (flipped) result.warnings.push_back(path + ": re-oriented " + std::to_string(flipped) + " inverted tetrahedra");
    result.mesh = std::move(mesh);
    return result;
}

}  // namespace uvr
