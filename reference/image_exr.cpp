// OpenEXR images (Debian's libopenexr): uvr's .npy layout in EXR's float channels, both ways (reference/image.h).
#include <exception>
#include <string>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfStdIO.h>

#include "reference/error.h"
#include "reference/image.h"
#include "reference/io_util.h"

namespace uvr {

namespace {

// Sizes an EXR may have here: the same bound the other readers put on a side (a corrupt header cannot make us
// allocate terabytes).
constexpr long kMaxSide = 65536;

}  // namespace

void write_exr(const std::string& path, const Image& image)
{
    // FLOAT channels, not HALF: the values must come back with the bits uvr computed (an EXR is then as exact as the
    // .npy). EXR's pixels are premultiplied and its rows go from the top, as uvr's are. Encoded in memory, then
    // written atomically like every output (io_util.h), so a failure leaves nothing half-written.
    std::string bytes;
    try {
        Imf::Header header(image.width, image.height);
        header.compression() = Imf::ZIP_COMPRESSION;  // lossless
        const char* names[4] = {"R", "G", "B", "A"};
        for (const char* n : names) header.channels().insert(n, Imf::Channel(Imf::FLOAT));
        Imf::FrameBuffer fb;
        const std::size_t xs = 4 * sizeof(float), ys = xs * std::size_t(image.width);
        for (int c = 0; c < 4; ++c)
            fb.insert(names[c], Imf::Slice(Imf::FLOAT, (char*)(image.rgba.data() + c), xs, ys));
        Imf::StdOSStream stream;
        {
            Imf::OutputFile out(stream, header);
            out.setFrameBuffer(fb);
            out.writePixels(image.height);
        }  // the file's offset table is written when it closes
        bytes = stream.str();
    } catch (const std::exception& e) {
        throw InputError(path, std::string("cannot encode the OpenEXR image: ") + e.what());
    }
    write_file_atomically(path, bytes);
}

Image read_exr(const std::string& path, bool* has_alpha)
{
    try {
        Imf::InputFile in(path.c_str());
        const Imath::Box2i dw = in.header().dataWindow();
        const long w = long(dw.max.x) - dw.min.x + 1, h = long(dw.max.y) - dw.min.y + 1;
        if (w <= 0 || h <= 0 || w > kMaxSide || h > kMaxSide)
            throw InputError(path, "OpenEXR data window of " + std::to_string(w) + "x" + std::to_string(h) +
                                       " is out of range");
        const Imf::ChannelList& ch = in.header().channels();
        for (const char* n : {"R", "G", "B"})
            if (!ch.findChannel(n))
                throw InputError(path, std::string("OpenEXR image has no ") + n +
                                           " channel (uvr reads R, G, B and optionally A)");
        for (auto it = ch.begin(); it != ch.end(); ++it)
            if (it.channel().xSampling != 1 || it.channel().ySampling != 1)
                throw InputError(path, std::string("OpenEXR channel ") + it.name() + " is subsampled");
        const bool alpha = ch.findChannel("A") != nullptr;
        if (has_alpha) *has_alpha = alpha;
        Image img{int(w), int(h)};
        // The data window may start anywhere: the frame buffer's base is shifted so pixel (min.x, min.y) lands on
        // element 0. HALF and UINT channels are converted to FLOAT by the library (HALF exactly).
        const std::size_t xs = 4 * sizeof(float), ys = xs * std::size_t(w);
        char* base = reinterpret_cast<char*>(img.rgba.data()) - std::ptrdiff_t(dw.min.x) * std::ptrdiff_t(xs) -
                     std::ptrdiff_t(dw.min.y) * std::ptrdiff_t(ys);
        Imf::FrameBuffer fb;
        const char* names[4] = {"R", "G", "B", "A"};
        for (int c = 0; c < 4; ++c)
            fb.insert(names[c], Imf::Slice(Imf::FLOAT, base + c * sizeof(float), xs, ys, 1, 1, c == 3 ? 1.0 : 0.0));
        in.setFrameBuffer(fb);
        in.readPixels(dw.min.y, dw.max.y);
        return img;
    } catch (const InputError&) {
        throw;
    } catch (const std::exception& e) {
        throw InputError(path, std::string("not a readable OpenEXR image: ") + e.what());
    }
}

}  // namespace uvr
