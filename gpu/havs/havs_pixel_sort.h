// --k all (kEveryFragment, gpu/havs/havs_setup.h): the k-buffer as deep as each pixel's fragments, emulated by
// keeping a tile's fragments and sorting each pixel's once. The same bits as the k-buffer program at any k at least
// the pixel's fragment count (tests/test_havs_pixel_sort.cpp), at the memory of one tile's fragments instead of k
// entries for every pixel, and in n log n steps a pixel instead of n k. Emulation only (a GPU's k-buffer has a fixed
// depth). With --ties facing (TieOrder, gpu/havs/havs_setup.h) back faces go first at one distance: uvr's exact order,
// not a k-buffer's. Derivation (why the program's order is distance, then arrival): docs/havs.md, "k = all".
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <vector>

#include "gpu/havs/havs_kbuffer.h"
#include "gpu/pipeline/tiles.h"

namespace uvr::gpu {

// The nearest distance the sorted path takes: two different distances at least this far from 0 differ by a normal
// float (the smaller one's ulp is at least 2^-125), so the program's difference t = d - y, computed with denormals
// flushed, is 0 exactly when the distances are equal, and its sign is the comparison's. A pixel with a distance below
// it (or NaN, or not nearer than the flush fragment) runs the program itself with k = its fragment count (and so the
// program's ties, whatever --ties says).
inline constexpr float kPixelSortNearest = 0x1p-102f;

// One tile's fragments, in arrival order (operator()), then composited pixel by pixel (close) into the frame's
// colour `fb` and diagnostics `diag` (or null), GL rows, `width` pixels a row, through segment shader `shade`.
template <class Shade>
class PixelSortTile {
public:
    // facing_ties: --ties facing (TieOrder, havs_setup.h).
    PixelSortTile(const TileRect& tile, const HavsFrameConstants& fc, glm::vec4* fb, KBufferDiagnostics* diag,
                  int width, const Shade& shade, bool facing_ties = false)
        : tile_(tile), fc_(fc), fb_(fb), diag_(diag), width_(width), shade_(shade), facing_ties_(facing_ties)
    {
    }

    // A fragment of a triangle the rasterizer sees back-facing (`back_facing`) or not.
    void operator()(const KEntry& e, int px, int py, bool back_facing)
    {
        pixel_.push_back(uint16_t((py - tile_.py0) * ScreenTiles::kTile + (px - tile_.px0)));
        entry_.push_back(e);
        if (facing_ties_) front_.push_back(back_facing ? 0 : 1);
    }

    // Each pixel's fragments as the k-buffer program with k at least their count leaves them: the runs composite
    // only empty fronts (nothing), the buffer holds the fragments by distance descending and, at one distance, the
    // newest in the lowest slot; the flush takes them out by distance ascending, at one distance the higher slot
    // first, so the older fragment first.
    void close()
    {
        const HavsFrameConstants& fc = fc_;
        constexpr int kTilePixels = ScreenTiles::kTile * ScreenTiles::kTile;  // a uint16_t holds a tile's pixel
        // Counting sort by pixel: each pixel's fragments contiguous, in arrival order.
        std::vector<uint32_t> start(kTilePixels + 1, 0);
        for (uint16_t p : pixel_) ++start[std::size_t(p) + 1];
        for (int p = 0; p < kTilePixels; ++p) start[std::size_t(p) + 1] += start[std::size_t(p)];
        std::vector<KEntry> by_pixel(entry_.size());
        std::vector<uint8_t> front_by_pixel(front_.size());
        {
            std::vector<uint32_t> next(start.begin(), start.end() - 1);
            for (std::size_t i = 0; i < entry_.size(); ++i) {
                if (facing_ties_) front_by_pixel[next[pixel_[i]]] = front_[i];
                by_pixel[next[pixel_[i]]++] = entry_[i];
            }
        }
        const float flush_y = fc.paper_entries ? kPaperFlushFragment.y : kFlushFragment.y;
        std::vector<uint64_t> keys;
        std::vector<KEntry> sorted;
        for (int local = 0; local < kTilePixels; ++local) {
            const uint32_t n = start[std::size_t(local) + 1] - start[std::size_t(local)];
            if (n == 0) continue;
            const KEntry* e = &by_pixel[start[std::size_t(local)]];
            const int px = tile_.px0 + local % ScreenTiles::kTile, py = tile_.py0 + local / ScreenTiles::kTile;
            const std::size_t p = std::size_t(py) * std::size_t(width_) + std::size_t(px);
            KBufferDiagnostics* d = diag_ ? diag_ + p : nullptr;
            bool plain = true;  // every distance in [kPixelSortNearest, flush): the order below is the program's
            for (uint32_t i = 0; i < n; ++i) plain = plain && e[i].y >= kPixelSortNearest && e[i].y < flush_y;
            if (!plain) {
                run_program(e, n, fb_[p], d);
                continue;
            }
            // Sort keys: a positive float's bits order as the float does; then, with --ties facing, back faces
            // first (bit 31); then the arrival index (n < 2^31: a tile holds far fewer fragments).
            keys.resize(n);
            const uint8_t* front = facing_ties_ ? &front_by_pixel[start[std::size_t(local)]] : nullptr;
            for (uint32_t i = 0; i < n; ++i) {
                uint32_t bits;
                std::memcpy(&bits, &e[i].y, sizeof bits);
                keys[i] = (uint64_t(bits) << 32) | (front ? uint64_t(front[i]) << 31 : 0) | i;
            }
            std::sort(keys.begin(), keys.end());
            sorted.resize(n);
            for (uint32_t i = 0; i < n; ++i) sorted[i] = e[keys[i] & 0x7fffffffu];  // the arrival index
            // The program's bookkeeping: every fragment reached it (the pixel's alpha is 0 until the flush, so no
            // kill), and after the last run all of them are held.
            if (d) {
                d->fragments += n;
                d->max_held = std::max(d->max_held, n);
            }
            kbuffer_program::composite_in_order(
                fc, int(n), [&](int i) { return sorted[std::size_t(i)]; }, fb_[p], shade_, d);
        }
        pixel_.clear();
        entry_.clear();
        front_.clear();
    }

private:
    // The definition itself: the program on a buffer of k = n entries, then the flush.
    void run_program(const KEntry* e, uint32_t n, glm::vec4& fb, KBufferDiagnostics* d) const
    {
        std::vector<KEntry> buffer(n, kEmptyEntry);
        for (uint32_t i = 0; i < n; ++i) kbuffer_program::run<0>(fc_, e[i], buffer.data(), int(n), fb, shade_, d);
        kbuffer_program::flush(fc_, buffer.data(), int(n), fb, shade_, d);
    }

    TileRect tile_;
    const HavsFrameConstants& fc_;
    glm::vec4* fb_;
    KBufferDiagnostics* diag_;
    int width_;
    const Shade& shade_;
    bool facing_ties_;
    std::vector<uint16_t> pixel_;
    std::vector<KEntry> entry_;
    std::vector<uint8_t> front_;  // --ties facing: 0 for a back-facing triangle's fragment, 1 otherwise
};

}  // namespace uvr::gpu
