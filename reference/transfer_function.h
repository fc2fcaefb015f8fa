// Transfer functions (SPEC §1): colour and extinction, piecewise linear in the scalar, constant beyond the end nodes.
#pragma once

#include <array>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "reference/mesh.h"

namespace uvr {

struct ColorNode {
    double s;
    glm::dvec3 rgb;
};
struct ExtinctionNode {
    double s;
    double tau;  // per world unit
};

struct TransferFunction {
    std::vector<ColorNode> color;            // sorted by s, at least one node
    std::vector<ExtinctionNode> extinction;  // sorted by s, at least one node

    glm::dvec3 color_at(double s) const;
    double tau_at(double s) const;
    // The sorted, unique scalar values where colour or extinction has a kink: a segment integral is split there.
    std::vector<double> breakpoints() const;
};

// Reads the JSON of SPEC §1: {"color": [[s,r,g,b],...], "extinction": [[s,tau],...]}, or "opacity" [[s,a],...] with
// "unit_distance" u (tau = -ln(1-a)/u per node), and a ParaView preset ("RGBPoints", flat s,r,g,b list; also a preset
// object or a one-element list of them under "color"). Throws InputError naming the file (and the line for JSON syntax
// errors) on anything malformed: unsorted nodes, colour outside [0,1], negative or non-finite extinction, opacity >= 1.
TransferFunction load_transfer_function(const std::string& path);
TransferFunction parse_transfer_function(const std::string& json_text, const std::string& file);

// The default: a five-node colour ramp over the field's range and an extinction with two bumps, scaled so that a ray
// along the whole bounding-box diagonal at the largest extinction has optical depth kDefaultOpticalDepth. That keeps
// the default image neither empty nor opaque whatever the mesh's size.
inline constexpr double kDefaultOpticalDepth = 4.0;
TransferFunction default_transfer_function(Range range, double bounds_diagonal);

std::string transfer_function_json(const TransferFunction& tf);

}  // namespace uvr
