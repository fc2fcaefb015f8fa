// The on-disk cache of reference images, so that studies never compute one twice.
//
// A reference image is a pure function of the mesh (points, tetrahedra) and the field's values, or the regular grid,
// and of the transfer function, the camera and the size; its key is a 64-bit FNV-1a hash over all of those bytes plus a
// version tag that changes whenever the reference's numerics change. Entries are .npy files written atomically
// (io_util.h), so an interrupted run never leaves a corrupt entry; an entry that does not read back as an image of the
// right size is ignored.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "reference/camera.h"
#include "reference/image.h"
#include "reference/mesh.h"
#include "reference/transfer_function.h"
#include "reference/volume.h"

namespace uvr {

// Bump when the reference integrator's results change, so old entries are not reused: the tetrahedral walk's, and
// the regular grids' (reference/volume_integrator.h).
inline constexpr const char* kReferenceCacheVersion = "uvr-reference-6";
inline constexpr const char* kVolumeReferenceCacheVersion = "uvr-volume-reference-2";

class Fnv1a {
public:
    void add(const void* data, std::size_t n);
    void add(const std::string& s) { add(s.data(), s.size()); }
    uint64_t value() const { return h_; }

private:
    uint64_t h_ = 1469598103934665603ull;
};

std::string reference_cache_key(const TetMesh& mesh, std::size_t field, const TransferFunction& tf,
                                const Camera& camera, int width, int height);
// A regular grid's: its dimensions, origin, spacing and samples instead of a mesh's points, cells and field.
std::string reference_cache_key(const Volume& volume, const TransferFunction& tf, const Camera& camera, int width,
                                int height);

// $UVR_CACHE_DIR, else $XDG_CACHE_HOME/uvr, else $HOME/.cache/uvr; created on first store.
std::string reference_cache_dir();

std::optional<Image> cache_load(const std::string& key, int width, int height);
// Stores best-effort: a cache that cannot be written is reported on stderr once and otherwise ignored.
void cache_store(const std::string& key, const Image& image);

}  // namespace uvr
