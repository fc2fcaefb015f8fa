#include "reference/image.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstring>

#include <png.h>

#include "reference/error.h"
#include "reference/io_util.h"

namespace uvr {

void write_npy(const std::string& path, const Image& image)
{
    // NPY v1.0: magic, version, little-endian header length, a Python dict padded with spaces to a multiple of 64
    // bytes (including the newline), then the raw data in C order.
    std::string dict = "{'descr': '<f4', 'fortran_order': False, 'shape': (" + std::to_string(image.height) + ", " +
                       std::to_string(image.width) + ", 4), }";
    const std::size_t unpadded = 10 + dict.size() + 1;
    dict.append((64 - unpadded % 64) % 64, ' ');
    dict.push_back('\n');
    std::string out("\x93NUMPY\x01\x00", 8);
    const uint16_t hlen = static_cast<uint16_t>(dict.size());
    out.push_back(static_cast<char>(hlen & 0xFF));
    out.push_back(static_cast<char>(hlen >> 8));
    out += dict;
    out.append(reinterpret_cast<const char*>(image.rgba.data()), image.rgba.size() * sizeof(float));
    write_file_atomically(path, out);
}

Image read_npy(const std::string& path, int* channels)
{
    const std::string data = read_file_bytes(path);
    if (data.size() < 10 || data.compare(0, 6, "\x93NUMPY") != 0) throw InputError(path, "not a .npy file");
    const unsigned major = static_cast<unsigned char>(data[6]);
    std::size_t hlen, start;
    if (major == 1) {
        hlen = static_cast<unsigned char>(data[8]) | (static_cast<unsigned char>(data[9]) << 8);
        start = 10;
    } else {
        if (data.size() < 12) throw InputError(path, "truncated .npy header");
        hlen = 0;
        for (int k = 0; k < 4; ++k) hlen |= std::size_t(static_cast<unsigned char>(data[8 + k])) << (8 * k);
        start = 12;
    }
    if (start + hlen > data.size()) throw InputError(path, "truncated .npy header");
    const std::string header = data.substr(start, hlen);
    if (header.find("'descr': '<f4'") == std::string::npos)
        throw InputError(path, ".npy data must be little-endian float32 ('<f4')");
    if (header.find("'fortran_order': False") == std::string::npos)
        throw InputError(path, ".npy data must be in C order");
    const auto lp = header.find("'shape': (");
    if (lp == std::string::npos) throw InputError(path, ".npy header has no shape");
    long dims[3] = {0, 0, 0};
    int nd = std::sscanf(header.c_str() + lp + 10, "%ld, %ld, %ld", &dims[0], &dims[1], &dims[2]);
    if (nd != 3 || dims[0] <= 0 || dims[1] <= 0 || (dims[2] != 4 && dims[2] != 3) || dims[0] > 65536 ||
        dims[1] > 65536)
        throw InputError(path, ".npy shape must be (H, W, 4) or (H, W, 3)");
    const std::size_t n = std::size_t(dims[0]) * std::size_t(dims[1]) * std::size_t(dims[2]);
    if (data.size() - start - hlen != n * 4)
        throw InputError(path, ".npy holds " + std::to_string(data.size() - start - hlen) + " data bytes, expected " +
                                   std::to_string(n * 4));
    Image img(static_cast<int>(dims[1]), static_cast<int>(dims[0]));
    if (channels) *channels = int(dims[2]);
    const char* src = data.data() + start + hlen;
    if (dims[2] == 4) {
        std::memcpy(img.rgba.data(), src, n * 4);
    } else {
        for (std::size_t p = 0; p < std::size_t(dims[0]) * std::size_t(dims[1]); ++p) {
            std::memcpy(&img.rgba[p * 4], src + p * 12, 12);
            img.rgba[p * 4 + 3] = 1.0f;
        }
    }
    return img;
}

namespace {

void png_write_to_string(png_structp png, png_bytep data, png_size_t len)
{
    static_cast<std::string*>(png_get_io_ptr(png))->append(reinterpret_cast<const char*>(data), len);
}

}  // namespace

void write_png_rgb8(const std::string& path, int width, int height, const std::vector<unsigned char>& rgb)
{
    std::string out;
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    png_infop info = png ? png_create_info_struct(png) : nullptr;
    if (!png || !info) throw InputError(path, "cannot initialise libpng");
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        throw InputError(path, "PNG encoding failed");
    }
    png_set_write_fn(png, &out, png_write_to_string, nullptr);
    // zlib's fastest level: the images are viewed, not archived. At the default level (6) encoding took a third of a
    // 512² budget's time outside its renders; the files are 15-30 % larger.
    png_set_compression_level(png, 1);
    png_set_IHDR(png, info, static_cast<png_uint_32>(width), static_cast<png_uint_32>(height), 8, PNG_COLOR_TYPE_RGB,
                 PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    for (int j = 0; j < height; ++j)
        png_write_row(png, const_cast<png_bytep>(&rgb[std::size_t(j) * std::size_t(width) * 3]));
    png_write_end(png, nullptr);
    png_destroy_write_struct(&png, &info);
    write_file_atomically(path, out);
}

void write_png(const std::string& path, const Image& image, glm::dvec3 background)
{
    std::vector<unsigned char> rgb(std::size_t(image.width) * std::size_t(image.height) * 3);
    for (std::size_t p = 0; p < std::size_t(image.width) * std::size_t(image.height); ++p) {
        const float* px = &image.rgba[p * 4];
        for (int c = 0; c < 3; ++c) {
            // Premultiplied "over": C + (1 - alpha) * background.
            const double v = double(px[c]) + (1.0 - double(px[3])) * background[c];
            rgb[p * 3 + c] = static_cast<unsigned char>(std::lround(std::clamp(v, 0.0, 1.0) * 255.0));
        }
    }
    write_png_rgb8(path, image.width, image.height, rgb);
}

void write_image(const std::string& path, const Image& image, glm::dvec3 background)
{
    const std::string ext = file_extension(path);
    if (ext == ".npy") return write_npy(path, image);
    if (ext == ".png") return write_png(path, image, background);
    if (ext == ".exr") return write_exr(path, image);
    throw InputError(path, "unsupported image extension '" + ext + "' (use .npy, .exr or .png)");
}

void parse_size(const std::string& text, int& width, int& height)
{
    int w = 0, h = 0;
    char x = 0, extra = 0;
    if (std::sscanf(text.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || (x != 'x' && x != 'X') || w < 1 || h < 1 ||
        w > 16384 || h > 16384)
        throw InputError("", "--size must be WxH with 1 <= W, H <= 16384, found '" + text + "'");
    width = w;
    height = h;
}

namespace {

Image read_pfm(const std::string& path)
{
    const std::string data = read_file_bytes(path);
    // Header: "PF" (colour) or "Pf" (grey), width and height, a scale whose sign gives the byte order (negative:
    // little-endian), each followed by white space; then the rows from the bottom.
    std::size_t at = 0;
    auto token = [&]() {
        while (at < data.size() && std::isspace(static_cast<unsigned char>(data[at]))) ++at;
        const std::size_t from = at;
        while (at < data.size() && !std::isspace(static_cast<unsigned char>(data[at]))) ++at;
        return data.substr(from, at - from);
    };
    const std::string magic = token();
    if (magic != "PF" && magic != "Pf") throw InputError(path, "not a PFM file (it must start with PF or Pf)");
    const int channels = magic == "PF" ? 3 : 1;
    char* end = nullptr;
    const std::string ws = token(), hs = token(), ss = token();
    const long w = std::strtol(ws.c_str(), &end, 10);
    const bool w_ok = end && *end == 0;
    const long h = std::strtol(hs.c_str(), &end, 10);
    const bool h_ok = end && *end == 0;
    const double scale = std::strtod(ss.c_str(), &end);
    if (!w_ok || !h_ok || !(end && *end == 0) || w <= 0 || h <= 0 || w > 65536 || h > 65536 || scale == 0.0 ||
        !std::isfinite(scale))
        throw InputError(path, "malformed PFM header (width, height and a non-zero scale expected)");
    if (scale > 0.0) throw InputError(path, "big-endian PFM (positive scale) is not supported; write it little-endian");
    ++at;  // the single white-space character after the scale
    const std::size_t n = std::size_t(w) * std::size_t(h) * std::size_t(channels);
    if (data.size() < at || data.size() - at != n * 4)
        throw InputError(path, "PFM holds " + std::to_string(data.size() < at ? 0 : data.size() - at) +
                                   " data bytes, expected " + std::to_string(n * 4));
    Image img{int(w), int(h)};
    for (long y = 0; y < h; ++y)
        for (long x = 0; x < w; ++x) {
            float v[3];
            const char* src = data.data() + at + (std::size_t(y) * std::size_t(w) + std::size_t(x)) * channels * 4;
            std::memcpy(v, src, std::size_t(channels) * 4);
            if (channels == 1) v[1] = v[2] = v[0];
            float* dst = &img.rgba[(std::size_t(h - 1 - y) * std::size_t(w) + std::size_t(x)) * 4];  // row 0 on top
            dst[0] = v[0];
            dst[1] = v[1];
            dst[2] = v[2];
            dst[3] = 1.0f;
        }
    return img;
}

Image read_png(const std::string& path)
{
    png_image png{};
    png.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_file(&png, path.c_str()))
        throw InputError(path, std::string("not a readable PNG: ") + png.message);
    png.format = PNG_FORMAT_RGBA;
    if (png.width == 0 || png.height == 0 || png.width > 65536 || png.height > 65536) {
        png_image_free(&png);
        throw InputError(path, "PNG size out of range");
    }
    std::vector<unsigned char> rgba(PNG_IMAGE_SIZE(png));
    if (!png_image_finish_read(&png, nullptr, rgba.data(), 0, nullptr))
        throw InputError(path, std::string("cannot decode the PNG: ") + png.message);
    Image img(int(png.width), int(png.height));
    for (std::size_t p = 0; p < std::size_t(png.width) * png.height; ++p) {
        // Composited over black: colour times alpha (the premultiplied colour a renderer shows on black).
        const float a = float(rgba[4 * p + 3]) / 255.0f;
        for (int c = 0; c < 3; ++c) img.rgba[4 * p + std::size_t(c)] = float(rgba[4 * p + std::size_t(c)]) / 255.0f * a;
        img.rgba[4 * p + 3] = 1.0f;
    }
    return img;
}

}  // namespace

namespace {

OutsideImage read_outside_image_as_stored(const std::string& path)
{
    const std::string ext = file_extension(path);
    if (ext == ".npy") {
        OutsideImage o;
        int channels = 4;
        o.image = read_npy(path, &channels);
        o.colour_only = channels == 3;  // read_npy gave it alpha 1: only its colour means anything
        return o;
    }
    if (ext == ".exr") {
        OutsideImage o;
        bool alpha = false;
        o.image = read_exr(path, &alpha);
        o.colour_only = !alpha;
        return o;
    }
    if (ext == ".pfm") return {read_pfm(path), true};
    if (ext == ".png") return {read_png(path), true};
    throw InputError(path, "unsupported image format '" + ext + "' (use .npy, .exr, .pfm or .png)");
}

}  // namespace

OutsideImage read_outside_image(const std::string& path)
{
    OutsideImage o = read_outside_image_as_stored(path);
    // A NaN or an infinity would make every measure NaN or infinite: a silently meaningless number, so it is refused.
    const Image& im = o.image;
    for (std::size_t p = 0; p < im.rgba.size(); ++p)
        if (!std::isfinite(im.rgba[p]))
            throw InputError(path, "pixel (" + std::to_string(p / 4 % std::size_t(im.width)) + ", " +
                                       std::to_string(p / 4 / std::size_t(im.width)) + ") channel " +
                                       std::to_string(p % 4) + " is not finite");
    return o;
}

}  // namespace uvr
