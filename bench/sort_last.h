// Sort-last rendering in one process (docs/distributed.md, "Sort-last HAVS and VICP"): the mesh split into parts
// (reference/partition.h), each part rendered on its own by HAVS or VICP with the whole scene's camera and transfer
// function, and the parts' images blended back to front in the order of their boxes, as ParaView blends the images of
// its processes. uvr render --parts N; uvr budget's `partition` factor.
#pragma once

#include <cstdint>
#include <vector>

#include "bench/algorithms.h"
#include "reference/mesh.h"

namespace uvr::cli {

// The parts' order, back to front, for `camera`. The boxes are split recursively at an axis-aligned plane that
// separates them (recursive coordinate bisection's planes separate its parts' boxes), the side away from the eye
// first (orthographic: the side the view direction points to). Boxes that no plane separates (METIS's parts) are
// ordered by their centres' depth along the view direction, farthest first, and `separated` is set false: no order of
// such boxes is a visibility order in general.
std::vector<uint32_t> back_to_front(const std::vector<Bounds>& boxes, const Camera& camera, bool& separated);

// The box of a part's cell centroids (the region recursive coordinate bisection put the part's cells in).
Bounds centroid_box(const TetMesh& part);

// The scene of one part: its cells with the whole scene's field, transfer function, camera and size, and the whole's
// extent (SceneExtent: its tables span the whole's range and longest edge).
Scene part_scene(const Scene& s, TetMesh part);

// Images (premultiplied RGBA) blended in `order`, back to front (each over what is behind it), in double and rounded
// to float once.
Image blend_back_to_front(const std::vector<Image>& images, const std::vector<uint32_t>& order);

// The parts' stats as one frame's: numbers add up ("max_..." take the largest, "..._per_tet" the mean over the parts'
// "cells", "k" is a setting), a null anywhere is null, strings and booleans are part 0's (every part's settings).
nlohmann::json merge_part_stats(const std::vector<nlohmann::json>& parts);

// `algo` (havs or vicp) on o.parts parts of s's mesh made by o.partition, blended. stats: the parts' merged
// (merge_part_stats), with "sort_last": {parts, partition, order, separated, part_ms, part_stats: every part's stats};
// the diagnostic images summed over the parts (max_held: the largest).
AlgoResult render_sort_last(const Scene& s, const std::string& algo, const AlgoOptions& o);

}  // namespace uvr::cli
