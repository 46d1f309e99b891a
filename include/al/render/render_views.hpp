// `al-refine render` as a library call: load a scene, cameras and an optional removed set, render
// the selected views and write RGB / alpha / 16-bit depth / depth preview PNGs (and float .npy)
// per view, plus report.json, as one output set (al/core/output_set.hpp).
#pragma once
#include <cstddef>
#include <string>

#include <nlohmann/json.hpp>

#include "al/io/masks.hpp"
#include "al/render/render.hpp"

namespace al {

struct RenderViewsOptions {
  std::string scene, cameras, removed;  // scene and cameras required
  RemovedIs removed_is = RemovedIs::kRemoved;
  std::string views = "all";            // comma-separated names or "all"
  int width = 0, height = 0;            // > 0: render size, keeping the field of view
  bool npy = false;                     // also float32 rgb/depth/alpha and int32 radii .npy
  RenderOptions render;                 // background, SH degree, threads
  std::string out_dir;                  // required
  bool progress = true;
  nlohmann::json params = nlohmann::json::object();  // the caller's flags, echoed in report.json
  void Check() const;  // scene, cameras and out_dir given; width, height >= 0; the render options
};

struct RenderViewsResult {
  std::size_t views = 0, num_removed = 0;
  nlohmann::json report;  // as written
};

RenderViewsResult RenderViewsToFolder(const RenderViewsOptions& options);

// Bytes one render of a scene of `gaussians` at width x height holds at its peak (output images,
// per-Gaussian projection and tile lists, encoded PNGs): what --max-memory is checked against.
double EstimateRenderBytes(std::size_t gaussians, int width, int height, int feature_channels = 0);

}  // namespace al
