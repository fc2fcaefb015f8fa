#include "gpu/vicp/vicp.h"

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstring>
#include <functional>
#include <type_traits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include "gpu/pipeline/exact_coverage.h"
#include "gpu/pipeline/rasterize.h"
#include "gpu/pipeline/clip_position.h"
#include "gpu/pipeline/denormals.h"
#include "gpu/pipeline/tiles.h"
#include "gpu/vicp/vicp_published_fragment.h"
#include "gpu/vicp/vicp_published_lanes.h"
#include "reference/error.h"
#include "reference/timing.h"

namespace uvr::gpu {

void store_vicp_frame(const std::vector<glm::vec4>& colour, const std::vector<VicpDiagnostics>& diag, int width,
                      int height, VicpFrame& out)
{
    const std::size_t npix = std::size_t(width) * std::size_t(height);
    out.image = Image(width, height);
    if (!diag.empty()) {
        out.fragments.resize(npix);
        out.ordering_errors.resize(npix);
    }
    VicpStats& st = out.stats;
    for_each_gl_pixel(width, height, [&](std::size_t p, std::size_t q) {
        std::memcpy(&out.image.rgba[4 * q], &colour[p][0], 4 * sizeof(float));
        if (diag.empty()) return;
        const VicpDiagnostics& d = diag[p];
        out.fragments[q] = d.fragments;
        out.ordering_errors[q] = d.ordering_errors;
        st.fragments += d.fragments;
        st.ordering_errors += d.ordering_errors;
        st.max_fragments = std::max(st.max_fragments, d.fragments);
    });
}

// Pixel p's diagnostics, or none when the frame keeps none.
static VicpDiagnostics* diagnostics_at(std::vector<VicpDiagnostics>& diag, std::size_t p)
{
    return diag.empty() ? nullptr : &diag[p];
}

void store_setup_stats(const VicpMesh& vm, const VicpFrameSetup& fs, VicpStats& st)
{
    st.table_ms = vm.table_ms();
    st.cells = vm.mesh().tets.size();
    st.drawn_cells = fs.stream.size();
    st.order = fs.order_stats;
    st.sort_ms = fs.sort_ms;
    st.project_ms = fs.project_ms;
    st.clipped_cells = fs.clipped_cells;
    st.culled_cells = fs.culled_cells;
    st.near_sections = fs.near_sections;
    st.fan_triangles = fs.fan_triangles();
    st.gpu_clipped = fs.gpu_clipped;
}

// --coverage exact: the cell covers the pixels whose rays cross it, its whole chord from the mesh's own points in
// double (the cut cells too: a chord starts at the eye at the earliest), composited as the fragment program does.
// A pixel's ray that only touches the cell (a chord of no length) is not covered.
void VicpRenderer::composite_exact_coverage(const VicpFrameConstants& fc, const VicpFrameSetup& fs, uint32_t slot,
                                            bool cut, const TileRect& tile, const SegmentShader& shade, int width,
                                            std::vector<glm::vec4>& fb, std::vector<VicpDiagnostics>& diag) const
{
    const VicpCell& cell = fs.stream[slot];
    // Pixels to test: the box of the cell's window positions, a pixel wider on each side than their float rounding
    // could hide; a cell the view cuts (some of its points may lie behind the eye) tests its whole tile.
    TileRect box = tile;
    if (!cut) {
        float x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
        for (uint32_t v : cell.v) {
            x0 = std::min(x0, fs.win[v].x);
            x1 = std::max(x1, fs.win[v].x);
            y0 = std::min(y0, fs.win[v].y);
            y1 = std::max(y1, fs.win[v].y);
        }
        box.px0 = std::max(box.px0, int(std::floor(x0)) - 1);
        box.px1 = std::min(box.px1, int(std::ceil(x1)) + 1);
        box.py0 = std::max(box.py0, int(std::floor(y0)) - 1);
        box.py1 = std::min(box.py1, int(std::ceil(y1)) + 1);
    }
    const VicpTet tet = mesh_.constants(cell, mesh_.points_d());
    for (int py = box.py0; py <= box.py1; ++py)
        for (int px = box.px0; px <= box.px1; ++px) {
            const VicpSegment seg = vicp_fragment_values(fc, tet, px, py);
            // No length, no exit (the ray lies in the plane of every face it could leave by; its length is then
            // kVicpNoExit times the ray direction's length, which is near 1, against chords of a mesh's size), or
            // parallel to a face and outside it: not crossed.
            if (seg.misses || !(seg.t_out > seg.t_in) || !(seg.length < 1e-10 * kVicpNoExit)) continue;
            const std::size_t p = std::size_t(py) * std::size_t(width) + std::size_t(px);
            vicp_composite(fc, seg, fb[p], shade, diagnostics_at(diag, p));
        }
}

// --interpolation gpu: the published programs on a whole cell: ProjectTet's records, VertexProg at each front face's
// vertices, the varyings through the interpolation stage, FragmentProg's exit, today's compositing. The segment's
// distance from the eye (the ordering-error diagnostic's) is the interpolated entry point's
// (vicp_published_entry_distance); the wrong-exit and length diagnostics compare with the exact variant's segment,
// which only the emulation computes.
template <class Shade>
void VicpRenderer::composite_published(const VicpFrameConstants& fc, const VicpFrameSetup& fs, uint32_t slot,
                                       const VicpPublishedView& view, const std::vector<SetupVertex>& setup,
                                       const TileRect& tile, ViewportArithmetic arith, const Shade& shade, int width,
                                       std::vector<glm::vec4>& fb, std::vector<VicpDiagnostics>& diag,
                                       std::vector<uint32_t>& wrong_exits, std::vector<float>& length_error) const
{
    const Framebuffer fbuf{fs.width, fs.height, RenderTarget::fbo};
    const VicpCell& cell = fs.stream[slot];
    bool have_records = false;
    VicpPublishedVertex records[12];
    VicpTet tet;
    for (int f = 0; f < 4; ++f) {
        const uint32_t v[3] = {cell.v[std::size_t(kVicpCorner[f][0])], cell.v[std::size_t(kVicpCorner[f][1])],
                               cell.v[std::size_t(kVicpCorner[f][2])]};
        const WindowCoord wv[3] = {fs.win[v[0]], fs.win[v[1]], fs.win[v[2]]};
        const TriangleSetup ts = setup_triangle(wv, fbuf);
        if (ts.empty() || ts.facing != Facing::front) continue;
        if (!have_records) {
            mesh_.published_records(cell, fs.points_f, records);
            if (diagnostics_) tet = mesh_.constants(cell, fs.snapped);  // the exact segment's
            have_records = true;
        }
        const SetupVertex sv[3] = {setup[v[0]], setup[v[1]], setup[v[2]]};
        VicpPublishedVaryings vary[3];
        for (int j = 0; j < 3; ++j) vary[j] = vicp_published_vertex_program(view, records[3 * f + j]);
        const VicpPublishedPlanes planes = vicp_published_planes(sv, vary, ts);
        if constexpr (std::is_same_v<Shade, TableSegmentShader>) {
            if (!diagnostics_ && vicp_published_lanes_available(arith)) {  // the same bits, eight fragments at once
                FragmentBatch batch;
                for_each_fragment_in_tile(ts, tile, [&](int px, int py) {
                    batch.px[batch.n] = px;
                    batch.py[batch.n] = py;
                    if (++batch.n < FragmentBatch::kLanes) return;
                    composite_published_lanes(planes, fc, shade, batch, width, fb.data());
                    batch.n = 0;
                });
                if (batch.n > 0) composite_published_lanes(planes, fc, shade, batch, width, fb.data());
                continue;
            }
        }
        // The ordering-error diagnostic's entry point (vicp_published_entry_distance): the vertex positions, `smooth`.
        AttributePlane entry_planes[3];
        for (int c = 0; c < (diagnostics_ ? 3 : 0); ++c) {
            const float x[3] = {records[3 * f].position[c], records[3 * f + 1].position[c],
                                records[3 * f + 2].position[c]};
            entry_planes[c] = attribute_plane(planes.setup, sv, x, Qualifier::smooth);
        }
        for_each_fragment_in_tile(ts, tile, [&](int px, int py) {
            const float factor = perspective_factor(planes.setup, px, py, arith);  // shared by every smooth input
            const VicpPublishedExit e = vicp_published_exit(vicp_published_varyings_at(planes, px, py, factor, arith));
            const std::size_t p = std::size_t(py) * std::size_t(width) + std::size_t(px);
            double t_in = 0.0;  // the segment's distance from the eye serves the diagnostics only
            if (diagnostics_) {
                glm::vec3 entry;
                interpolate(entry_planes, 3, Qualifier::smooth, px, py, factor, arith, &entry[0]);
                t_in = double(vicp_published_entry_distance(view, entry));
            }
            const VicpSegment seg{e.s_front, e.s_back, t_in, t_in + double(e.length), e.length};
            vicp_composite(fc, seg, fb[p], shade, diagnostics_at(diag, p));
            if (!diagnostics_) return;
            const VicpSegment exact = vicp_fragment_values(fc, tet, px, py);
            // A wrong exit: another face than the exact crossing's, or a segment where the exact ray has none (or the
            // reverse). Entry j is the face opposite the front face's corner j.
            const int chosen = e.face < 0 ? -1 : kVicpCorner[f][e.face];
            const int expected = exact.length > 0.0 ? exact.exit_face : -1;
            if (chosen != expected) ++wrong_exits[p];
            // The length error: the interpolated segment against the exact one (none where the ray misses the cell).
            const double exact_length = exact.length > 0.0 ? exact.length : 0.0;
            length_error[p] = std::max(length_error[p], float(std::abs(double(e.length) - exact_length)));
        });
    }
}

VicpRenderer::VicpRenderer(const TetMesh& mesh, const MeshTopology& topo, std::size_t field, const TransferFunction& tf,
                           const VicpOptions& options, bool diagnostics)
    : mesh_(mesh, topo, field, tf, options), diagnostics_(diagnostics)
{
}

namespace {

constexpr uint32_t kWholeCell = UINT32_MAX;

// Which stream slots hold a cell the view cuts, and its index in fs.cuts (kWholeCell for a whole cell).
class CutSlots {
public:
    explicit CutSlots(const VicpFrameSetup& fs)
    {
        if (fs.cuts.empty()) return;
        of_slot_.assign(fs.stream.size(), kWholeCell);
        for (uint32_t i = 0; i < fs.cuts.size(); ++i) of_slot_[fs.cuts[i].slot] = i;
    }
    uint32_t operator()(uint32_t slot) const { return of_slot_.empty() ? kWholeCell : of_slot_[slot]; }

private:
    std::vector<uint32_t> of_slot_;
};

// The stream's cells binned into screen tiles by the bounding boxes of the points they are drawn with: their four
// points, or their fans' vertices for the cells the view cuts.
void bin_cells(const VicpFrameSetup& fs, const CutSlots& cut_index, ScreenTiles& tiles)
{
    tiles.bin(fs.stream.size(), [&](std::size_t slot) {
        const uint32_t c = cut_index(uint32_t(slot));
        if (c == kWholeCell) return tiles.range(fs.win, fs.stream[slot].v.data(), 4);
        ScreenTiles::Range r;  // the hull of the fan triangles' boxes: the box of all their vertices
        for (uint32_t k = fs.cuts[c].first; k < fs.cuts[c].first + fs.cuts[c].count; ++k)
            r = r.hull(tiles.range(fs.win, &fs.fans[4 * std::size_t(k)], 3));
        return r;
    });
}

// The exact variant on one cell in one tile (and, in both modes, a cell the view cuts): each triangle rasterized, its
// fragments through the fragment program when it is front-facing by llvmpipe's fixed-point area (only the faces the
// eye sees from outside the cell make fragments; GL discards the others on gl_FrontFacing, shaders/vicp.frag).
void composite_exact_interpolation(const VicpMesh& mesh, const VicpFrameSetup& fs, uint32_t slot, uint32_t cut,
                                   const TileRect& tile, const Framebuffer& fbuf, const SegmentShader& shade,
                                   std::vector<glm::vec4>& fb, std::vector<VicpDiagnostics>& diag)
{
    const VicpFrameConstants& fc = fs.constants;
    bool have_constants = false;
    VicpTet tet;
    const auto draw = [&](const uint32_t v0, const uint32_t v1, const uint32_t v2) {
        const WindowCoord wv[3] = {fs.win[v0], fs.win[v1], fs.win[v2]};
        const TriangleSetup ts = setup_triangle(wv, fbuf);
        if (ts.empty() || ts.facing != Facing::front) return;
        for_each_fragment_in_tile(ts, tile, [&](int px, int py) {
            if (!have_constants) {
                tet = mesh.constants(fs.stream[slot], fs.snapped);  // the vertex program's flat outputs
                have_constants = true;
            }
            const std::size_t p = std::size_t(py) * std::size_t(fbuf.width) + std::size_t(px);
            const VicpSegment seg = vicp_fragment_values(fc, tet, px, py);
            vicp_composite(fc, seg, fb[p], shade, diagnostics_at(diag, p));
        });
    };
    if (cut == kWholeCell) {
        const Tet& t = fs.stream[slot].v;
        for (int f = 0; f < 4; ++f) draw(t[kVicpCorner[f][0]], t[kVicpCorner[f][1]], t[kVicpCorner[f][2]]);
        return;
    }
    for (uint32_t k = fs.cuts[cut].first; k < fs.cuts[cut].first + fs.cuts[cut].count; ++k) {
        const uint32_t* tri = &fs.fans[4 * std::size_t(k)];
        draw(tri[0], tri[1], tri[2]);
    }
}

// What the GL driver sends of the published stream under its default (--send covered): the faces that make fragments.
uint64_t published_sent_faces(const VicpFrameSetup& fs, const CutSlots& cut_index)
{
    return tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, fs.stream.size()), uint64_t(0),
        [&](const tbb::blocked_range<std::size_t>& r, uint64_t n) {
            for (std::size_t slot = r.begin(); slot != r.end(); ++slot)
                if (cut_index(uint32_t(slot)) == kWholeCell)
                    n += uint64_t(std::popcount(vicp_sent_faces(fs, fs.stream[slot], TriangleSubmission::covered)));
            return n;
        },
        std::plus<uint64_t>());
}

}  // namespace

