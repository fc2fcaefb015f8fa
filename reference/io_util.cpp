#include "reference/io_util.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include <unistd.h>
#include <zlib.h>

#include "reference/error.h"

namespace uvr {

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "readers assume a little-endian machine");

std::string read_file_bytes(const std::string& path)
{
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (!f) throw InputError(path, std::string("cannot open: ") + std::strerror(errno));
    std::string data;
    char buf[1 << 16];
    std::size_t n;
    while ((n = std::fread(buf, 1, sizeof buf, f)) > 0) data.append(buf, n);
    bool bad = std::ferror(f);
    std::fclose(f);
    if (bad) throw InputError(path, "cannot read the file");
    return data;
}

void BinaryCursor::truncated(uint64_t bytes, const char* what) const
{
    throw InputError(file_, "truncated: " + std::string(what) + " needs " + std::to_string(bytes) +
                                " bytes at byte offset " + std::to_string(pos_) + ", but only " +
                                std::to_string(remaining()) + " remain");
}

TextScanner::TextScanner(std::string_view text, std::string file, bool hash_comments)
    : text_(text), file_(std::move(file)), hash_comments_(hash_comments)
{
}

void TextScanner::skip_space()
{
    while (pos_ < text_.size()) {
        char c = text_[pos_];
        if (c == '\n') {
            ++line_;
            ++pos_;
        } else if (std::isspace(static_cast<unsigned char>(c))) {
            ++pos_;
        } else if (hash_comments_ && c == '#') {
            while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
        } else {
            break;
        }
    }
}

bool TextScanner::at_end()
{
    skip_space();
    return pos_ >= text_.size();
}

std::string_view TextScanner::token(const char* what)
{
    skip_space();
    if (pos_ >= text_.size()) {
        token_line_ = line_;
        fail(std::string("unexpected end of file, expected ") + what);
    }
    std::size_t start = pos_;
    while (pos_ < text_.size() && !std::isspace(static_cast<unsigned char>(text_[pos_])) &&
           !(hash_comments_ && text_[pos_] == '#'))
        ++pos_;
    token_line_ = line_;
    return text_.substr(start, pos_ - start);
}

int64_t TextScanner::integer(const char* what)
{
    std::string_view t = token(what);
    int64_t v = 0;
    auto [p, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    if (ec != std::errc() || p != t.data() + t.size())
        fail(std::string("expected ") + what + " (an integer), found '" + std::string(t.substr(0, 40)) + "'");
    return v;
}

double TextScanner::real(const char* what)
{
    std::string_view t = token(what);
    std::string s(t);
    char* end = nullptr;
    errno = 0;
    double v = std::strtod(s.c_str(), &end);
    if (end != s.c_str() + s.size() || s.empty())
        fail(std::string("expected ") + what + " (a number), found '" + s.substr(0, 40) + "'");
    return v;  // overflow gives +-inf, which validation reports by name
}

std::string_view TextScanner::line_rest()
{
    // Skip blanks on the current line only.
    while (pos_ < text_.size() && text_[pos_] != '\n' && std::isspace(static_cast<unsigned char>(text_[pos_]))) ++pos_;
    std::size_t start = pos_;
    while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
    std::string_view r = text_.substr(start, pos_ - start);
    if (!r.empty() && r.back() == '\r') r.remove_suffix(1);
    token_line_ = line_;
    if (pos_ < text_.size()) {
        ++pos_;
        ++line_;
    }
    return r;
}

void TextScanner::set_offset(std::size_t pos)
{
    pos = std::min(pos, text_.size());
    // Count only the newlines between the old and the new position, so skipping forward over many binary blocks
    // stays linear in the file size.
    const auto b = text_.begin();
    if (pos >= pos_)
        line_ += static_cast<long>(std::count(b + static_cast<long>(pos_), b + static_cast<long>(pos), '\n'));
    else
        line_ -= static_cast<long>(std::count(b + static_cast<long>(pos), b + static_cast<long>(pos_), '\n'));
    pos_ = pos;
    token_line_ = line_;
}

void TextScanner::fail(const std::string& what) const
{
    throw InputError(file_, token_line_, what);
}

std::string inflate_bytes(std::string_view in, uint64_t expected_size, const std::string& file, const char* what)
{
    z_stream zs{};
    // 15 + 32: zlib or gzip header, detected automatically.
    if (inflateInit2(&zs, 15 + 32) != Z_OK) throw InputError(file, "zlib initialisation failed");
    std::string out;
    const uint64_t cap = expected_size ? expected_size : kMaxElements;
    out.resize(expected_size ? expected_size : std::min<uint64_t>(std::max<uint64_t>(in.size() * 4, 1024), cap));
    zs.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(in.data()));
    zs.avail_in = static_cast<uInt>(in.size());
    uint64_t produced = 0;
    int rc = Z_OK;
    for (;;) {
        if (produced == out.size()) {
            if (expected_size || out.size() >= cap) break;
            out.resize(std::min<uint64_t>(out.size() * 2, cap));
        }
        uint64_t room = std::min<uint64_t>(out.size() - produced, 1u << 30);
        zs.next_out = reinterpret_cast<Bytef*>(&out[produced]);
        zs.avail_out = static_cast<uInt>(room);
        rc = inflate(&zs, Z_NO_FLUSH);
        produced += room - zs.avail_out;
        if (rc == Z_STREAM_END) break;
        if (rc != Z_OK) break;
        if (zs.avail_in == 0 && zs.avail_out != 0) break;  // input exhausted before the stream ended
    }
    inflateEnd(&zs);
    if (rc != Z_STREAM_END && !(expected_size && produced == expected_size && rc == Z_OK))
        throw InputError(file, std::string("corrupt or truncated compressed data in ") + what);
    if (expected_size && produced != expected_size)
        throw InputError(file, std::string("compressed ") + what + " holds " + std::to_string(produced) +
                                   " bytes, expected " + std::to_string(expected_size));
    out.resize(produced);
    return out;
}

