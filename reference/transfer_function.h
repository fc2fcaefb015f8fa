// Transfer functions (docs/spec.md §1): colour and extinction, piecewise linear in the scalar, constant beyond the end
// nodes.
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
    // Whether extinction is zero for every scalar in [lo, hi].
    bool clear_between(double lo, double hi) const;
    // The sorted, unique scalar values where colour or extinction has a kink: a segment integral is split there.
    std::vector<double> breakpoints() const;
};

// Reads the JSON of docs/spec.md §1: {"color": [[s,r,g,b],...], "extinction": [[s,tau],...]}, or "opacity" [[s,a],...]
// with "unit_distance" u (tau = -ln(1-a)/u per node), and a ParaView preset ("RGBPoints", flat s,r,g,b list; also a
// preset object or a one-element list of them under "color"). Throws InputError naming the file (and the line for JSON
// syntax errors) on anything malformed: unsorted nodes, colour outside [0,1], negative or non-finite extinction,
// opacity >= 1.
TransferFunction load_transfer_function(const std::string& path);
TransferFunction parse_transfer_function(const std::string& json_text, const std::string& file);

// The default: a five-node colour ramp over the field's range and an extinction with two bumps, scaled so that a ray
// along the whole bounding-box diagonal at the largest extinction has optical depth kDefaultOpticalDepth. That keeps
// the default image neither empty nor opaque whatever the mesh's size.
inline constexpr double kDefaultOpticalDepth = 4.0;
TransferFunction default_transfer_function(Range range, double bounds_diagonal);

// The default for a regular grid: default_transfer_function, made transparent over the band of values around the
// histogram's most common value (256 bins over the range; the band reaches kBackgroundMargin of the range beyond that
// bin on each side, with linear ramps as wide), so that the dominant background (air around a CT scan, the empty space
// of a simulation box) does not fog the view; and its extinction raised by f^(-1/3), f the fraction of the voxels left
// visible (the window's mean), so that the visible part, not the whole box, gets the default's optical depth.
// docs/user-guide.md, "Regular grids".
inline constexpr double kBackgroundMargin = 0.02;
// The smallest f the boost takes (at most 4 times the extinction): below it the visible voxels are scattered specks
// (noise around the background), whose chords are not f^(1/3) of the box, and a larger boost would only make them
// opaque dots.
inline constexpr double kMinVisibleFraction = 1.0 / 64.0;
TransferFunction default_volume_transfer_function(const std::vector<float>& values, Range range, double bounds_diagonal);

// --tf preset:NAME: the default extinction under one of ParaView's common colour maps, by its ParaView name or short
// name, case-insensitive: "Viridis (matplotlib)" / viridis, "Inferno (matplotlib)" / inferno, "Plasma (matplotlib)" /
// plasma, "Cool to Warm" / cool-to-warm, "Grayscale" / grayscale, "Jet" / jet. Throws InputError listing them.
TransferFunction with_colour_preset(TransferFunction tf, Range range, const std::string& name);
std::vector<std::string> colour_preset_names();

std::string transfer_function_json(const TransferFunction& tf);

}  // namespace uvr
