// The one clock of uvr's timings: what a frame reports per stage ("stages_ms"), what bench times.
#pragma once

#include <chrono>

namespace uvr {

using Clock = std::chrono::steady_clock;

// Milliseconds from t0 to now.
inline double ms_since(Clock::time_point t0)
{
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

}  // namespace uvr
