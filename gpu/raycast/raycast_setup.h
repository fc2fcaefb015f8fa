// The ray caster's CPU stage (Krüger and Westermann), shared by the emulated driver (gpu/raycast/raycast.cpp) and the
// GL driver (gpu/raycast/gl_raycast.cpp), so that both march the same texture with the same tables and constants:
//   - once per volume (RaycastVolume): the volume texture's texels in the format the GPU holds them, the encoding
//     from a texel's value to the normalized scalar, the tables (classification, or the pre-integrated one of HAVS);
//   - once per frame (raycast_frame_constants): the uniforms of the fragment program (gpu/raycast/raycast_fragment.h).
// Twins: none (CPU stage); gpu/raycast/gl_raycast.h uploads its textures and sets its uniforms.
// Derivation (texel centres, --volume-format, the scalar encoding): docs/raycast.md, "The volume texture".
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "gpu/raycast/classification_table.h"
#include "gpu/pipeline/segment.h"
#include "gpu/pipeline/interpolation.h"
#include "gpu/pipeline/preintegration_table.h"
#include "gpu/raycast/raycast_fragment.h"
#include "reference/camera.h"
#include "reference/volume.h"
#include "reference/choice.h"

namespace uvr::gpu {

enum class VolumeFormat { native, f32, u16, u8 };
inline constexpr Choices<VolumeFormat, 4> kVolumeFormats{{{VolumeFormat::native, "native", "the data's own type"},
                                                          {VolumeFormat::f32, "f32", "32-bit float"},
                                                          {VolumeFormat::u16, "u16", "16-bit unorm"},
                                                          {VolumeFormat::u8, "u8", "8-bit unorm"}}};
VolumeFormat parse_volume_format(const std::string& name);  // "native", "f32", "u16", "u8"; InputError otherwise

// Blinn-Phong with a point light (--light X,Y,Z in world coordinates).
struct RaycastLight {
    glm::dvec3 position{0.0};
    double ambient = 0.3, diffuse = 0.7, specular = 0.2;
    int shininess = 16;
};

struct RaycastOptions {
    double step = 0.0;  // world units; 0: half the smallest spacing (docs/spec.md §3)
    bool preintegrate = false;
    float threshold = 0.95f;  // docs/spec.md §3; 1 switches early termination off
    VolumeFormat volume_format = VolumeFormat::native;
    std::optional<RaycastLight> light;  // shading when set
    SegmentMode segment = SegmentMode::table;  // --preintegrate: the table, or the exact integral (emulation only)
    int table_size = 128;            // the pre-integrated table's texels per axis
    TexelFormat table_format = TexelFormat::f32;
    // gpu: the published passes, entry and exit from the box's faces as the rasterizer interpolates them (docs/spec.md
    // §7); exact: the pixel's ray against the box in double (docs/raycast.md, "The published passes").
    InterpolationMode interpolation = InterpolationMode::gpu;
};

// The step when none is given: half the smallest spacing (docs/spec.md §3).
double default_raycast_step(const Volume& volume);

// A ray never takes more samples than this: --step is refused when the box's diagonal needs more.
inline constexpr int kMaxRaySamples = 1 << 20;

// Texels an 8- or 16-bit volume texture holds past its last one: the packet march (gpu/raycast/raycast_packet.h) reads
// each texel as the low byte or half of a 32-bit gather, so up to 3 bytes beyond the last one are read, and ignored.
inline constexpr std::size_t kPacketGatherPadding = 3;

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
    std::shared_ptr<const PreintegrationTable> table_;
    double table_ms_ = 0.0;
};

// The fragment program's uniforms for one frame.
RaycastFrameConstants raycast_frame_constants(const RaycastVolume& rv, const Camera& cam, int width, int height);

// The textures as the emulation reads them (the volume's, the tables; llvmpipe's features of this CPU).
RaycastTextures raycast_textures(const RaycastVolume& rv);

}  // namespace uvr::gpu
