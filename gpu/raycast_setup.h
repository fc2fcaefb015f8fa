// The ray caster's CPU stage (seed 002), shared by the emulated driver (raycast.cpp) and the GL driver
// (gl_raycast.cpp), so that both march the same texture with the same tables and constants:
//   - once per volume (RaycastVolume): the volume texture's texels in the format the GPU holds them, the encoding
//     from a texel's value to the normalized scalar, the tables (classification, or the pre-integrated one of HAVS);
//   - once per frame (raycast_frame_constants): the uniforms of the fragment program (gpu/raycast_fragment.h).
//
// The volume texture. Texel i of each axis is sample i (GL's texel centres): trilinear GL_LINEAR filtering between
// texel centres is the trilinear field of the reference (reference/volume_integrator.h) inside the samples' box, and
// the march never leaves that box. Formats (--volume-format):
//   - native (the default): a uint8 volume as R8 with its bytes, a uint16 volume as R16 with its values, any other
//     type as R32F holding the normalized scalar (s - lo) / (hi - lo) rounded to float;
//   - f32, u16, u8: the normalized scalar in that format, quantized as a glTexImage3D upload of float data quantizes
//     it (float_to_unorm16 / float_to_unorm8), for comparing formats on one volume.
// The texture answers u (the unorm value, or the float); the shader turns it into the table coordinate x = u *
// scalar_scale + scalar_bias, the scalar normalized over the tables' range (for native R8 the scalar is 255 u, for
// native R16 65535 u, for the normalized encodings lo + u (hi - lo)). The tables' range is the data's widened by half
// a texel at each end (raycast_setup.cpp says why).
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "gpu/classification_table.h"
#include "gpu/havs_setup.h"
#include "gpu/preintegration_table.h"
#include "gpu/raycast_fragment.h"
#include "reference/camera.h"
#include "reference/volume.h"

namespace uvr::gpu {

enum class VolumeFormat { native, f32, u16, u8 };
VolumeFormat parse_volume_format(const std::string& name);  // "native", "f32", "u16", "u8"; InputError otherwise

// Blinn-Phong with a point light (--light X,Y,Z in world coordinates).
struct RaycastLight {
    glm::dvec3 position{0.0};
    double ambient = 0.3, diffuse = 0.7, specular = 0.2;
    int shininess = 16;
};

struct RaycastOptions {
    double step = 0.0;               // world units; 0: half the smallest spacing (SPEC §3)
    bool preintegrate = false;
    float threshold = 0.95f;         // SPEC §3; 1 switches early termination off
    VolumeFormat volume_format = VolumeFormat::native;
    std::optional<RaycastLight> light;  // shading when set
    SegmentMode segment = SegmentMode::table;  // --preintegrate: the table, or the exact integral (emulation only)
    int table_size = 128;            // the pre-integrated table's texels per axis
    TexelFormat table_format = TexelFormat::f32;
};

// The step when none is given: half the smallest spacing (SPEC §3).
double default_raycast_step(const Volume& volume);

// A ray never takes more samples than this: --step is refused when the box's diagonal needs more.
inline constexpr int kMaxRaySamples = 1 << 20;

class RaycastVolume {
public:
    // Throws InputError naming the volume for an option out of range (a step that is not positive, or so small that
    // a ray would need more than kMaxRaySamples samples).
    RaycastVolume(const Volume& volume, const TransferFunction& tf, const RaycastOptions& options);

    const Volume& volume() const { return volume_; }
    const RaycastOptions& options() const { return options_; }  // step filled in
    const Range& range() const { return range_; }        // the data's
    const Range& table_range() const { return table_range_; }  // the tables': the data's, half a texel wider
    const glm::dvec3& origin() const { return origin_; }  // the box's centre
    TexelFormat texel_format() const { return format_; }
    TextureView view() const;  // the volume texture (one channel)
    const void* texels() const;
    float scalar_scale() const { return scalar_scale_; }
    float scalar_bias() const { return scalar_bias_; }
    const SegmentIntegrator& integrator() const { return integrator_; }
    const ClassificationTable* classification() const { return classification_.get(); }  // post-classification
    const PreintegrationTable* table() const { return table_.get(); }  // --preintegrate with the table
    double table_ms() const { return table_ms_; }
    std::size_t texture_bytes() const;

private:
    const Volume& volume_;
    RaycastOptions options_;
    Range range_, table_range_;
    glm::dvec3 origin_{0.0};
    TexelFormat format_ = TexelFormat::f32;
    std::vector<float> f32_;
    std::vector<uint16_t> u16_;
    std::vector<uint8_t> u8_;
    float scalar_scale_ = 1.0f, scalar_bias_ = 0.0f;
    SegmentIntegrator integrator_;
    std::unique_ptr<ClassificationTable> classification_;
    std::unique_ptr<PreintegrationTable> table_;
    double table_ms_ = 0.0;
};

// The fragment program's uniforms for one frame.
RaycastFrameConstants raycast_frame_constants(const RaycastVolume& rv, const Camera& cam, int width, int height);

// The textures as the emulation reads them (the volume's, the tables; llvmpipe's features of this CPU).
RaycastTextures raycast_textures(const RaycastVolume& rv);

}  // namespace uvr::gpu
