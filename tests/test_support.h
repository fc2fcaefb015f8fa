// Helpers shared by the tests: where the data is, temporary files, running the `uvr` program.
#pragma once

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <string>
#include <vector>

#include <sys/wait.h>
#include <unistd.h>

namespace uvr::test {

// Whether this test program runs with the sanitizers (scripts/test-sanitize.sh): AddressSanitizer's runtime, linked
// into the program, defines __asan_init. Asked at run time because the sanitized build links the test code the normal
// build compiled, without instrumentation (tests/CMakeLists.txt).
extern "C" __attribute__((weak)) void __asan_init();
inline bool sanitized()
{
    return __asan_init != nullptr;
}

// How many random cases a test draws through one code path: `n`, or an eighth of it in the build with the sanitizers
// (scripts/test-sanitize.sh). The sanitizers check the memory accesses and the arithmetic along each path, which the
// first thousands of cases already take; the full counts, sized for what the tests assert about their statistics, run
// in the normal build. A floor a test asserts on a count of such cases scales the same way (docs/robustness.md).
inline constexpr std::size_t kSanitizedCaseShare = 8;
inline std::size_t random_cases(std::size_t n)
{
    return sanitized() ? n / kSanitizedCaseShare : n;
}

// The values of a parameter a loop takes through one code path (k, a table's size): all of them, or under the
// sanitizers the first and the last, which take the path at both ends of its range. The normal build checks every
// value's result (docs/robustness.md).
template <class T>
std::vector<T> configurations(std::initializer_list<T> all)
{
    if (!sanitized() || all.size() <= 2) return all;
    return {*all.begin(), *(all.end() - 1)};
}

// The views (or scenes) a loop renders through one code path: all of them, or under the sanitizers the first, which
// takes the path that the others take with other numbers.
template <class T>
std::vector<T> views(std::initializer_list<T> all)
{
    if (!sanitized() || all.size() <= 1) return all;
    return {*all.begin()};
}

// The pre-integration table's texels per axis in a test of frames that does not test the table itself: the default
// `n`, or under the sanitizers a quarter of it. Every texel is the same computation (the segment integral), which
// the frames then sample by the same code at any size; a 128^3 table is most of an instrumented GL frame test's time.
inline int table_side(int n)
{
    return sanitized() ? std::max(2, n / 4) : n;
}

inline std::string data_path(const std::string& rel)
{
    // Appended in place: `std::string(UVR_DATA_DIR) + "/" + rel` trips a false -Warray-bounds in gcc 12 at -O2.
    std::string path = UVR_DATA_DIR;
    path += '/';
    path += rel;
    return path;
}

// A fresh directory under the system temp dir, removed when the object goes away.
class TempDir {
public:
    explicit TempDir(const std::string& tag)
    {
        static int counter = 0;
        path_ = std::filesystem::temp_directory_path() /
                ("uvr-test-" + tag + "-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
        std::filesystem::remove_all(path_);
        std::filesystem::create_directories(path_);
    }
    ~TempDir() { std::error_code ec; std::filesystem::remove_all(path_, ec); }
    std::string file(const std::string& name) const { return (path_ / name).string(); }
    std::string write(const std::string& name, const std::string& contents) const
    {
        std::ofstream out(file(name), std::ios::binary);
        out << contents;
        return file(name);
    }

private:
    std::filesystem::path path_;
};

// The first `n` bytes of a file (to make truncated copies of real data).
inline std::string file_prefix(const std::string& path, std::size_t n)
{
    std::ifstream in(path, std::ios::binary);
    std::string s(n, '\0');
    in.read(s.data(), static_cast<std::streamsize>(n));
    s.resize(static_cast<std::size_t>(in.gcount()));
    return s;
}

inline std::string file_contents(const std::string& path)
{
    return file_prefix(path, static_cast<std::size_t>(std::filesystem::file_size(path)));
}

}  // namespace uvr::test

#include <array>
#include <catch2/catch.hpp>

#include "reference/error.h"

namespace uvr::test {

// Runs `fn` and checks that it throws uvr::InputError whose message contains every one of `phrases`.
template <class Fn>
void require_input_error(Fn&& fn, std::initializer_list<std::string> phrases)
{
    try {
        fn();
        FAIL("expected an InputError containing '" << *phrases.begin() << "', but nothing was thrown");
    } catch (const uvr::InputError& e) {
        INFO("message: " << e.what());
        for (const auto& p : phrases) CHECK_THAT(e.what(), Catch::Contains(p));
    }
}

struct CommandResult {
    int exit_code = -1;
    std::string out;  // stdout
    std::string err;  // stderr
};

// The `uvr` program of the build this test program belongs to: bench/uvr beside its tests/ directory (CMake's layout
// of one build directory). Found at run time, as the sanitized build links the normal build's test objects.
inline std::string uvr_binary()
{
    static const std::string path =
        (std::filesystem::read_symlink("/proc/self/exe").parent_path().parent_path() / "bench" / "uvr").string();
    return path;
}

// Runs the `uvr` program with `args` (shell-quoted by the caller), capturing stdout and stderr separately.
// `env`: variable assignments for this run only ("NAME=value ...", as a shell takes them before a command);
// `launcher`: a command that runs the program (mpirun and its options), or "".
inline CommandResult run_uvr(const std::string& args, const std::string& env = "", const std::string& launcher = "")
{
    TempDir tmp("run");
    const std::string out = tmp.file("stdout"), err = tmp.file("stderr");
    const std::string cmd = env + (env.empty() ? "" : " ") + launcher + (launcher.empty() ? "" : " ") + "'" +
                            uvr_binary() + "' " + args + " >'" + out + "' 2>'" + err + "' </dev/null";
    const int status = std::system(cmd.c_str());
    CommandResult r;
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    r.out = file_contents(out);
    r.err = file_contents(err);
    return r;
}

}  // namespace uvr::test

