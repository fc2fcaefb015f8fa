#include "gpu/havs/havs.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>

#include <unistd.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "gpu/havs/havs_kbuffer.h"
#include "gpu/havs/havs_pixel_sort.h"
#include "gpu/havs/havs_paper_span.h"
#include "gpu/pipeline/rasterize.h"
#include "gpu/pipeline/denormals.h"
#include "gpu/pipeline/exact_coverage.h"
#include "gpu/pipeline/huge_pages.h"
#include "gpu/pipeline/tiles.h"
#include "reference/error.h"
#include "reference/timing.h"

namespace uvr::gpu {

namespace {

const HavsOptions& checked_k(const HavsOptions& options)
{
    if (options.k < 1 && options.k != kEveryFragment) throw InputError("", "--k must be at least 1, or all");
    if (options.ties == TieOrder::facing && options.k != kEveryFragment)
        throw InputError("", "--ties facing needs --k all: a k-buffer orders fragments at one distance by its slots");
    return options;
}

// The k-buffer program on each fragment as it arrives, for one tile (the frame's draw; `close` does nothing).
template <class Program>
struct KBufferTile {
    const Program& program;
    KEntry* kbuf;
    glm::vec4* fb;
    KBufferDiagnostics* diag;
    int width, k;
    void operator()(const KEntry& e, int px, int py, bool /*back_facing*/) const
    {
        const std::size_t p = std::size_t(py) * std::size_t(width) + std::size_t(px);
        program(e, kbuf + p * std::size_t(k), fb[p], diag ? diag + p : nullptr);
    }
    void close() const {}
};

// The emulated k-buffer holds k entries of 8 bytes a pixel. It may take at most half of the machine's memory, so
// that the mesh, its topology and the frame's other buffers still fit; a larger k is refused before any work.
void check_kbuffer_memory(int k, int width, int height)
{
    const double bytes = double(k) * double(width) * double(height) * double(sizeof(KEntry));
    const double physical = double(sysconf(_SC_PHYS_PAGES)) * double(sysconf(_SC_PAGESIZE));
    if (bytes > 0.5 * physical) {
        char msg[256];
        std::snprintf(msg, sizeof msg,
                      "--k %d at %dx%d needs a k-buffer of %.1f GiB, more than half of this machine's %.1f GiB; use a "
                      "smaller k or image",
                      k, width, height, bytes / 1073741824.0, physical / 1073741824.0);
        throw InputError("", msg);
    }
}

}  // namespace

void store_havs_frame(const glm::vec4* colour, const std::vector<KBufferDiagnostics>* diag, int width,
                      int height, HavsFrame& out)
{
    const std::size_t npix = std::size_t(width) * std::size_t(height);
    out.image = Image(width, height);
    if (diag) {
        out.fragments.resize(npix);
        out.max_held.resize(npix);
        out.ordering_errors.resize(npix);
    }
    HavsStats& st = out.stats;
    for_each_gl_pixel(width, height, [&](std::size_t p, std::size_t q) {
        std::memcpy(&out.image.rgba[4 * q], &colour[p][0], 4 * sizeof(float));
        if (!diag) return;
        const KBufferDiagnostics& d = (*diag)[p];
        out.fragments[q] = d.fragments;
        out.max_held[q] = d.max_held;
        out.ordering_errors[q] = d.ordering_errors;
        st.fragments += d.fragments;
        st.ordering_errors += d.ordering_errors;
        st.max_fragments = std::max(st.max_fragments, d.fragments);
        st.max_held = std::max(st.max_held, d.max_held);
    });
}

HavsFrameSetup begin_havs_frame(const HavsMesh& mesh, const Camera& cam, int width, int height, HavsStats& st)
{
    st.table_ms = mesh.table_ms();
    st.faces = mesh.face_count();
    HavsFrameSetup fs = setup_havs_frame(mesh, cam, width, height);
    st.sort_ms = fs.sort_ms;
    st.clipped_faces = fs.clipped_faces;
    st.culled_faces = fs.culled_faces;
    st.near_sections = fs.near_sections;
    st.gpu_clipped = fs.gpu_clipped;
    st.triangles = fs.draw.size();
    return fs;
}

HavsRenderer::HavsRenderer(const TetMesh& mesh, const MeshTopology& topo, std::size_t field,
                           const TransferFunction& tf, const HavsOptions& options, bool diagnostics)
    : mesh_(mesh, topo, field, tf, checked_k(options)), diagnostics_(diagnostics)
{
}

HavsRenderer::~HavsRenderer() = default;

namespace {

// What the raster stage of one frame reads: the frame's set-up, the binned triangles, the published varyings'
// vertices (--interpolation gpu) and the switches.
struct RasterInput {
    const HavsMesh& mesh;
    const HavsFrameSetup& fs;
    const ScreenTiles& tiles;
    const HavsPaperVertices& paper;
    Framebuffer fbuf;
    ViewportArithmetic arith;
    bool exact_coverage, paper_varyings;
};

// The triangles, in drawing order, binned into screen tiles by their window-space bounding boxes. With the
// rasterizer's coverage a triangle with no pixel centre in its snapped bounding box covers nothing (may_cover_pixel):
// it goes to no tile, as the GL drivers do not send it (havs_sent_triangles).
void bin_triangles(const HavsMesh& mesh, const HavsFrameSetup& fs, ScreenTiles& tiles)
{
    const bool snapped = mesh.options().coverage == Coverage::gpu;
    tiles.bin(fs.draw.size(), [&](std::size_t i) {
        if (i + kPrefetchAhead < fs.draw.size()) __builtin_prefetch(fs.triangle(mesh, fs.draw[i + kPrefetchAhead]));
        const uint32_t* v = fs.triangle(mesh, fs.draw[i]);
        const WindowCoord wv[3] = {fs.win[v[0]], fs.win[v[1]], fs.win[v[2]]};
        return snapped && !may_cover_pixel(wv) ? ScreenTiles::Range{} : tiles.range(fs.win, v, 3);
    });
}

// Draw item `i`'s fragments in `tile`, in arrival order, to sink(entry, px, py, back_facing). `entries`: scratch for a
// row span's entries (--interpolation gpu), kept by the caller for the whole tile.
template <class Sink>
void raster_triangle(const RasterInput& in, const TileRect& tile, uint32_t i, KEntry* entries, Sink& sink)
{
    const HavsFrameSetup& fs = in.fs;
    const uint32_t id = fs.draw[i];
    const uint32_t* v = fs.triangle(in.mesh, id);
    // Coverage: the rasterizer's (snapped) or the exact one. A boundary face is oriented outward, so it is an exit
    // face when the rasterizer sees it back-facing (clockwise in window coordinates: gl_FrontFacing false) and an
    // entry face otherwise. The facing comes from the coverage's own area (the rasterizer's snapped one, or the exact
    // one), so it agrees with the fragments even for slivers.
    const WindowCoord wv[3] = {fs.win[v[0]], fs.win[v[1]], fs.win[v[2]]};
    TriangleSetup ts = setup_triangle(wv, in.fbuf);
    ExactTriangle et;
    Facing facing = ts.facing;
    if (in.exact_coverage) {
        const glm::dvec2 p[3] = {{fs.win_d[v[0]].x, fs.win_d[v[0]].y},
                                 {fs.win_d[v[1]].x, fs.win_d[v[1]].y},
                                 {fs.win_d[v[2]].x, fs.win_d[v[2]].y}};
        et = exact_triangle(p, v);
        if (et.empty()) return;
        facing = et.facing;
        // A triangle the rasterizer would drop (zero snapped area) still needs an order for its planes: the one
        // llvmpipe gives a triangle of this facing in an FBO (front faces have a negative area there).
        if (ts.facing == Facing::none) ts.swap01 = facing == Facing::front;
    } else if (ts.empty()) {
        return;
    }
    const auto visit = [&](auto&& fragment) {
        if (in.exact_coverage)
            for_each_exact_fragment_in_tile(et, tile, fragment);
        else
            for_each_fragment_in_tile(ts, tile, fragment);
    };
    const bool back_facing = facing == Facing::back;  // --ties facing's key
    const auto apply = [&](const KEntry& e, int px, int py) { sink(e, px, py, back_facing); };
    const HavsFrameConstants& fc = fs.constants;
    if (!in.paper_varyings) {
        // --interpolation exact: flat per-face constants, in double, rounded once (what the CPU uploads).
        HavsFace face = havs_face_constants(in.mesh, fs, id);
        if (face.side == kSideExit && facing != Facing::back) face.side = kSideEntry;
        visit([&](int px, int py) { apply(havs_fragment_entry(fc, face, px, py, in.exact_coverage), px, py); });
        return;
    }
    // --interpolation gpu: the paper's varyings through the interpolation stage, the side a flat attribute.
    float side = havs_face_side(in.mesh, fs, id);
    if (side == kSideExit && facing != Facing::back) side = kSideEntry;
    const SetupVertex sv[3] = {in.paper.setup[v[0]], in.paper.setup[v[1]], in.paper.setup[v[2]]};
    const glm::vec3 eye[3] = {in.paper.eye[v[0]], in.paper.eye[v[1]], in.paper.eye[v[2]]};
    float s[3] = {fs.s_f[v[0]], fs.s_f[v[1]], fs.s_f[v[2]]};
    if (fc.paper_entries) {  // the mark travels in the scalar (havs_paper_exit), the side stays interior
        if (side == kSideExit)
            for (float& sj : s) sj = paper_exit_scalar(sj);
        side = kSideInterior;
    }
    const HavsVaryingPlanes planes = havs_varying_planes(sv, eye, s, side, ts);
    if (in.exact_coverage) {
        visit([&](int px, int py) { apply(havs_paper_entry(fc, havs_varyings_at(planes, px, py, in.arith)), px, py); });
        return;
    }
    // A row span at a time (havs_paper_span.h: the same bits as pixel by pixel), then each pixel's k-buffer in column
    // order, as the fragments arrive.
    for_each_span_in_tile(ts, tile, [&](int py, int first, int last) {
        havs_paper_entries(fc, planes, py, first, last, in.arith, entries);
        for (int px = first; px <= last; ++px) apply(entries[px - first], px, py);
    });
}

// The tiles in parallel: `open_tile(tile)` gives the tile's fragment sink, which takes the tile's fragments in arrival
// order, then sink.close() (KBufferTile: the k-buffer program as each fragment arrives; PixelSortTile: --k all).
template <class OpenTile>
void raster_tiles(const RasterInput& in, const OpenTile& open_tile)
{
    in.tiles.visit([&](const TileRect& tile, const std::vector<uint32_t>& items) {
        auto sink = open_tile(tile);
        // A span's entries (--interpolation gpu): made once a tile, as initializing them for every span took a
        // quarter of this loop's own time.
        KEntry entries[ScreenTiles::kTile];
        for (uint32_t i : items) raster_triangle(in, tile, i, entries, sink);
        sink.close();
    });
}

// The flush: what k full-screen passes of the flush fragment composite (havs_flush, the same bits). A pixel no
// fragment reached (every entry empty, the colour +0) is left as it is: its k runs composite empty segments, colour 0
// over +0, which changes no bit.
template <class Shade>
void flush_pixels(const HavsFrameConstants& fc, KEntry* kbuf, glm::vec4* fb, KBufferDiagnostics* diag_at,
                  std::size_t npix, int k, const Shade& shade)
{
    const glm::vec4 cleared(0.0f);
    const auto untouched = [&](std::size_t p) {
        if (std::memcmp(&fb[p], &cleared, sizeof cleared) != 0) return false;
        for (std::size_t i = p * std::size_t(k); i < (p + 1) * std::size_t(k); ++i)
            if (std::memcmp(&kbuf[i], &kEmptyEntry, sizeof kEmptyEntry) != 0) return false;
        return true;
    };
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, npix), [&](const tbb::blocked_range<std::size_t>& r) {
        const FlushDenormals llvmpipe_mxcsr;
        for (std::size_t p = r.begin(); p != r.end(); ++p)
            if (!untouched(p))
                kbuffer_program::flush(fc, &kbuf[p * std::size_t(k)], k, fb[p], shade, diag_at ? diag_at + p : nullptr);
    });
}

