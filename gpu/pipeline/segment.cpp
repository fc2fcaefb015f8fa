#include "gpu/pipeline/segment.h"

#include <algorithm>
#include <mutex>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>

#include "reference/timing.h"
#include "reference/transfer_function.h"

namespace uvr::gpu {

double longest_tet_edge(const TetMesh& mesh)
{
    double longest = 0.0;
    for (const Tet& t : mesh.tets) {
        double edge = 0.0;
        for (int a = 0; a < 4; ++a)
            for (int b = a + 1; b < 4; ++b) edge = std::max(edge, glm::length(mesh.points[t[a]] - mesh.points[t[b]]));
        // Only a tetrahedron that would lengthen the answer is asked whether it is flat (the costlier test).
        if (edge > longest && !is_degenerate(mesh, t)) longest = edge;
    }
    return longest;
}

namespace {

// Everything a segment table depends on; two keys are equal exactly when the tables would be the same bits.
struct TableKey {
    std::vector<ColorNode> color;
    std::vector<ExtinctionNode> extinction;
    Range range;
    int size = 0;
    TexelFormat format = TexelFormat::f32;
    double max_length = 0.0;

    bool operator==(const TableKey& o) const
    {
        auto same_color = [](const ColorNode& a, const ColorNode& b) { return a.s == b.s && a.rgb == b.rgb; };
        auto same_tau = [](const ExtinctionNode& a, const ExtinctionNode& b) { return a.s == b.s && a.tau == b.tau; };
        return std::equal(color.begin(), color.end(), o.color.begin(), o.color.end(), same_color) &&
               std::equal(extinction.begin(), extinction.end(), o.extinction.begin(), o.extinction.end(), same_tau) &&
               range.lo == o.range.lo && range.hi == o.range.hi && size == o.size && format == o.format &&
               max_length == o.max_length;
    }
};

// The most recent table, its key and its build time. One entry: a sweep over k, an emulated frame beside its GL twin
// and a budget's factor runs ask for the same table in a row, and a held table costs its size in memory.
struct TableCache {
    std::mutex mutex;
    TableKey key;  // the inputs of `table`, when there is one
    std::shared_ptr<const PreintegrationTable> table;
    double ms = 0.0;
    std::size_t built = 0;
};

TableCache& table_cache()
{
    static TableCache cache;
    return cache;
}

}  // namespace

std::shared_ptr<const PreintegrationTable> build_segment_table(const SegmentIntegrator& integrator, const Range& range,
                                                               int size, TexelFormat format, double max_length,
                                                               double& ms)
{
    const TransferFunction& tf = integrator.transfer_function();
    TableKey key{tf.color, tf.extinction, range, size, format, max_length};
    TableCache& cache = table_cache();
    {
        const std::lock_guard<std::mutex> lock(cache.mutex);
        if (cache.table && cache.key == key) {
            ms = cache.ms;
            return cache.table;
        }
        cache.table.reset();  // not held through the build: a process never holds two tables for the cache's sake
    }
    // Built outside the lock (the build runs TBB tasks); two threads asking at once build the same bits twice.
    const auto t0 = Clock::now();
    PreintegrationConfig cfg;
    cfg.scalar_resolution = cfg.length_resolution = size;
    cfg.format = format;
    cfg.max_length = max_length;
    auto table = std::make_shared<const PreintegrationTable>(integrator, range, cfg);
    ms = ms_since(t0);
    const std::lock_guard<std::mutex> lock(cache.mutex);
    cache.key = std::move(key);
    cache.table = table;
    cache.ms = ms;
    ++cache.built;
    return table;
}

std::size_t segment_tables_built()
{
    const std::lock_guard<std::mutex> lock(table_cache().mutex);
    return table_cache().built;
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
    return *exact_segment_shader(nullptr, integrator, range);
}

std::optional<ExactSegmentShader> exact_segment_shader(const PreintegrationTable* table,
                                                       const SegmentIntegrator& integrator, const Range& range)
{
    if (table) return std::nullopt;
    return ExactSegmentShader{&integrator, range.lo, range.hi > range.lo ? range.hi - range.lo : 1.0};
}

void ExactSegmentShader::many(std::size_t n, const float* u_front, const float* u_back, const float* length,
                              glm::vec4* out) const
{
    double sf[kMaxMany] = {}, sb[kMaxMany] = {}, len[kMaxMany] = {};
    glm::dvec4 rgba[kMaxMany];
    for (std::size_t i = 0; i < n; ++i) {
        sf[i] = lo + double(u_front[i]) * span;
        sb[i] = lo + double(u_back[i]) * span;
        len[i] = double(length[i]);
    }
    integrator->integrate_many(n, sf, sb, len, rgba);
    for (std::size_t i = 0; i < n; ++i) out[i] = glm::vec4(rgba[i]);
}

}  // namespace uvr::gpu
