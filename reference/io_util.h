// Small I/O helpers shared by the readers: whole-file reads, bounded binary cursors, a line-aware text scanner,
// endianness, zlib/gzip inflation. Every failure is an InputError that names the file (and line for text).
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

namespace uvr {

// Reads the whole file. Throws InputError "cannot open" / "cannot read" naming the path.
std::string read_file_bytes(const std::string& path);

// The largest allocation a reader may make from counts in a header before it has checked them against the bytes the
// file holds: readers compare claimed counts with the remaining size first (hostile headers fail before allocating).
inline constexpr uint64_t kMaxElements = uint64_t(1) << 34;

// Byte order of the machine is little-endian (x86-64, aarch64); checked in io_util.cpp with a static_assert.
template <class T>
T byteswap_value(T v)
{
    unsigned char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(b[i], b[sizeof(T) - 1 - i]);
    std::memcpy(&v, b, sizeof(T));
    return v;
}

// A cursor over a byte buffer that never reads past its end: every read checks the remaining size and throws
// InputError(file, "truncated: ...") when it is short.
class BinaryCursor {
public:
    BinaryCursor(std::string_view data, std::string file, bool big_endian)
        : data_(data), file_(std::move(file)), big_endian_(big_endian) {}

    template <class T>
    T read(const char* what)
    {
        require(sizeof(T), what);
        T v;
        std::memcpy(&v, data_.data() + pos_, sizeof(T));
        pos_ += sizeof(T);
        return big_endian_ ? byteswap_value(v) : v;
    }
    // Reads n values of T into out (resized), after checking n * sizeof(T) bytes remain.
    template <class T>
    void read_array(uint64_t n, std::vector<T>& out, const char* what)
    {
        if (n > remaining() / sizeof(T)) truncated(n * sizeof(T), what);
        out.resize(n);
        std::memcpy(out.data(), data_.data() + pos_, n * sizeof(T));
        pos_ += n * sizeof(T);
        if (big_endian_)
            for (auto& v : out) v = byteswap_value(v);
    }
    void require(uint64_t bytes, const char* what) const
    {
        if (bytes > remaining()) truncated(bytes, what);
    }
    void skip(uint64_t bytes, const char* what)
    {
        require(bytes, what);
        pos_ += bytes;
    }
    uint64_t remaining() const { return data_.size() - pos_; }
    uint64_t position() const { return pos_; }
    void seek(uint64_t pos) { pos_ = pos <= data_.size() ? pos : data_.size(); }
    const std::string& file() const { return file_; }
    bool big_endian() const { return big_endian_; }
    void set_big_endian(bool b) { big_endian_ = b; }
    std::string_view rest() const { return data_.substr(pos_); }

private:
    [[noreturn]] void truncated(uint64_t bytes, const char* what) const;
    std::string_view data_;
    std::string file_;
    bool big_endian_;
    uint64_t pos_ = 0;
};

// Whitespace-separated tokens with line numbers, for the text formats (VTK legacy ASCII, TetGen, OFF, headers).
// '#' starts a comment to the end of the line when comments are enabled.
class TextScanner {
public:
    TextScanner(std::string_view text, std::string file, bool hash_comments);

    bool at_end();                         // skips whitespace (and comments) first
    std::string_view token(const char* what);   // throws "unexpected end of file, expected <what>"
    int64_t integer(const char* what);     // throws "expected <what> (an integer), found '<tok>'"
    double real(const char* what);         // accepts nan/inf spellings so that validation can name them
    std::string_view line_rest();          // the rest of the current line (without the newline), advancing past it
    long line() const { return token_line_; }  // 1-based line of the last token (or line_rest) returned
    std::size_t offset() const { return pos_; }  // byte offset just past the last token
    void set_offset(std::size_t pos);      // (re)positions, recounting lines
    [[noreturn]] void fail(const std::string& what) const;  // InputError(file, line, what)
    const std::string& file() const { return file_; }

private:
    void skip_space();
    std::string_view text_;
    std::string file_;
    bool hash_comments_;
    std::size_t pos_ = 0;
    long line_ = 1;
    long token_line_ = 1;
};

// zlib stream (RFC 1950) or gzip (RFC 1952) inflation of `in` into exactly `expected_size` bytes (when non-zero) or
// as much as it holds (expected_size 0, capped at kMaxElements bytes). Throws InputError(file, "corrupt ...").
std::string inflate_bytes(std::string_view in, uint64_t expected_size, const std::string& file, const char* what);

// Standard base64 (RFC 4648) with whitespace ignored; throws InputError on a bad character.
std::string decode_base64(std::string_view in, const std::string& file, const char* what);

std::string lowercase(std::string_view s);
std::vector<std::string> split_words(std::string_view s);  // on spaces and tabs, empty words dropped
std::string file_extension(const std::string& path);  // lowercase, with the dot: ".vtk"; "" if none
std::string directory_of(const std::string& path);    // "" or ending in '/'
// Escapes &, <, >, " for HTML and XML text, and for attribute values in double quotes.
std::string escape_markup(const std::string& s);

}  // namespace uvr

namespace uvr {

// Writes `bytes` to `path` through a temporary file in the same directory that is renamed over `path` only once it is
// complete, so a failure (unwritable directory, full disk) leaves no half-written output and no stale temporary.
// Throws InputError naming `path`.
void write_file_atomically(const std::string& path, std::string_view bytes);

}  // namespace uvr