// Raster per tile. The paper's k with the table's usual path: the program instantiated with k fixed and the sample
// called directly (the same operations, so the same bits: tests/test_havs_kbuffer.cpp), which takes a tenth off the
// frame's raster+fragment time (docs/gl-backend.md, "Speed"). Anything else: the run-time instance. --k all: each
// pixel's fragments sorted once a tile (havs_pixel_sort.h), composited there.
void raster_stage(const RasterInput& in, const SegmentShader& shade,
                  const std::optional<TableSegmentShader>& table_path, KEntry* kbuf, glm::vec4* fb,
                  KBufferDiagnostics* diag_at, int width)
{
    const HavsFrameConstants& fc = in.fs.constants;
    const int k = in.mesh.options().k;
    const bool every_fragment = k == kEveryFragment;
    const auto kbuffer_tiles = [&](const auto& program) {
        raster_tiles(in, [&](const TileRect&) {
            return KBufferTile<std::decay_t<decltype(program)>>{program, kbuf, fb, diag_at, width, k};
        });
    };
    const auto pixel_sort_tiles = [&](const auto& shade_as) {
        raster_tiles(in, [&](const TileRect& tile) {
            return PixelSortTile<std::decay_t<decltype(shade_as)>>(tile, fc, fb, diag_at, width, shade_as,
                                                                   in.mesh.options().ties == TieOrder::facing);
        });
    };
    if (every_fragment && table_path) {
        pixel_sort_tiles(*table_path);
    } else if (every_fragment) {
        pixel_sort_tiles(shade);
    } else if (table_path && k == kbuffer_program::kPaperK) {
        kbuffer_tiles([&](KEntry e, KEntry* entries, glm::vec4& colour, KBufferDiagnostics* d) {
            return kbuffer_program::run<kbuffer_program::kPaperK>(fc, e, entries, k, colour, *table_path, d);
        });
    } else {
        kbuffer_tiles([&](KEntry e, KEntry* entries, glm::vec4& colour, KBufferDiagnostics* d) {
            return kbuffer_program::run<0>(fc, e, entries, k, colour, shade, d);
        });
    }
}

}  // namespace

