// `uvr partition MESH --parts N --out DIR`: the mesh split into parts, written as DIR/NAME.pvtu and one .vtu piece per
// part (docs/distributed.md).
#include <cstdio>
#include <filesystem>
#include <optional>

#include <glm/common.hpp>
#include <nlohmann/json.hpp>

#include "bench/commands.h"
#include "bench/options.h"
#include "bench/scene.h"
#include "gpu/pipeline/segment.h"
#include "reference/dataset.h"
#include "reference/error.h"
#include "reference/partition.h"
#include "reference/write_vtk_xml.h"

namespace uvr::cli {

namespace {

struct PartitionOptions {
    SceneOptions scene;  // the input; the view for --balance view
    uint32_t parts = 0;
    std::string method = "rcb";     // kPartitionMethods
    std::string balance = "cells";  // kPartitionBalances
    std::string out;
    bool json = false;
};

// NAME: the input's file name without its extension (builtin:torus gives torus).
std::string output_name(const std::string& path)
{
    const std::string name = std::filesystem::path(path).stem().string();
    const std::size_t colon = name.rfind(':');
    return colon == std::string::npos ? name : name.substr(colon + 1);
}

// Joins `piece`'s extent into `whole` (`first`: the first piece): bounds, longest edge, every field's range.
void join_extent(WholeExtent& whole, const TetMesh& piece, bool first)
{
    const Bounds b = mesh_bounds(piece);
    const double longest = gpu::longest_tet_edge(piece);
    if (first) {
        whole = {b, longest, {}};
        for (const ScalarField& f : piece.fields) whole.ranges.push_back({f.name, field_range(f)});
        return;
    }
    whole.bounds.lo = glm::min(whole.bounds.lo, b.lo);
    whole.bounds.hi = glm::max(whole.bounds.hi, b.hi);
    whole.longest_edge = std::max(whole.longest_edge, longest);
    for (std::size_t i = 0; i < piece.fields.size(); ++i) {
        const Range r = field_range(piece.fields[i]);
        Range& to = whole.ranges[i].second;
        to = {std::min(to.lo, r.lo), std::max(to.hi, r.hi)};
    }
}

// Writes every piece, then the .pvtu with the whole mesh's extent as the ranks will find it: joined from each piece
// read back as a rank reads it (the reader's own checks and re-orientation applied). A failure removes what was
// written, so DIR holds all of it or none of it.
nlohmann::json write_parts(const TetMesh& mesh, const std::vector<uint32_t>& part_of, uint32_t parts,
                           const std::string& dir, const std::string& name)
{
    std::vector<std::string> pieces, written;
    WholeExtent whole;
    nlohmann::json report = nlohmann::json::array();
    try {
        for (uint32_t p = 0; p < parts; ++p) {
            const TetMesh part = extract_part(mesh, part_of, p);
            pieces.push_back(name + "_" + std::to_string(p) + ".vtu");
            written.push_back(dir + "/" + pieces.back());
            write_vtu(written.back(), part);
            join_extent(whole, *read_vtk_xml(written.back()).mesh, p == 0);
            report.push_back(
                {{"piece", pieces.back()}, {"tetrahedra", part.tets.size()}, {"points", part.points.size()}});
        }
        written.push_back(dir + "/" + name + ".pvtu");
        write_pvtu(written.back(), mesh, pieces, &whole);
    } catch (...) {
        std::error_code ec;
        for (const std::string& f : written) std::filesystem::remove(f, ec);
        throw;
    }
    return report;
}

// Per tetrahedron, its steps in the scene's view, traced by the reference (view_steps): what --balance view balances.
std::vector<uint64_t> steps_in_view(const Scene& s)
{
    const RayIntegrator integrator(s.mesh(), *s.topology, s.field, s.tf);
    return view_steps(integrator, s.mesh().tets.size(), s.camera, s.width, s.height);
}

}  // namespace

void register_partition(CLI::App& app)
{
    auto* cmd = app.add_subcommand("partition", "Split a mesh into parts: DIR/NAME.pvtu and one .vtu piece per part");
    auto o = std::make_shared<PartitionOptions>();
    add_scene_options(*cmd, o->scene);
    cmd->add_option("--parts", o->parts, "Number of parts (1 to the number of tetrahedra)")->required();
    cmd->add_option("--method", o->method, choices_help(kPartitionMethods))->capture_default_str();
    cmd->add_option("--balance", o->balance, choices_help(kPartitionBalances))->capture_default_str();
    cmd->add_option("--out", o->out, "Output directory")->required();
    cmd->add_flag("--json", o->json, "Print the parts as one JSON object on stdout");
    cmd->callback([o, cmd] {
        const PartitionMethod method = parse_choice("--method", kPartitionMethods, o->method);
        const PartitionBalance balance = parse_choice("--balance", kPartitionBalances, o->balance);
        if (balance == PartitionBalance::cells)
            for (const char* view_option : {"--tf", "--camera", "--view", "--size"})
                if (cmd->count(view_option) > 0)
                    throw InputError("", std::string(view_option) + " sets the view that --balance view balances for");
        Dataset d = load_input(o->scene.input);
        if (!d.mesh)
            throw InputError(o->scene.input.path, "uvr partition splits tetrahedral meshes, not regular grids");
        print_warnings(d);
        std::optional<Scene> view;  // holds the mesh from here on where it is set
        std::vector<uint64_t> steps;
        if (balance == PartitionBalance::view) {
            view.emplace(setup_scene(std::move(d), o->scene));
            steps = steps_in_view(*view);
        }
        const TetMesh& mesh = view ? view->mesh() : *d.mesh;
        const std::vector<uint32_t> part_of = partition_mesh(mesh, o->parts, method, view ? &steps : nullptr);
        std::error_code ec;
        std::filesystem::create_directories(o->out, ec);
        if (ec) throw InputError(o->out, "cannot create the directory: " + ec.message());
        const std::string name = output_name(o->scene.input.path);
        const nlohmann::json parts = write_parts(mesh, part_of, o->parts, o->out, name);
        const nlohmann::json j = {
            {"file", o->out + "/" + name + ".pvtu"}, {"method", o->method}, {"balance", o->balance}, {"parts", parts}};
        if (o->json) {
            std::printf("%s\n", j.dump(1).c_str());
            return;
        }
        std::printf("%s: %u parts by %s, balancing %s\n", j["file"].get<std::string>().c_str(), o->parts,
                    o->method.c_str(), o->balance.c_str());
        for (const auto& p : parts)
            std::printf("  %-24s %zu tetrahedra, %zu points\n", p["piece"].get<std::string>().c_str(),
                        p["tetrahedra"].get<std::size_t>(), p["points"].get<std::size_t>());
    });
}

}  // namespace uvr::cli
