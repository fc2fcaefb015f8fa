#include "reference/image_cache.h"

#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "reference/error.h"

namespace uvr {

void Fnv1a::add(const void* data, std::size_t n)
{
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < n; ++i) {
        h_ ^= p[i];
        h_ *= 1099511628211ull;
    }
}

namespace {

// The scene's hash so far, finished with what every reference image depends on, as 16 hex digits.
std::string finish_key(Fnv1a& h, const TransferFunction& tf, const Camera& camera, int width, int height)
{
    h.add(transfer_function_json(tf));
    h.add(camera_json(camera));
    h.add(&width, sizeof width);
    h.add(&height, sizeof height);
    char buf[32];
    std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h.value()));
    return buf;
}

}  // namespace

std::string reference_cache_key(const TetMesh& mesh, std::size_t field, const TransferFunction& tf,
                                const Camera& camera, int width, int height)
{
    Fnv1a h;
    h.add(std::string(kReferenceCacheVersion));
    h.add(mesh.points.data(), mesh.points.size() * sizeof(glm::dvec3));
    h.add(mesh.tets.data(), mesh.tets.size() * sizeof(Tet));
    const ScalarField& f = mesh.fields.at(field);
    h.add(f.values.data(), f.values.size() * sizeof(double));
    h.add(&f.association, sizeof f.association);
    return finish_key(h, tf, camera, width, height);
}

std::string reference_cache_key(const Volume& volume, const TransferFunction& tf, const Camera& camera, int width,
                                int height)
{
    Fnv1a h;
    h.add(std::string(kVolumeReferenceCacheVersion));
    h.add(volume.dims.data(), sizeof volume.dims);
    h.add(&volume.origin, sizeof volume.origin);
    h.add(&volume.spacing, sizeof volume.spacing);
    h.add(volume.values.data(), volume.values.size() * sizeof(float));
    return finish_key(h, tf, camera, width, height);
}

std::string reference_cache_dir()
{
    if (const char* d = std::getenv("UVR_CACHE_DIR"); d && *d) return d;
    if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x) return std::string(x) + "/uvr";
    if (const char* home = std::getenv("HOME"); home && *home) return std::string(home) + "/.cache/uvr";
    return "/tmp/uvr-cache";
}

std::optional<Image> cache_load(const std::string& key, int width, int height)
{
    const std::string path = reference_cache_dir() + "/" + key + ".npy";
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) return std::nullopt;
    try {
        Image img = read_npy(path);
        if (img.width == width && img.height == height) return img;
    } catch (const InputError&) {
        // A damaged entry is not an error of the user's: recompute and overwrite it.
    }
    return std::nullopt;
}

void cache_store(const std::string& key, const Image& image)
{
    const std::string dir = reference_cache_dir();
    try {
        std::filesystem::create_directories(dir);
        write_npy(dir + "/" + key + ".npy", image);
    } catch (const std::exception& e) {
        static bool warned = false;
        if (!warned) std::fprintf(stderr, "uvr: warning: reference cache not written (%s)\n", e.what());
        warned = true;
    }
}

}  // namespace uvr
