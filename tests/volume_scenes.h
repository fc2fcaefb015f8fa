// Volumes for the regular-grid tests (the reference's and the ray caster's): grids made from a field function, and the
// shared data sets with the CLI's defaults (the transfer function and camera `uvr render` uses without options).
#pragma once

#include <array>
#include <functional>
#include <string>

#include <glm/geometric.hpp>

#include "reference/camera.h"
#include "reference/dataset.h"
#include "reference/transfer_function.h"
#include "reference/volume.h"
#include "test_support.h"

namespace uvr::test {

// Sample (i, j, k) = field(origin + (i, j, k) * spacing).
inline Volume grid(std::array<int64_t, 3> dims, glm::dvec3 origin, glm::dvec3 spacing,
                   const std::function<double(const glm::dvec3&)>& field)
{
    Volume v;
    v.source = "test grid";
    v.dims = dims;
    v.origin = origin;
    v.spacing = spacing;
    for (int64_t k = 0; k < dims[2]; ++k)
        for (int64_t j = 0; j < dims[1]; ++j)
            for (int64_t i = 0; i < dims[0]; ++i)
                v.values.push_back(float(field(origin + glm::dvec3(double(i), double(j), double(k)) * spacing)));
    finalize_volume(v);
    return v;
}

// A data set from data with the CLI's default transfer function and default camera (orbited by az, el).
struct VolumeScene {
    Volume volume;
    TransferFunction tf;
    Camera camera;
};

inline VolumeScene volume_scene(const std::string& rel, double azimuth = 0.0, double elevation = 0.0)
{
    Dataset d = load_dataset(data_path(rel));
    VolumeScene s{std::move(*d.volume), {}, {}};
    const Bounds b = volume_bounds(s.volume);
    s.tf = default_transfer_function(volume_range(s.volume), glm::length(b.extent()));
    s.camera = default_camera(b, 1.0, azimuth, elevation);
    return s;
}

}  // namespace uvr::test