HavsFrame HavsRenderer::render(const Camera& cam, int width, int height) const
{
    const int k = mesh_.options().k;
    const bool every_fragment = k == kEveryFragment;  // --k all: havs_pixel_sort.h, no k-buffer
    if (!every_fragment) check_kbuffer_memory(k, width, height);
    HavsFrame out;
    HavsStats& st = out.stats;
    // Set-up: the sorted faces, the vertex stage, the frame's constants; the tiles.
    const HavsFrameSetup fs = begin_havs_frame(mesh_, cam, width, height, st);
    const HavsFrameConstants& fc = fs.constants;
    auto t0 = Clock::now();
    ScreenTiles tiles(width, height);
    bin_triangles(mesh_, fs, tiles);
    st.setup_ms = fs.vertex_ms + fs.clip_ms + ms_since(t0);
    const bool paper_varyings = mesh_.options().interpolation == InterpolationMode::gpu;
    t0 = Clock::now();
    const HavsPaperVertices paper = paper_varyings ? havs_paper_vertices(fs) : HavsPaperVertices{};
    st.setup_ms += ms_since(t0);
    const RasterInput in{mesh_,
                         fs,
                         tiles,
                         paper,
                         Framebuffer{width, height, RenderTarget::fbo},
                         host_viewport_arithmetic(),
                         mesh_.options().coverage == Coverage::exact,
                         paper_varyings};

    // Per-pixel state, GL rows (from the bottom); the segment shader: the table as llvmpipe samples it, or the exact
    // integral in double.
    const std::size_t npix = std::size_t(width) * std::size_t(height);
    HugeVector<KEntry> kbuf(npix * std::size_t(k), kEmptyEntry);  // none under --k all
    HugeVector<glm::vec4> fb(npix, glm::vec4(0.0f));
    std::vector<KBufferDiagnostics> diag(diagnostics_ ? npix : 0);
    KBufferDiagnostics* const diag_at = diagnostics_ ? diag.data() : nullptr;  // pixel p's: diag_at + p
    const SegmentShader shade =
        segment_shader(mesh_.table(), mesh_.options().filter, mesh_.integrator(), mesh_.range());

    // Raster per tile (raster_stage), the table's direct sample found first.
    t0 = Clock::now();
    const std::optional<TableSegmentShader> table_path = table_segment_shader(mesh_.table(), mesh_.options().filter);
    raster_stage(in, shade, table_path, kbuf.data(), fb.data(), diag_at, width);
    st.raster_fragment_ms = ms_since(t0);

    // Flush (--k all composited with each tile), with the table's direct sample where the program had it.
    t0 = Clock::now();
    if (!every_fragment && table_path)
        flush_pixels(fc, kbuf.data(), fb.data(), diag_at, npix, k, *table_path);
    else if (!every_fragment)
        flush_pixels(fc, kbuf.data(), fb.data(), diag_at, npix, k, shade);
    st.flush_ms = ms_since(t0);

    store_havs_frame(fb.data(), diagnostics_ ? &diag : nullptr, width, height, out);
    return out;
}

}  // namespace uvr::gpu
