// The sub-commands of `uvr`, one file each (cmd_<name>.cpp). Each registers itself on the application; its callback
// throws InputError for bad input, which main() turns into a message and exit code.
#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "bench/algorithms.h"
#include "bench/options.h"

namespace uvr::cli {

void register_info(CLI::App& app);
void register_demo(CLI::App& app);
void register_render(CLI::App& app);
void register_bench(CLI::App& app);
void register_export(CLI::App& app);
void register_compare(CLI::App& app);
void register_sweep(CLI::App& app);
void register_budget(CLI::App& app);
void register_partition(CLI::App& app);
void register_verify(CLI::App& app);
void register_gpu_check(CLI::App& app);

// compare's work, which demo shares: the reference and `algos` on scene `s` (and `images`, made elsewhere, each
// under its label) measured against the reference, written to `dir` (images, error maps, metrics.json, index.html).
// Everything is checked before anything is written. Returns metrics.json's object.
struct LabelledImage {
    std::string path, label;
};
nlohmann::json run_compare(const Scene& s, const std::vector<std::string>& algos, const AlgoOptions& o,
                           const std::string& dir, const std::string& mesh_name,
                           const std::vector<LabelledImage>& images = {});

// uvr bench's timing of one configuration, which the GPU check shares: builds the renderer (build_ms), renders
// `warmup` + `repeat` frames, and keeps each timed frame's wall time and stage times. The row holds the last frame's
// statistics, the median frame ("frame_ms") and stages ("stages"), and the algorithm's rates; `last_image`, where
// given, receives the last frame's image.
nlohmann::json time_frames(const Scene& s, const Algorithm& algo, const AlgoOptions& o, int warmup, int repeat,
                           Image* last_image = nullptr);

}  // namespace uvr::cli
