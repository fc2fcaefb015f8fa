#include "gpu/raycast/raycast_setup.h"

#include <chrono>
#include <cmath>
#include <cstdio>

#include "gpu/pipeline/pixel_rays.h"
#include "reference/error.h"
#include "reference/timing.h"

namespace uvr::gpu {

VolumeFormat parse_volume_format(const std::string& name)
{
    return parse_choice("--volume-format", kVolumeFormats, name);
}

double default_raycast_step(const Volume& volume)
{
    const glm::dvec3& sp = volume.spacing;
    return 0.5 * std::min(sp.x, std::min(sp.y, sp.z));
}

RaycastVolume::RaycastVolume(const Volume& volume, const TransferFunction& tf, const RaycastOptions& options)
    : volume_(volume), options_(options), range_(volume_range(volume)), integrator_(tf)
{
    const Bounds box = volume_bounds(volume);
    origin_ = box.center();
    if (options_.step == 0.0) options_.step = default_raycast_step(volume);
    if (!(options_.step > 0.0) || !std::isfinite(options_.step))
        throw InputError(volume.source, "--step must be positive and finite (world units)");
    const glm::dvec3 e = box.extent();
    const double diagonal = std::sqrt(e.x * e.x + e.y * e.y + e.z * e.z);
    if (diagonal / options_.step > double(kMaxRaySamples - 2))
    {
        char msg[160];
        std::snprintf(msg, sizeof msg, "--step %g would take more than %d samples along the volume's diagonal (%g)",
                      options_.step, kMaxRaySamples, diagonal);
        throw InputError(volume.source, msg);
    }
    if (!(options_.threshold >= 0.0f && options_.threshold <= 1.0f))
        throw InputError(volume.source, "--threshold must be in [0, 1]");
    if (options_.light && !(options_.light->shininess >= 0 && options_.light->shininess <= 1024))
        throw InputError(volume.source, "the light's shininess must be in [0, 1024]");

    // The tables' range: the data's, widened by half a texel at each end, so that the first and last texel centres
    // hold the data's extreme values. With the data's own range the lowest half texel of normalized scalars, [0,
    // 0.5 / N], would clamp to a texel holding a higher scalar: an error of the order of 1 / N wherever values crowd
    // the range's ends (measured on hydrogen, whose values are mostly near 0: RMSE 4.6e-3 with the 128-texel
    // pre-integrated table, 2.1e-5 with the widened range; docs/raycast.md).
    const double lo = range_.lo, span = range_.hi > range_.lo ? range_.hi - range_.lo : 1.0;
    const int texels = options_.preintegrate ? options_.table_size : kClassificationTexels;
    table_range_ = texel_centred_range(range_, texels);
    const double table_span = table_range_.hi - table_range_.lo;
    // A texel's value u stands for the scalar u * unit + zero; the shader's x = u * scalar_scale + scalar_bias is
    // that scalar normalized over the tables' range.
    double unit = span, zero = lo;
    const std::size_t n = volume.values.size();
    VolumeFormat f = options_.volume_format;
    if (f == VolumeFormat::native && volume.type == VoxelType::u8) {
        format_ = TexelFormat::u8;
        u8_.resize(n + kPacketGatherPadding);
        for (std::size_t i = 0; i < n; ++i) u8_[i] = uint8_t(volume.values[i]);
        unit = 255.0, zero = 0.0;
    } else if (f == VolumeFormat::native && volume.type == VoxelType::u16) {
        format_ = TexelFormat::u16;
        u16_.resize(n + kPacketGatherPadding);
        for (std::size_t i = 0; i < n; ++i) u16_[i] = uint16_t(volume.values[i]);
        unit = 65535.0, zero = 0.0;
    } else {
        // The scalar normalized over the data's range, then the format's quantization (the upload of float data).
        format_ = f == VolumeFormat::u16 ? TexelFormat::u16 : f == VolumeFormat::u8 ? TexelFormat::u8 : TexelFormat::f32;
        auto normalized = [&](std::size_t i) { return float((double(volume.values[i]) - lo) / span); };
        if (format_ == TexelFormat::f32) {
            f32_.resize(n);
            for (std::size_t i = 0; i < n; ++i) f32_[i] = normalized(i);
        } else if (format_ == TexelFormat::u16) {
            u16_.resize(n + kPacketGatherPadding);
            for (std::size_t i = 0; i < n; ++i) u16_[i] = float_to_unorm16(normalized(i));
        } else {
            u8_.resize(n + kPacketGatherPadding);
            for (std::size_t i = 0; i < n; ++i) u8_[i] = float_to_unorm8(normalized(i));
        }
    }
    scalar_scale_ = float(unit / table_span);
    scalar_bias_ = float((zero - table_range_.lo) / table_span);

    const auto t0 = Clock::now();
    if (!options_.preintegrate) {
        classification_ = std::make_unique<ClassificationTable>(integrator_, table_range_, options_.step);
        table_ms_ = ms_since(t0);
    } else if (options_.segment == SegmentMode::table) {
        // The length axis spans [0, step]: every segment of the march is a full step but the last, which is shorter.
        table_ = build_segment_table(integrator_, table_range_, options_.table_size, options_.table_format, options_.step,
                                     table_ms_);
    }
}

const void* RaycastVolume::texels() const
{
    switch (format_) {
    case TexelFormat::u8: return u8_.data();
    case TexelFormat::u16: return u16_.data();
    case TexelFormat::f32: break;
    }
    return f32_.data();
}

std::size_t RaycastVolume::texture_bytes() const
{
    return volume_.values.size() * std::size_t(texel_channel_bytes(format_));
}

TextureView RaycastVolume::view() const
{
    TextureView v;
    v.format = format_;
    v.channels = 1;
    v.width = int(volume_.dims[0]);
    v.height = int(volume_.dims[1]);
    v.depth = int(volume_.dims[2]);
    v.texels = texels();
    return v;
}

RaycastFrameConstants raycast_frame_constants(const RaycastVolume& rv, const Camera& cam, int width, int height)
{
    RaycastFrameConstants fc;
    static_cast<PixelRays&>(fc) = pixel_rays(cam, width, height, rv.origin());
    const Volume& v = rv.volume();
    const Bounds box = volume_bounds(v);
    fc.box_lo = box.lo - rv.origin();
    fc.box_hi = box.hi - rv.origin();
    const glm::dvec3 dims(double(v.dims[0]), double(v.dims[1]), double(v.dims[2]));
    fc.tex_scale = 1.0 / (dims * v.spacing);
    fc.tex_half = 0.5 / dims;
    fc.tex_extent = glm::vec3(dims * v.spacing);
    const RaycastOptions& o = rv.options();
    fc.step = o.step;
    fc.step_f = float(o.step);
    const glm::dvec3 e = box.extent();
    fc.max_samples = int(std::sqrt(e.x * e.x + e.y * e.y + e.z * e.z) / o.step) + 2;
    fc.preintegrate = o.preintegrate ? 1 : 0;
    fc.threshold = o.threshold;
    fc.scalar_scale = rv.scalar_scale();
    fc.scalar_bias = rv.scalar_bias();
    if (const PreintegrationTable* table = rv.table()) {
        fc.length_scale = table->length_scale();
        fc.length_bias = table->length_bias();
    }
    if (o.light) {
        fc.shade = 1;
        fc.light = o.light->position - rv.origin();
        fc.ambient = o.light->ambient;
        fc.diffuse = o.light->diffuse;
        fc.specular = o.light->specular;
        fc.shininess = o.light->shininess;
        fc.texel = glm::vec3(1.0 / dims);
        fc.gradient_scale = glm::vec3(0.5 / v.spacing);
    }
    return fc;
}

RaycastTextures raycast_textures(const RaycastVolume& rv)
{
    RaycastTextures t;
    t.volume = rv.view();
    t.classification = rv.classification();
    t.cpu = host_llvmpipe_cpu();
    if (rv.options().preintegrate) {
        t.segment = segment_shader(rv.table(), TextureFilter::linear, rv.integrator(), rv.table_range());
        t.table_segment = table_segment_shader(rv.table(), TextureFilter::linear);
        t.exact_segment = exact_segment_shader(rv.table(), rv.integrator(), rv.table_range());
    }
    return t;
}

}  // namespace uvr::gpu
