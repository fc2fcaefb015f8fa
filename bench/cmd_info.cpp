// `uvr info MESH [--json]`: what a data set holds (docs/spec.md §3).
#include <cstdio>

#include <nlohmann/json.hpp>

#include "bench/options.h"
#include "bench/commands.h"
#include "reference/field.h"
#include "reference/partition.h"
#include "reference/topology.h"

namespace uvr::cli {

namespace {

nlohmann::json vec3(const glm::dvec3& v) { return {v.x, v.y, v.z}; }

nlohmann::json describe_parts(const MeshTopology& topo, const std::vector<uint32_t>& piece_of_cell)
{
    nlohmann::json parts = nlohmann::json::array();
    for (const PartCounts& c : count_parts(topo, piece_of_cell))
        parts.push_back(
            {{"tetrahedra", c.tetrahedra}, {"boundary_faces", c.boundary_faces}, {"cut_faces", c.cut_faces}});
    return parts;
}

// `piece_of_cell`: a file of pieces (.pvtu) is also described piece by piece.
nlohmann::json describe_mesh(const TetMesh& mesh, const std::vector<uint32_t>& piece_of_cell)
{
    const MeshTopology topo = build_topology(mesh);
    nlohmann::json j;
    if (!piece_of_cell.empty()) j["parts"] = describe_parts(topo, piece_of_cell);
    const Bounds b = mesh_bounds(mesh);
    j["kind"] = "tetrahedral mesh";
    j["points"] = mesh.points.size();
    j["tetrahedra"] = mesh.tets.size();
    j["degenerate_tetrahedra"] = count_degenerate(mesh);
    j["faces"] = {{"unique", topo.faces.size()}, {"boundary", topo.boundary_faces}, {"internal", topo.internal_faces}};
    std::size_t repeated = 0;
    for (std::size_t i = 0; i < topo.canonical.size(); ++i) repeated += topo.canonical[i] != i ? 1 : 0;
    j["repeated_points"] = repeated;  // points at the position of a lower-numbered point (welded for adjacency)
    j["fields"] = nlohmann::json::array();
    for (const auto& f : mesh.fields) {
        const Range r = field_range(f);
        const FieldSummary fs = summarize_field(mesh, topo, f);
        j["fields"].push_back({{"name", f.name}, {"min", r.lo}, {"max", r.hi}, {"kind", field_kind_name(fs.kind)},
                               {"jump_faces", fs.jump_faces}});
    }
    j["bounds"] = {{"min", vec3(b.lo)}, {"max", vec3(b.hi)}};
    j["convex"] = boundary_is_convex(mesh, topo);
    j["volume"] = total_tet_volume(mesh);
    return j;
}

nlohmann::json describe_volume(const Volume& v)
{
    const Bounds b = volume_bounds(v);
    const Range r = volume_range(v);
    nlohmann::json j;
    j["kind"] = "regular grid";
    j["dims"] = {v.dims[0], v.dims[1], v.dims[2]};
    j["points"] = uint64_t(v.dims[0]) * uint64_t(v.dims[1]) * uint64_t(v.dims[2]);
    j["voxel_type"] = voxel_type_name(v.type);
    j["origin"] = vec3(v.origin);
    j["spacing"] = vec3(v.spacing);
    j["fields"] = {{{"name", v.name}, {"min", r.lo}, {"max", r.hi}, {"kind", "point"}, {"jump_faces", 0}}};
    j["bounds"] = {{"min", vec3(b.lo)}, {"max", vec3(b.hi)}};
    return j;
}

// What a format says of itself (Dataset::info): Exodus II's blocks, sets, variables and time steps.
void print_format(const nlohmann::json& f)
{
    const auto names = [](const nlohmann::json& list) {
        std::string s;
        for (const auto& x : list) s += (s.empty() ? "" : ", ") + (x.is_string() ? x.get<std::string>() : x.dump());
        return s.empty() ? std::string("none") : s;
    };
    std::printf("  format       %s\n", f.value("format", std::string("?")).c_str());
    for (const auto& b : f.value("blocks", nlohmann::json::array()))
        std::printf("  block        %s '%s': %s, %s elements\n", b.value("id", nlohmann::json()).dump().c_str(),
                    b.value("name", std::string()).c_str(), b.value("type", std::string()).c_str(),
                    b.value("elements", nlohmann::json()).dump().c_str());
    const std::pair<const char*, const char*> lists[] = {
        {"node_sets", "node sets"}, {"side_sets", "side sets"}, {"nodal_variables", "nodal vars"},
        {"element_variables", "element vars"}};
    for (const auto& [key, label] : lists)
        if (f.contains(key)) std::printf("  %-12s %s\n", label, names(f[key]).c_str());
    if (f.contains("times"))
        std::printf("  time steps   %zu (reading %s)\n", f["times"].size(),
                    f.value("time_step", nlohmann::json()).dump().c_str());
    if (f.contains("whole_extent"))
        std::printf("  recorded     the whole mesh's bounds, longest edge and field ranges (docs/distributed.md)\n");
}

void print_text(const nlohmann::json& j)
{
    std::printf("%s: %s\n", j["file"].get<std::string>().c_str(), j["kind"].get<std::string>().c_str());
    if (j["kind"] == "tetrahedral mesh") {
        std::printf("  points       %zu", j["points"].get<std::size_t>());
        if (j["repeated_points"] != 0)
            std::printf(" (%zu repeat a position: welded for adjacency, values kept)",
                        j["repeated_points"].get<std::size_t>());
        std::printf("\n");
        std::printf("  tetrahedra   %zu", j["tetrahedra"].get<std::size_t>());
        if (j["degenerate_tetrahedra"] != 0)
            std::printf(" (%zu flat, from collapsed grid cells)", j["degenerate_tetrahedra"].get<std::size_t>());
        std::printf("\n");
        std::printf("  faces        %zu unique (%zu boundary, %zu internal)\n", j["faces"]["unique"].get<std::size_t>(),
                    j["faces"]["boundary"].get<std::size_t>(), j["faces"]["internal"].get<std::size_t>());
        std::printf("  convex       %s\n", j["convex"].get<bool>() ? "yes" : "no");
    } else {
        std::printf("  dims         %lld x %lld x %lld (%s)\n", j["dims"][0].get<long long>(),
                    j["dims"][1].get<long long>(), j["dims"][2].get<long long>(),
                    j["voxel_type"].get<std::string>().c_str());
        std::printf("  spacing      %g %g %g\n", j["spacing"][0].get<double>(), j["spacing"][1].get<double>(),
                    j["spacing"][2].get<double>());
    }
    const auto& lo = j["bounds"]["min"];
    const auto& hi = j["bounds"]["max"];
    std::printf("  bounds       [%g, %g] x [%g, %g] x [%g, %g]\n", lo[0].get<double>(), hi[0].get<double>(),
                lo[1].get<double>(), hi[1].get<double>(), lo[2].get<double>(), hi[2].get<double>());
    if (j["fields"].empty()) std::printf("  fields       none\n");
    if (j.contains("format")) print_format(j["format"]);
    if (j.contains("parts"))
        for (std::size_t p = 0; p < j["parts"].size(); ++p)
            std::printf("  part %-7zu %zu tetrahedra, %zu boundary faces, %zu cut faces\n", p,
                        j["parts"][p]["tetrahedra"].get<std::size_t>(),
                        j["parts"][p]["boundary_faces"].get<std::size_t>(),
                        j["parts"][p]["cut_faces"].get<std::size_t>());
    for (const auto& f : j["fields"]) {
        std::printf("  field        %-20s [%.9g, %.9g]", f["name"].get<std::string>().c_str(), f["min"].get<double>(),
                    f["max"].get<double>());
        if (f.contains("kind"))
            std::printf(" %s, jumps across %zu faces", f["kind"].get<std::string>().c_str(),
                        f["jump_faces"].get<std::size_t>());
        std::printf("\n");
    }
}

}  // namespace

void register_info(CLI::App& app)
{
    auto* cmd = app.add_subcommand("info", "Describe a mesh or volume: counts, faces, fields, bounds, convexity");
    auto in = std::make_shared<InputOptions>();
    auto json = std::make_shared<bool>(false);
    add_input_options(*cmd, *in);
    cmd->add_flag("--json", *json, "Print one JSON object on stdout");
    cmd->callback([in, json] {
        const Dataset d = load_input(*in, true);
        print_warnings(d);
        nlohmann::json j = d.mesh ? describe_mesh(*d.mesh, d.piece_of_cell) : describe_volume(*d.volume);
        j["file"] = in->path;
        if (!d.info_json.empty()) j["format"] = nlohmann::json::parse(d.info_json);
        j["warnings"] = d.warnings;
        if (*json)
            std::printf("%s\n", j.dump(1).c_str());
        else
            print_text(j);
    });
}

}  // namespace uvr::cli
