#include "reference/transfer_function.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>

#include <nlohmann/json.hpp>

#include "reference/error.h"
#include "reference/io_util.h"

namespace uvr {

namespace {

template <class Node, class Get>
auto piecewise_linear(const std::vector<Node>& nodes, double s, Get get)
{
    if (s <= nodes.front().s) return get(nodes.front());
    if (s >= nodes.back().s) return get(nodes.back());
    // First node with node.s > s; nodes with equal s form a jump, and the later one applies at s exactly.
    auto it = std::upper_bound(nodes.begin(), nodes.end(), s, [](double v, const Node& n) { return v < n.s; });
    const Node& b = *it;
    const Node& a = *(it - 1);
    const double w = (s - a.s) / (b.s - a.s);
    return get(a) + (get(b) - get(a)) * w;
}

long line_of(const std::string& text, std::size_t byte)
{
    return 1 + static_cast<long>(std::count(text.begin(), text.begin() + static_cast<long>(std::min(byte, text.size())),
                                            '\n'));
}

double number(const nlohmann::json& v, const std::string& file, const std::string& where)
{
    if (!v.is_number()) throw InputError(file, where + " must be a number, found " + v.dump());
    const double d = v.get<double>();
    if (!std::isfinite(d)) throw InputError(file, where + " is not finite");
    return d;
}

std::vector<std::vector<double>> node_list(const nlohmann::json& arr, std::size_t width, const std::string& file,
                                           const std::string& key)
{
    if (!arr.is_array() || arr.empty())
        throw InputError(file, "\"" + key + "\" must be a non-empty list of [s, ...] nodes");
    std::vector<std::vector<double>> out;
    for (std::size_t i = 0; i < arr.size(); ++i) {
        const auto& n = arr[i];
        const std::string where = "\"" + key + "\" node " + std::to_string(i);
        if (!n.is_array() || n.size() != width)
            throw InputError(file, where + " must have " + std::to_string(width) + " numbers, found " + n.dump());
        std::vector<double> row;
        for (std::size_t k = 0; k < width; ++k) row.push_back(number(n[k], file, where));
        if (!out.empty() && row[0] < out.back()[0])
            throw InputError(file, where + " is out of order: s = " + std::to_string(row[0]) + " after " +
                                       std::to_string(out.back()[0]) + " (nodes must be sorted by s)");
        out.push_back(row);
    }
    return out;
}

std::vector<ColorNode> rgb_points(const nlohmann::json& preset, const std::string& file)
{
    const nlohmann::json* p = &preset;
    if (p->is_array() && p->size() == 1 && (*p)[0].is_object()) p = &(*p)[0];
    if (!p->is_object() || !p->contains("RGBPoints"))
        throw InputError(file, "a ParaView preset must hold \"RGBPoints\"");
    const auto& pts = (*p)["RGBPoints"];
    if (!pts.is_array() || pts.empty() || pts.size() % 4 != 0)
        throw InputError(file, "\"RGBPoints\" must be a flat list of s, r, g, b quadruples");
    nlohmann::json rows = nlohmann::json::array();
    for (std::size_t i = 0; i < pts.size(); i += 4) rows.push_back({pts[i], pts[i + 1], pts[i + 2], pts[i + 3]});
    std::vector<ColorNode> out;
    for (const auto& r : node_list(rows, 4, file, "RGBPoints")) out.push_back({r[0], {r[1], r[2], r[3]}});
    return out;
}

}  // namespace

glm::dvec3 TransferFunction::color_at(double s) const
{
    return piecewise_linear(color, s, [](const ColorNode& n) { return n.rgb; });
}

bool TransferFunction::clear_between(double lo, double hi) const
{
    if (tau_at(lo) != 0.0 || tau_at(hi) != 0.0) return false;
    // Linear between nodes: zero at both ends and at every node between (both sides of a jump) is zero throughout.
    auto it = std::lower_bound(extinction.begin(), extinction.end(), lo,
                               [](const ExtinctionNode& n, double v) { return n.s < v; });
    for (; it != extinction.end() && it->s <= hi; ++it)
        if (it->tau != 0.0) return false;
    return true;
}

double TransferFunction::tau_at(double s) const
{
    return piecewise_linear(extinction, s, [](const ExtinctionNode& n) { return n.tau; });
}

std::vector<double> TransferFunction::breakpoints() const
{
    std::vector<double> b;
    for (const auto& n : color) b.push_back(n.s);
    for (const auto& n : extinction) b.push_back(n.s);
    std::sort(b.begin(), b.end());
    b.erase(std::unique(b.begin(), b.end()), b.end());
    return b;
}

TransferFunction parse_transfer_function(const std::string& text, const std::string& file)
{
    nlohmann::json j;
    try {
        j = nlohmann::json::parse(text);
    } catch (const nlohmann::json::parse_error& e) {
        throw InputError(file, line_of(text, e.byte ? e.byte - 1 : 0), std::string("invalid JSON: ") + e.what());
    } catch (const nlohmann::json::exception& e) {  // out_of_range 406: a number too large for a double (1e400)
        throw InputError(file, std::string("invalid JSON: ") + e.what());
    }
    if (!j.is_object()) throw InputError(file, "a transfer function must be a JSON object");
    TransferFunction tf;
    if (j.contains("RGBPoints")) {
        tf.color = rgb_points(j, file);
    } else if (j.contains("color")) {
        const auto& c = j["color"];
        if (c.is_object() || (c.is_array() && !c.empty() && c[0].is_object())) {
            tf.color = rgb_points(c, file);
        } else {
            for (const auto& r : node_list(c, 4, file, "color")) tf.color.push_back({r[0], {r[1], r[2], r[3]}});
        }
    } else {
        throw InputError(file, "missing \"color\" (or a ParaView \"RGBPoints\" preset)");
    }
    for (std::size_t i = 0; i < tf.color.size(); ++i)
        for (int k = 0; k < 3; ++k)
            if (tf.color[i].rgb[k] < 0.0 || tf.color[i].rgb[k] > 1.0)
                throw InputError(file, "colour node " + std::to_string(i) + " has a component outside [0, 1]");
    if (j.contains("extinction")) {
        for (const auto& r : node_list(j["extinction"], 2, file, "extinction")) {
            if (r[1] < 0.0) throw InputError(file, "extinction must be >= 0, found " + std::to_string(r[1]));
            tf.extinction.push_back({r[0], r[1]});
        }
    } else if (j.contains("opacity")) {
        if (!j.contains("unit_distance"))
            throw InputError(file, "\"opacity\" needs \"unit_distance\" (the length over which it applies)");
        const double u = number(j["unit_distance"], file, "\"unit_distance\"");
        if (!(u > 0.0)) throw InputError(file, "\"unit_distance\" must be positive");
        for (const auto& r : node_list(j["opacity"], 2, file, "opacity")) {
            if (r[1] < 0.0 || r[1] >= 1.0)
                throw InputError(file, "opacity must be in [0, 1) (1 would be an infinite extinction), found " +
                                           std::to_string(r[1]));
            const double tau = -std::log1p(-r[1]) / u;
            if (!std::isfinite(tau))
                throw InputError(file, "opacity " + std::to_string(r[1]) +
                                           " is an infinite extinction over so small a \"unit_distance\"");
            tf.extinction.push_back({r[0], tau});
        }
    } else {
        throw InputError(file, "missing \"extinction\" (or \"opacity\" with \"unit_distance\")");
    }
    return tf;
}

TransferFunction load_transfer_function(const std::string& path)
{
    return parse_transfer_function(read_file_bytes(path), path);
}

namespace {

// The default's colours: a viridis-like ramp, perceptually ordered, readable on black.
constexpr double kDefaultRamp[5][3] = {{0.267, 0.005, 0.329},
                                       {0.230, 0.322, 0.546},
                                       {0.128, 0.567, 0.551},
                                       {0.369, 0.789, 0.383},
                                       {0.993, 0.906, 0.144}};

// The ramp's nodes from `first` on, spread evenly over [lo, lo + d].
std::vector<ColorNode> ramp_colours(double lo, double d, int first)
{
    std::vector<ColorNode> c;
    const int n = 5 - first;
    for (int i = 0; i < n; ++i) {
        const double* rgb = kDefaultRamp[first + i];
        c.push_back({lo + d * i / double(n - 1), {rgb[0], rgb[1], rgb[2]}});
    }
    return c;
}

}  // namespace

TransferFunction default_transfer_function(Range range, double diagonal)
{
    double lo = range.lo, hi = range.hi;
    if (!(hi > lo)) hi = lo + 1.0;  // a constant field still gets a usable table
    const double d = hi - lo;
    TransferFunction tf;
    tf.color = ramp_colours(lo, d, 0);
    const double k = kDefaultOpticalDepth / (diagonal > 0.0 ? diagonal : 1.0);
    static const double kShape[5][2] = {{0.0, 0.05}, {0.3, 1.0}, {0.55, 0.15}, {0.8, 0.9}, {1.0, 0.3}};
    for (const auto& n : kShape) tf.extinction.push_back({lo + d * n[0], k * n[1]});
    return tf;
}

TransferFunction default_volume_transfer_function(const std::vector<float>& values, Range range, double diagonal)
{
    TransferFunction tf = default_transfer_function(range, diagonal);
    const double lo = range.lo, hi = range.hi > range.lo ? range.hi : range.lo + 1.0, d = hi - lo;
    constexpr int kBins = 256;
    std::vector<std::size_t> count(kBins, 0);
    for (float v : values) {
        if (!std::isfinite(v)) continue;
        const int b = std::clamp(int((double(v) - lo) / d * kBins), 0, kBins - 1);
        ++count[std::size_t(b)];
    }
    const int mode = int(std::max_element(count.begin(), count.end()) - count.begin());  // first of the most common
    // Transparent over [band_lo, band_hi], ramping back to the default over kBackgroundMargin on each side.
    const double band_lo = lo + d * (double(mode) / kBins - kBackgroundMargin);
    const double band_hi = lo + d * (double(mode + 1) / kBins + kBackgroundMargin);
    const double ramp = d * kBackgroundMargin;
    auto window = [&](double s) {
        if (s >= band_lo && s <= band_hi) return 0.0;
        const double away = s < band_lo ? band_lo - s : s - band_hi;
        return std::min(1.0, away / ramp);
    };
    // The product of two piecewise-linear functions: linear where the window is constant, so that its nodes there are
    // the default's, the window's corners and the range's ends; on the window's ramps a quadratic, sampled where the
    // range's kWindowSamples intervals meet. (A node between two collinear ones would change nothing but the cost:
    // every node is a breakpoint that the reference and the exact segments split at.)
    constexpr int kWindowSamples = 128;
    const auto on_ramp = [&](double s) {
        return (s > band_lo - ramp && s < band_lo) || (s > band_hi && s < band_hi + ramp);
    };
    std::vector<double> at{lo, lo + d * kWindowSamples / double(kWindowSamples)};
    for (int i = 1; i < kWindowSamples; ++i)
        if (const double s = lo + d * i / double(kWindowSamples); on_ramp(s)) at.push_back(s);
    for (double s : {band_lo - ramp, band_lo, band_hi, band_hi + ramp})
        if (s > lo && s < hi) at.push_back(s);
    for (const ExtinctionNode& n : tf.extinction) at.push_back(n.s);
    std::sort(at.begin(), at.end());
    at.erase(std::unique(at.begin(), at.end()), at.end());
    // What is left visible is a part of the box, not all of it: a compact part that holds the fraction f of the
    // voxels has chords about f^(1/3) of the box's, so its extinction is raised by f^(-1/3) to give a ray through it
    // the optical depth the mesh default gives the whole diagonal (the windowed default alone is dim).
    double visible = 0.0;
    std::size_t finite = 0;
    for (float v : values)
        if (std::isfinite(v)) {
            visible += window(double(v));
            ++finite;
        }
    const double f = std::max(kMinVisibleFraction, finite ? visible / double(finite) : 1.0);
    const double boost = std::cbrt(1.0 / f);
    std::vector<ExtinctionNode> ext;
    for (double s : at) ext.push_back({s, tf.tau_at(s) * window(s) * boost});
    tf.extinction = ext;
    // The ramp without its first, near-black node: a volume's visible voxels are mostly the values just beside the
    // background, which that node coloured almost black on black.
    tf.color = ramp_colours(lo, d, 1);
    return tf;
}

namespace {

struct ColourPreset {
    const char* paraview_name;
    const char* short_name;
    std::vector<std::array<double, 3>> rgb;  // equally spaced over the range
};

const std::vector<ColourPreset>& colour_presets()
{
    // Sampled from the colour maps as ParaView ships them (matplotlib's for the first three; Moreland's diverging map).
    static const std::vector<ColourPreset> presets = {
        {"Viridis (matplotlib)", "viridis",
         {{0.267, 0.005, 0.329}, {0.231, 0.322, 0.545}, {0.129, 0.569, 0.549}, {0.369, 0.788, 0.384},
          {0.993, 0.906, 0.144}}},
        {"Inferno (matplotlib)", "inferno",
         {{0.001, 0.000, 0.014}, {0.259, 0.039, 0.408}, {0.576, 0.149, 0.404}, {0.867, 0.318, 0.227},
          {0.988, 0.645, 0.040}, {0.988, 1.000, 0.645}}},
        {"Plasma (matplotlib)", "plasma",
         {{0.050, 0.030, 0.528}, {0.416, 0.000, 0.659}, {0.694, 0.165, 0.565}, {0.881, 0.392, 0.383},
          {0.988, 0.652, 0.211}, {0.940, 0.975, 0.131}}},
        {"Cool to Warm", "cool-to-warm", {{0.230, 0.299, 0.754}, {0.865, 0.865, 0.865}, {0.706, 0.016, 0.150}}},
        {"Grayscale", "grayscale", {{0.0, 0.0, 0.0}, {1.0, 1.0, 1.0}}},
        {"Jet", "jet",
         {{0.0, 0.0, 0.5}, {0.0, 0.0, 1.0}, {0.0, 0.5, 1.0}, {0.0, 1.0, 1.0}, {0.5, 1.0, 0.5}, {1.0, 1.0, 0.0},
          {1.0, 0.5, 0.0}, {1.0, 0.0, 0.0}, {0.5, 0.0, 0.0}}},
    };
    return presets;
}

std::string lower(std::string s)
{
    for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

}  // namespace

std::vector<std::string> colour_preset_names()
{
    std::vector<std::string> names;
    for (const ColourPreset& p : colour_presets()) names.push_back(p.paraview_name);
    return names;
}

TransferFunction with_colour_preset(TransferFunction tf, Range range, const std::string& name)
{
    const double lo = range.lo, d = range.hi > range.lo ? range.hi - range.lo : 1.0;
    for (const ColourPreset& p : colour_presets()) {
        if (lower(name) != lower(p.paraview_name) && lower(name) != p.short_name) continue;
        tf.color.clear();
        const std::size_t n = p.rgb.size();
        for (std::size_t i = 0; i < n; ++i)
            tf.color.push_back({lo + d * double(i) / double(n - 1), {p.rgb[i][0], p.rgb[i][1], p.rgb[i][2]}});
        return tf;
    }
    std::string known;
    for (const ColourPreset& p : colour_presets()) known += (known.empty() ? "" : ", ") + std::string(p.short_name);
    throw InputError("", "unknown colour preset '" + name + "' (known: " + known + ", or their ParaView names)");
}

std::string transfer_function_json(const TransferFunction& tf)
{
    nlohmann::json j;
    for (const auto& n : tf.color) j["color"].push_back({n.s, n.rgb.r, n.rgb.g, n.rgb.b});
    for (const auto& n : tf.extinction) j["extinction"].push_back({n.s, n.tau});
    return j.dump(1);
}

}  // namespace uvr
