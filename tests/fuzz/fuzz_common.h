// Shared by the libFuzzer targets (tests/fuzz/fuzz_<reader>.cpp, built with -DUVR_FUZZ=ON; docs/robustness.md).
//
// The readers take file paths, so each input is written to a file in a private directory under /dev/shm (memory, no
// disk traffic) and the reader is called on it. A reader may fail only with uvr::InputError: any other exception
// escapes LLVMFuzzerTestOneInput and libFuzzer reports it (deadly signal after std::terminate), as it reports crashes,
// sanitizer findings, leaks, timeouts and allocations over -malloc_limit_mb.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <string_view>
#include <utility>

#include <unistd.h>

#include "reference/error.h"

namespace uvr_fuzz {

// The private directory, made once per process (removed at exit).
inline const std::string& work_dir()
{
    static const std::string dir = [] {
        const char* base = std::getenv("UVR_FUZZ_TMP");
        std::string tmpl = std::string(base && *base ? base : "/dev/shm") + "/uvr-fuzz-XXXXXX";
        if (!mkdtemp(tmpl.data())) {
            std::perror("uvr fuzz: mkdtemp");
            std::abort();
        }
        static std::string to_remove = tmpl;
        std::atexit([] {
            std::string cmd = "rm -rf '" + to_remove + "'";
            if (std::system(cmd.c_str()) != 0) {
            }
        });
        return tmpl;
    }();
    return dir;
}

// Writes `bytes` to work_dir()/name and returns the path.
inline std::string write_file(const std::string& name, std::string_view bytes)
{
    const std::string path = work_dir() + "/" + name;
    std::FILE* f = std::fopen(path.c_str(), "wb");
    if (!f) {
        std::perror("uvr fuzz: fopen");
        std::abort();
    }
    if (!bytes.empty() && std::fwrite(bytes.data(), 1, bytes.size(), f) != bytes.size()) {
        std::perror("uvr fuzz: fwrite");
        std::abort();
    }
    std::fclose(f);
    return path;
}

inline std::string_view as_view(const uint8_t* data, std::size_t size)
{
    return std::string_view(reinterpret_cast<const char*>(data), size);
}

// Two files from one input: the bytes before the first kSplit and those after it (the second is empty when there is
// no separator). Used by TetGen (.node + .ele) and PLOT3D (XYZ + Q).
inline constexpr std::string_view kSplit = "UVRSPLIT";
inline std::pair<std::string_view, std::string_view> split(std::string_view in, bool& had_separator)
{
    const std::size_t at = in.find(kSplit);
    had_separator = at != std::string_view::npos;
    if (!had_separator) return {in, {}};
    return {in.substr(0, at), in.substr(at + kSplit.size())};
}

// Formats with detached data (NRRD "data file", MetaImage "ElementDataFile") may name any path; a header that names a
// device or a kernel file (/dev/zero, ../../dev/urandom, /proc/self/mem) would make the reader read forever or read
// the fuzzer's own memory. Such inputs are not what these targets test (they test parsing), so they are rejected
// (return -1: libFuzzer keeps them out of the corpus).
inline bool names_system_path(std::string_view in)
{
    for (std::string_view s : {"dev/", "proc/", "sys/"})
        if (in.find(s) != std::string_view::npos) return true;
    return false;
}

// An invariant of data a reader accepted; a violation is a finding (abort, so libFuzzer saves the input).
inline void require(bool ok, const char* what)
{
    if (!ok) {
        std::fprintf(stderr, "uvr fuzz: invariant violated: %s\n", what);
        std::abort();
    }
}

// Runs the reader; InputError is the expected way to fail, anything else propagates to libFuzzer. With
// UVR_FUZZ_VERBOSE=1 in the environment, each input's outcome is printed (to check seeds: `fuzz_off corpus/off/*`).
template <class F>
int expect_input_error_only(F&& read)
{
    static const bool verbose = [] {
        const char* v = std::getenv("UVR_FUZZ_VERBOSE");
        return v && *v && *v != '0';
    }();
    try {
        read();
        if (verbose) std::fprintf(stderr, "uvr fuzz: read\n");
    } catch (const uvr::InputError& e) {
        if (verbose) std::fprintf(stderr, "uvr fuzz: InputError: %s\n", e.what());
    }
    return 0;
}

}  // namespace uvr_fuzz
