// The one clock of uvr's timings: what a frame reports per stage ("stages_ms"), what bench times; and the process's
// peak memory.
#pragma once

#include <chrono>
#include <cstdint>

#include <sys/resource.h>

namespace uvr {

using Clock = std::chrono::steady_clock;

// Milliseconds from t0 to now.
inline double ms_since(Clock::time_point t0)
{
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// This process's peak resident memory so far (getrusage), in bytes.
inline uint64_t peak_memory_bytes()
{
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return uint64_t(u.ru_maxrss) * 1024u;  // kilobytes on Linux
}

}  // namespace uvr
