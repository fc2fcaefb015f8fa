// A progress bar on stderr for long commands: shown only on a terminal, and only once a task has run for a second,
// so short renders and redirected output stay clean.
#pragma once

#include <chrono>
#include <cstdio>
#include <string>

#include <unistd.h>

namespace uvr::cli {

class ProgressBar {
public:
    explicit ProgressBar(std::string label)
        : label_(std::move(label)), start_(std::chrono::steady_clock::now()), tty_(isatty(STDERR_FILENO) != 0) {}
    ~ProgressBar() { finish(); }

    void update(double fraction)
    {
        if (!tty_) return;
        const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
        if (elapsed < 1.0) return;
        const int width = 40, filled = int(fraction * width + 0.5);
        std::fprintf(stderr, "\r%s [%.*s%*s] %3d%% %5.1fs", label_.c_str(), filled,
                     "########################################", width - filled, "", int(fraction * 100 + 0.5),
                     elapsed);
        std::fflush(stderr);
        shown_ = true;
    }
    void finish()
    {
        if (shown_) std::fprintf(stderr, "\n");
        shown_ = false;
    }

private:
    std::string label_;
    std::chrono::steady_clock::time_point start_;
    bool tty_;
    bool shown_ = false;
};

}  // namespace uvr::cli
