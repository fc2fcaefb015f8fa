// Helpers shared by the tests: where the data is, temporary files, running the `uvr` program.
#pragma once

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

namespace uvr::test {

inline std::string data_path(const std::string& rel) { return std::string(UVR_DATA_DIR) + "/" + rel; }

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
