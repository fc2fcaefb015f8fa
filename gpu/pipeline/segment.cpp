#include "gpu/pipeline/segment.h"

#include <algorithm>

#include <glm/geometric.hpp>

#include "reference/timing.h"

namespace uvr::gpu {

double longest_tet_edge(const TetMesh& mesh)
{
    double longest = 0.0;
    for (const Tet& t : mesh.tets) {
        if (is_degenerate(mesh, t)) continue;
        for (int a = 0; a < 4; ++a)
            for (int b = a + 1; b < 4; ++b)
                longest = std::max(longest, glm::length(mesh.points[t[a]] - mesh.points[t[b]]));
    }
    return longest;
}

std::unique_ptr<PreintegrationTable> build_segment_table(const SegmentIntegrator& integrator, const Range& range,
                                                         int size, TexelFormat format, double max_length, double& ms)
{
    const auto t0 = Clock::now();
    PreintegrationConfig cfg;
    cfg.scalar_resolution = cfg.length_resolution = size;
    cfg.format = format;
    cfg.max_length = max_length;
    auto table = std::make_unique<PreintegrationTable>(integrator, range, cfg);
    ms = ms_since(t0);
    return table;
}

std::optional<TableSegmentShader> table_segment_shader(const PreintegrationTable* table, TextureFilter filter)
{
    if (!table) return std::nullopt;
    const TextureView view = table->view();
    // The path table->sample (sample_3d) takes on this host, called directly.
    if (!takes_linear_f32x4_fma(view, filter, host_llvmpipe_cpu())) return std::nullopt;
    return TableSegmentShader{view};
}

SegmentShader segment_shader(const PreintegrationTable* table, TextureFilter filter,
                             const SegmentIntegrator& integrator, const Range& range)
{
    if (table) {
        if (const std::optional<TableSegmentShader> fast = table_segment_shader(table, filter)) return *fast;
        const LlvmpipeCpu cpu = host_llvmpipe_cpu();
        return [table, filter, cpu](float uf, float ub, float tz, float) {
            return table->sample(uf, ub, tz, cpu, filter);
        };
    }
    const double lo = range.lo, span = range.hi > range.lo ? range.hi - range.lo : 1.0;
    return [&integrator, lo, span](float uf, float ub, float, float length) {
        return glm::vec4(integrator.integrate(lo + double(uf) * span, lo + double(ub) * span, double(length)));
    };
}

}  // namespace uvr::gpu