VicpFrame VicpRenderer::render(const Camera& cam, int width, int height) const
{
    VicpFrame out;
    VicpStats& st = out.stats;
    const VicpFrameSetup fs = setup_vicp_frame(mesh_, cam, width, height);
    const VicpFrameConstants& fc = fs.constants;
    store_setup_stats(mesh_, fs, st);
    const Framebuffer fbuf{width, height, RenderTarget::fbo};
    const bool exact_coverage = mesh_.options().coverage == Coverage::exact;
    const bool published = mesh_.options().interpolation == InterpolationMode::gpu;
    if (published && exact_coverage)
        throw InputError(mesh_.mesh().source,
                         "--interpolation gpu with --algo vicp takes the rasterizer's coverage only");

    // Set-up: the tiles; with the published program, what attribute setup receives of each vertex.
    auto t0 = Clock::now();
    const CutSlots cut_index(fs);
    ScreenTiles tiles(width, height);
    bin_cells(fs, cut_index, tiles);
    st.setup_ms = fs.vertex_ms + ms_since(t0);
    const SegmentShader shade =
        segment_shader(mesh_.table(), mesh_.options().filter, mesh_.integrator(), mesh_.range());
    const std::optional<TableSegmentShader> table_path = table_segment_shader(mesh_.table(), mesh_.options().filter);
    const std::size_t npix = std::size_t(width) * std::size_t(height);
    std::vector<glm::vec4> fb(npix, glm::vec4(0.0f));
    std::vector<VicpDiagnostics> diag(diagnostics_ ? npix : 0);
    t0 = Clock::now();
    std::vector<SetupVertex> setup;
    const bool exits = published && diagnostics_;         // the wrong exits and length errors
    std::vector<uint32_t> wrong_exits(exits ? npix : 0);  // per pixel, GL rows
    std::vector<float> length_error(exits ? npix : 0);
    if (published) {
        const FlushDenormals llvmpipe_mxcsr;  // the draw module's viewport transform runs so (gpu/pipeline/denormals.h)
        setup.resize(fs.points_f.size());
        for (std::size_t i = 0; i < setup.size(); ++i)
            setup[i] = setup_vertex(vertex_position(fs.view, fs.points_f[i]).data(), fbuf);
    }
    const VicpPublishedView published_view = vicp_published_view(cam);
    const ViewportArithmetic arith = host_viewport_arithmetic();

    // Raster per tile, each cell in stream order.
    tiles.visit([&](const TileRect& tile, const std::vector<uint32_t>& items) {
        for (uint32_t slot : items) {
            const uint32_t cut = cut_index(slot);
            if (exact_coverage) composite_exact_coverage(fc, fs, slot, cut != kWholeCell, tile, shade, width, fb, diag);
            // The cells the view cuts are drawn by the exact variant in both modes: the published vertex program
            // cannot give a clipped face's new vertices or a near section their distances (docs/vicp.md, "The cells
            // a view cuts, with the published program").
            else if (published && cut == kWholeCell && table_path)
                composite_published(fc, fs, slot, published_view, setup, tile, arith, *table_path, width, fb, diag,
                                    wrong_exits, length_error);
            else if (published && cut == kWholeCell)
                composite_published(fc, fs, slot, published_view, setup, tile, arith, shade, width, fb, diag,
                                    wrong_exits, length_error);
            else
                composite_exact_interpolation(mesh_, fs, slot, cut, tile, fbuf, shade, fb, diag);
        }
    });
    st.raster_fragment_ms = ms_since(t0);
    if (published) st.sent_faces = published_sent_faces(fs, cut_index);

    store_vicp_frame(fb, diag, width, height, out);
    if (exits) {
        out.wrong_exits.resize(npix);
        out.length_error.resize(npix);
        for_each_gl_pixel(width, height, [&](std::size_t p, std::size_t q) {
            out.wrong_exits[q] = wrong_exits[p];
            out.length_error[q] = length_error[p];
            st.wrong_exits += wrong_exits[p];
            st.max_length_error = std::max(st.max_length_error, double(length_error[p]));
        });
    }
    return out;
}

}  // namespace uvr::gpu
