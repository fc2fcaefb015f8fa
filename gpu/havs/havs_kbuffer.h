// HAVS's k-buffer program (the HAVS paper, Appendix II; the second part of havs_fragment.h's fragment stage), a
// template over the stored-entry count K (0: k given at run time) and the segment shader's type, and the flush after
// it. havs_kbuffer and havs_flush (havs_fragment.h) are their run-time k, SegmentShader instances (run_any_k: the
// chains branch); the emulated frame (havs.cpp) also runs the program for the paper's k = 6 with the table's usual path
// (TableSegmentShader: chains unrolled, selecting by conditional moves, the sample called directly), and the flush with
// that shader. The same operations, so the same bits (tests/test_havs_kbuffer.cpp). Derivation: docs/havs.md; speed:
// docs/gl-backend.md, "Speed".
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "gpu/havs/havs_fragment.h"

namespace uvr::gpu::kbuffer_program {

// The paper's k (three RGBA textures of two entries each), the k the emulated frame instantiates the program for.
inline constexpr int kPaperK = 6;

// The program's scratch on the stack holds this many entries (2 KiB, as before k was unbounded: the old limit of 255
// plus the incoming fragment); a larger run-time k takes a per-thread buffer.
inline constexpr int kStackEntries = 256;

// A real entry: neither empty nor a flush fragment (nearer than the encoding's flush distance, as
// havs_real_entry in shaders/havs_fragment.frag).
inline bool real_entry(const HavsFrameConstants& fc, const KEntry& e)
{
    return e.y > 0.0f && e.y < (fc.paper_entries ? kPaperFlushFragment.y : kFlushFragment.y);
}

// The normalized scalar of an entry (see the entry encoding in havs_fragment.h).
inline float decode_scalar(float x)
{
    const float m = std::fabs(x);
    return m < kSideOutside ? m - 1.0f : m < kSideEntry ? m * 0.25f - 1.0f : m * 0.0625f - 1.0f;
}

// The segment of one run of the program, from `front` to `second` (see havs_kbuffer): composited over `fb`, with the
// diagnostics. Returns whether `second` is to be marked an exit in the buffer. Shared by the program and the flush.
template <class Shade>
bool composite_segment(const HavsFrameConstants& fc, KEntry front, KEntry second, glm::vec4& fb, const Shade& shade,
                       KBufferDiagnostics* diag)
{
    // The segment from r0 to r7: table coordinates (MAD for t_z, unfused), then the lookup; nullified when r0's
    // scalar is negative (a gap, an empty or a flush entry) and, with --gaps maxgap, when it is longer than the gap.
    const float length = second.y - front.y;
    glm::vec4 c(0.0f);
    if (fc.paper_entries) {
        // --entries paper: CMP c, r0.x, 0.0, c alone, and the scalars are the table's coordinates as they are.
        if (!(front.x < 0.0f)) c = shade(front.x, second.x, length * fc.length_scale + fc.length_bias, length);
    } else {
        // A segment that ends on a flush fragment (distance +inf) never lies inside the mesh: it starts on the last
        // fragment of the pixel, which is an exit face unless fragments at one distance (a ray exactly through a
        // surface vertex) were ordered exit-first by rounding. Nor does one that ends on an entry face (exact gaps):
        // the ray is outside the mesh before it enters. Such a segment's front is an exit face (nullified anyway) or
        // a fragment that rasterization put in front of the entry face: an interior face sharing an edge with it,
        // covering a pixel just past that edge through snapping and extrapolated at a grazing angle (0.0027 units in
        // front on an Oxygen Post pixel, docs/havs.md).
        const bool nullified = front.x < 0.0f || std::isinf(second.y) || second.x >= kSideEntry ||
                               (fc.max_gap > 0.0f && length > fc.max_gap);
        if (!nullified) {
            const float t_z = length * fc.length_scale + fc.length_bias;
            c = shade(decode_scalar(front.x), decode_scalar(second.x), t_z, length);
        }
    }
    // Ordering: in front-to-back order each segment starts where the previous one ended. A front nearer than the
    // previous segment's back means a fragment arrived after the segment across it was composited.
    if (diag && real_entry(fc, front)) {
        if (front.y < diag->last_back) ++diag->ordering_errors;
        if (real_entry(fc, second)) diag->last_back = std::fmax(diag->last_back, second.y);
    }
    // Front to back: fb = c * (1 - fb.a) + fb, per channel (MAD, unfused).
    const float one_minus_a = 1.0f - fb.a;
    fb = glm::vec4(c.r * one_minus_a + fb.r, c.g * one_minus_a + fb.g, c.b * one_minus_a + fb.b,
                   c.a * one_minus_a + fb.a);
    if (fc.paper_entries) return false;  // the paper's program re-marks nothing
    // Exact gaps: behind an exit face the ray is outside the mesh until it meets an entry face. Rasterization can put
    // a fragment there: a pixel just past the edge where interior faces meet the exit face is covered through
    // snapping, and their planes, extrapolated at a grazing angle, place the fragment a little behind the exit (2e-5
    // and 3e-4 units on a torus pixel, docs/havs.md), which would composite a segment outside the mesh. Such a
    // fragment, extrapolated (kSideOutside) and right behind an exit, is marked an exit in the buffer, so that the
    // segment starting on it is a gap too. A fragment inside its own triangle is left alone: behind an exit it is a
    // real one that arrived late (an ordering error), and its segment is real.
    return real_entry(fc, front) && front.x < 0.0f && real_entry(fc, second) && second.x >= kSideOutside &&
           second.x < kSideEntry;
}

// An entry as its 64 bits (x low, y high): run<K>'s unrolled chains select entries by integer moves, which compile to
// conditional moves, rather than by branches on the distances, which mispredict on short chains (the order in which a
// pixel's slots hold its entries changes with every run). Moving bits changes no value.
inline uint64_t entry_bits(const KEntry& e)
{
    uint64_t b;
    std::memcpy(&b, &e, sizeof b);
    return b;
}
inline KEntry bits_entry(uint64_t b)
{
    KEntry e;
    std::memcpy(static_cast<void*>(&e), &b, sizeof e);
    return e;
}
inline float bits_distance(uint64_t b)
{
    const uint32_t y = uint32_t(b >> 32);
    float d;
    std::memcpy(&d, &y, sizeof d);
    return d;
}
// -x of an entry: x's sign bit flipped, as float negation does (NaN included).
inline constexpr uint64_t kScalarSignBit = 0x80000000u;

// One run of the program with k read at run time (any k, up to thousands): the chains branch on the distances, which
// on long chains costs less than the conditional moves of run<K> (at k = 16 those made a Blunt Fin frame 12 % slower).
// The same operations as run<K> (tests/test_havs_kbuffer.cpp holds the two to the same bits at k = 6).
// Called by run after the kill and the fragment count, with k >= 1.
template <class Shade>
bool run_any_k(const HavsFrameConstants& fc, KEntry a0, KEntry* a, int k, glm::vec4& fb, const Shade& shade,
               KBufferDiagnostics* diag)
{
    // Find the entry with the smallest distance (r0); the others go to r1..rk. The paper's CMP: on t < 0 the running
    // minimum stays; otherwise (ties included) the stored entry becomes the minimum and the running one moves on, so
    // on a tie the entry already in the buffer is composited first. t is the paper's difference, not a comparison of
    // the two distances: with denormals flushed a tiny difference is 0, and inf - inf is NaN.
    // r is scratch for k + 1 entries, plain floats (x and y apart, as the chains read the distances alone), so that
    // no call pays for initializing them: on the stack up to kStackEntries, beyond that per thread, kept between calls.
    if (k < 1) return false;  // run's guard, repeated where the compiler sees the chains (r1 must exist)
    float stack_x[kStackEntries], stack_y[kStackEntries];
    float *rx = stack_x, *ry = stack_y;
    if (k + 1 > kStackEntries) {
        thread_local std::vector<float> heap;
        if (heap.size() < 2 * (std::size_t(k) + 1)) heap.resize(2 * (std::size_t(k) + 1));
        rx = heap.data();
        ry = rx + k + 1;
    }
    rx[0] = a0.x;
    ry[0] = a0.y;
    for (int i = 1; i <= k; ++i) {
        const float t = ry[0] - a[i - 1].y;
        if (t < 0.0f) {
            rx[i] = a[i - 1].x;
            ry[i] = a[i - 1].y;
        } else {
            rx[i] = rx[0];
            ry[i] = ry[0];
            rx[0] = a[i - 1].x;
            ry[0] = a[i - 1].y;
        }
    }
    // The second smallest (r7 of the paper) among r1..rk, by the same chain; it stays in the buffer.
    int second_i = 1;
    for (int i = 2; i <= k; ++i) {
        const float t = ry[second_i] - ry[i];
        if (!(t < 0.0f)) second_i = i;
    }
    if (composite_segment(fc, KEntry{rx[0], ry[0]}, KEntry{rx[second_i], ry[second_i]}, fb, shade, diag))
        rx[second_i] = -rx[second_i];
    // Write back r1..rk.
    uint32_t held = 0;
    for (int i = 1; i <= k; ++i) {
        a[i - 1] = KEntry{rx[i], ry[i]};
        if (diag) held += real_entry(fc, a[i - 1]) ? 1u : 0u;
    }
    if (diag && held > diag->max_held) diag->max_held = held;
    return true;
}

// One run of the program on one pixel (havs_kbuffer's contract); K > 0 fixes k at compile time (`k` is then K).
template <int K, class Shade>
bool run(const HavsFrameConstants& fc, KEntry a0, KEntry* a, int k, glm::vec4& fb, const Shade& shade,
         KBufferDiagnostics* diag)
{
    static_assert(K >= 0);
    if constexpr (K > 0) k = K;
    if (k < 1) return false;  // no stored entry to composite with: the renderers refuse such a k (--k)
    // KIL (threshold - alpha): the paper kills the fragment once the pixel is opaque enough; nothing is written.
    if (fc.threshold - fb.a < 0.0f) return false;
    if (diag && real_entry(fc, a0)) ++diag->fragments;
    if constexpr (K == 0) {
        return run_any_k(fc, a0, a, k, fb, shade, diag);
    } else {
        // The chains of run_any_k, unrolled, on the entries' 64 bits, selecting by conditional moves.
        uint64_t r[K + 1];
        uint64_t r0 = entry_bits(a0);
        float d0 = a0.y;
#pragma GCC unroll 16
        for (int i = 1; i <= K; ++i) {
            const uint64_t ai = entry_bits(a[i - 1]);
            const float di = a[i - 1].y;
            const bool keep = d0 - di < 0.0f;  // the paper's t < 0
            r[i] = keep ? ai : r0;
            r0 = keep ? r0 : ai;
            d0 = keep ? d0 : di;
        }
        int second_i = 1;
        float ds = bits_distance(r[1]);
#pragma GCC unroll 16
        for (int i = 2; i <= K; ++i) {
            const float di = bits_distance(r[i]);
            const bool take = !(ds - di < 0.0f);
            second_i = take ? i : second_i;
            ds = take ? di : ds;
        }
        if (composite_segment(fc, bits_entry(r0), bits_entry(r[second_i]), fb, shade, diag))
            r[second_i] ^= kScalarSignBit;
        uint32_t held = 0;
#pragma GCC unroll 16
        for (int i = 1; i <= K; ++i) {
            a[i - 1] = bits_entry(r[i]);
            if (diag) held += real_entry(fc, a[i - 1]) ? 1u : 0u;
        }
        if (diag && held > diag->max_held) diag->max_held = held;
        return true;
    }
}

// The flush's runs once the order is known: `n` entries, entry_at(0) .. entry_at(n - 1) in the order the runs take
// them out, each run's second entry the next run's front, the last run's the flush fragment. Shared by flush and
// --k all (gpu/havs/havs_pixel_sort.h).
template <class EntryAt, class Shade>
void composite_in_order(const HavsFrameConstants& fc, int n, const EntryAt& entry_at, glm::vec4& fb,
                        const Shade& shade, KBufferDiagnostics* diag)
{
    const KEntry flush = fc.paper_entries ? kPaperFlushFragment : kFlushFragment;
    if (n < 1) return;
    KEntry front = entry_at(0);
    for (int pass = 0; pass < n; ++pass) {
        if (fc.threshold - fb.a < 0.0f) return;  // KIL: this run and every later one write nothing
        // Once the front is a flush fragment, so is every later entry: the runs composite nothing. (The paper's
        // entries run them: their MAD of a zero colour turns a -0 channel into +0, as the ARB program does.)
        if (!fc.paper_entries && std::isinf(front.y)) return;
        KEntry second = pass + 1 < n ? entry_at(pass + 1) : flush;
        if (composite_segment(fc, front, second, fb, shade, diag)) second.x = -second.x;
        front = second;
    }
}

// The flush (havs_flush's contract), for any segment shader.
template <class Shade>
void flush(const HavsFrameConstants& fc, const KEntry* a, int k, glm::vec4& fb, const Shade& shade,
           KBufferDiagnostics* diag)
{
    // k runs of the program on the flush fragment (distance +inf) take the entries out in the order: distance
    // ascending, and among equal distances the later slot first (the chains' ties, which keep the relative slot
    // order of entries at one distance from run to run); each run's second entry is the next run's front. A
    // distance that is NaN, or not nearer than the flush fragment, breaks that order: then the k runs are made as
    // they are. Derivation: docs/havs.md, "The flush".
    const KEntry flush = fc.paper_entries ? kPaperFlushFragment : kFlushFragment;
    thread_local std::vector<uint32_t> order;
    order.resize(std::size_t(k));
    for (int i = 0; i < k; ++i) {
        if (std::isnan(a[i].y) || a[i].y >= flush.y) {  // the order below needs every entry before the flush's
            thread_local std::vector<KEntry> copy;
            copy.assign(a, a + k);
            for (int pass = 0; pass < k; ++pass) run<0>(fc, flush, copy.data(), k, fb, shade, diag);
            return;
        }
        order[std::size_t(i)] = uint32_t(i);
    }
    std::sort(order.begin(), order.end(),
              [a](uint32_t i, uint32_t j) { return a[i].y < a[j].y || (a[i].y == a[j].y && i > j); });
    composite_in_order(fc, k, [&](int i) { return a[order[std::size_t(i)]]; }, fb, shade, diag);
}

}  // namespace uvr::gpu::kbuffer_program
