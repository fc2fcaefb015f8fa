// Images: float32 premultiplied RGBA, row 0 at the top (docs/spec.md §2), and their files.
#pragma once

#include <string>
#include <vector>

#include <glm/vec3.hpp>

namespace uvr {

struct Image {
    int width = 0, height = 0;
    std::vector<float> rgba;  // width * height * 4, premultiplied, row-major from the top row

    Image() = default;
    Image(int w, int h) : width(w), height(h), rgba(std::size_t(w) * std::size_t(h) * 4, 0.0f) {}
    float* pixel(int i, int j) { return &rgba[(std::size_t(j) * std::size_t(width) + std::size_t(i)) * 4]; }
    const float* pixel(int i, int j) const { return &rgba[(std::size_t(j) * std::size_t(width) + std::size_t(i)) * 4]; }
};

// A read-only look at W x H premultiplied RGBA floats owned elsewhere (an Image, or a NumPy array from Python).
struct ImageView {
    int width = 0, height = 0;
    const float* rgba = nullptr;  // width * height * 4, row 0 on top
    ImageView() = default;
    ImageView(int w, int h, const float* data) : width(w), height(h), rgba(data) {}
    ImageView(const Image& image) : width(image.width), height(image.height), rgba(image.rgba.data()) {}  // NOLINT
};

// By extension: .npy (float32 H x W x 4), .exr (float32 R, G, B, A: the same bits), .png (8-bit RGB composited over
// `background`, no gamma: the values are taken as display values, as the GPU algorithms' framebuffers are). Written
// atomically (io_util.h). Throws InputError for an unsupported extension or a write failure.
void write_image(const std::string& path, const Image& image, glm::dvec3 background = glm::dvec3(0.0));
void write_npy(const std::string& path, const Image& image);
void write_png(const std::string& path, const Image& image, glm::dvec3 background);
void write_exr(const std::string& path, const Image& image);  // image_exr.cpp

// An OpenEXR image's R, G, B and (when present: *has_alpha) A channels as float, whatever their stored type, row 0 on
// top; without A, alpha is 1. Throws InputError naming the file.
Image read_exr(const std::string& path, bool* has_alpha = nullptr);

// Reads a float32 H x W x 4 (or H x W x 3, alpha 1) .npy written by uvr or numpy. Throws InputError on anything else.
Image read_npy(const std::string& path, int* channels = nullptr);  // channels: 4, or 3 (alpha set to 1)

// An image made by another renderer, to be measured against uvr's reference (uvr compare --image), by extension:
// .npy (H x W x 4 float32 premultiplied RGBA, row 0 on top, as uvr writes; H x W x 3: colour only), .exr (R, G, B and
// A premultiplied, as the format defines them; without A: colour only), .pfm (float RGB, rows from the bottom as the
// format stores them; colour only), .png (8-bit RGB, or RGBA composited over black; colour only, in steps of 1/255).
// Throws InputError naming the file and what is wrong, a value that is not finite included.
struct OutsideImage {
    Image image;
    bool colour_only = false;  // no alpha: only the colour over black can be compared
};
OutsideImage read_outside_image(const std::string& path);

// 8-bit RGB(A) rows for a PNG of arbitrary content (error heat-maps, diagnostics), written atomically.
void write_png_rgb8(const std::string& path, int width, int height, const std::vector<unsigned char>& rgb);

// "WxH" -> width, height (each 1..16384). Throws InputError (file empty) with the option text.
void parse_size(const std::string& text, int& width, int& height);

}  // namespace uvr
