// What one ray segment between two fragments contributes, shared by the projection algorithms (HAVS, VICP) and the
// ray caster's pre-integrated mode: the pre-integrated table as llvmpipe samples it, or the exact integral (emulation
// only). Inputs: the two normalized scalars, the table's length coordinate and the length. Output: premultiplied RGBA.
// Twins: shaders/preintegration_table.frag (the lookup), gpu/gl/gl_preintegration_table.h (its upload).
// Derivation of the table and its coordinates: docs/tables.md.
#pragma once

#include <functional>
#include <memory>
#include <optional>

#include <glm/vec4.hpp>

#include "gpu/pipeline/preintegration_table.h"
#include "reference/mesh.h"
#include "reference/segment_integral.h"
#include "reference/choice.h"

namespace uvr::gpu {

enum class SegmentMode { table, exact };
inline constexpr Choices<SegmentMode, 2> kSegmentModes{
    {{SegmentMode::table, "table", "the pre-integrated table"},
     {SegmentMode::exact, "exact", "the segment's integral in closed form; emulation only"}}};

// What the table lookup (or, in emulation, the exact integral) returns for the segment from entry `front` to entry
// `back`: u_front = |front.x| - 1, u_back = |back.x| - 1, t_z = (back.y - front.y) * length_scale + length_bias.
using SegmentShader = std::function<glm::vec4(float u_front, float u_back, float t_z, float length)>;

// the longest edge of the mesh's non-degenerate tetrahedra (no segment inside one cell is longer: the table's range);
double longest_tet_edge(const TetMesh& mesh);
// the pre-integrated table of `integrator` over `range` with `size` texels per axis up to `max_length`, and the
// milliseconds its build took. A table is a pure function of those inputs, so the process keeps the most recent one
// and hands it to the next renderer that asks for the same inputs (the transfer function compared node by node); `ms`
// is then the build's time, as when it was built (docs/tables.md, "Building a table once");
std::shared_ptr<const PreintegrationTable> build_segment_table(const SegmentIntegrator& integrator, const Range& range,
                                                               int size, TexelFormat format, double max_length,
                                                               double& ms);
// how many tables build_segment_table has built in this process (the ones it handed out again not counted).
std::size_t segment_tables_built();
// what a segment contributes: the table as llvmpipe samples it, or, without a table (--segment exact), the exact
// integral in double of the segment between the normalized scalars.
SegmentShader segment_shader(const PreintegrationTable* table, TextureFilter filter,
                             const SegmentIntegrator& integrator, const Range& range);

// The table's usual path (RGBA32F, linear, a host with FMA3: sample_linear_f32x4_fma) as a plain callable, which a
// program can call without std::function's indirection; segment_shader returns the same calls. nullopt where
// segment_shader takes another path.
struct TableSegmentShader {
    TextureView view;
    glm::vec4 operator()(float u_front, float u_back, float t_z, float /*length*/) const
    {
        const float coord[3] = {u_front, u_back, t_z};
        return sample_linear_f32x4_fma(view, coord, 3);
    }
};
std::optional<TableSegmentShader> table_segment_shader(const PreintegrationTable* table, TextureFilter filter);

// The exact integral (no table) as a plain callable; segment_shader returns the same calls. `many` gives n segments'
// results at once, each the bits operator() gives it (SegmentIntegrator::integrate_many's lanes).
struct ExactSegmentShader {
    const SegmentIntegrator* integrator;
    double lo, span;  // the normalized scalars' range: s = lo + u * span
    glm::vec4 operator()(float u_front, float u_back, float /*t_z*/, float length) const
    {
        return glm::vec4(
            integrator->integrate(lo + double(u_front) * span, lo + double(u_back) * span, double(length)));
    }
    // out[i] = operator()(u_front[i], u_back[i], -, length[i]) for i < n <= kMaxMany.
    static constexpr std::size_t kMaxMany = 8;
    void many(std::size_t n, const float* u_front, const float* u_back, const float* length, glm::vec4* out) const;
};
// The exact shader where there is no table; nullopt where segment_shader takes the table.
std::optional<ExactSegmentShader> exact_segment_shader(const PreintegrationTable* table,
                                                       const SegmentIntegrator& integrator, const Range& range);

}  // namespace uvr::gpu