std::string decode_base64(std::string_view in, const std::string& file, const char* what)
{
    auto value = [](char c) -> int {
        if (c >= 'A' && c <= 'Z') return c - 'A';
        if (c >= 'a' && c <= 'z') return c - 'a' + 26;
        if (c >= '0' && c <= '9') return c - '0' + 52;
        if (c == '+') return 62;
        if (c == '/') return 63;
        return -1;
    };
    std::string out;
    out.reserve(in.size() / 4 * 3);
    uint32_t acc = 0;
    int bits = 0;
    for (char c : in) {
        if (std::isspace(static_cast<unsigned char>(c))) continue;
        if (c == '=') {
            // Padding ends a base64 group; VTK concatenates separately encoded groups (header, then data), so reset.
            acc = 0;
            bits = 0;
            continue;
        }
        int v = value(c);
        if (v < 0)
            throw InputError(file, std::string("invalid base64 character '") + c + "' in " + what);
        acc = (acc << 6) | static_cast<uint32_t>(v);
        bits += 6;
        if (bits >= 8) {
            bits -= 8;
            out.push_back(static_cast<char>((acc >> bits) & 0xFF));
        }
    }
    return out;
}

std::vector<std::string> split_words(std::string_view s)
{
    std::vector<std::string> words;
    std::size_t pos = 0;
    while ((pos = s.find_first_not_of(" \t", pos)) != std::string_view::npos) {
        std::size_t end = s.find_first_of(" \t", pos);
        words.emplace_back(s.substr(pos, end == std::string_view::npos ? end : end - pos));
        pos = end;
    }
    return words;
}

std::string lowercase(std::string_view s)
{
    std::string r(s);
    for (auto& c : r) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return r;
}

std::string file_extension(const std::string& path)
{
    auto slash = path.find_last_of('/');
    auto dot = path.find_last_of('.');
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
    return lowercase(path.substr(dot));
}

std::string directory_of(const std::string& path)
{
    auto slash = path.find_last_of('/');
    return slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
}

}  // namespace uvr

namespace uvr {

void write_file_atomically(const std::string& path, std::string_view bytes)
{
    const std::string tmp = path + ".tmp-" + std::to_string(::getpid());
    std::FILE* f = std::fopen(tmp.c_str(), "wb");
    if (!f) throw InputError(path, std::string("cannot write: ") + std::strerror(errno));
    const bool ok = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
    const int err = ok ? 0 : errno;
    const bool closed = std::fclose(f) == 0;
    if (!ok || !closed) {
        std::remove(tmp.c_str());
        throw InputError(path, std::string("cannot write: ") + std::strerror(err ? err : errno));
    }
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
        const int e = errno;
        std::remove(tmp.c_str());
        throw InputError(path, std::string("cannot write: ") + std::strerror(e));
    }
}

std::string escape_markup(const std::string& s)
{
    std::string o;
    for (char c : s) {
        switch (c) {
            case '&':
                o += "&amp;";
                break;
            case '<':
                o += "&lt;";
                break;
            case '>':
                o += "&gt;";
                break;
            case '"':
                o += "&quot;";
                break;
            default:
                o += c;
        }
    }
    return o;
}

}  // namespace uvr
