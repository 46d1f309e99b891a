// Binary masks and 8-bit grey images for the evaluator's metrics (METRICS.md §1).
// Pure in-memory types: the evaluator calls the metrics on its own renders, the `metrics`
// subcommand on PNGs read from disk.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "al/io/image.hpp"

namespace al::metrics {

// Single-channel 8-bit image, row-major, row 0 = top.
struct Gray8 {
  int width = 0, height = 0;
  std::vector<std::uint8_t> pixels;  // height * width
};

// Binary mask, row-major, values 0 or 1.
struct Mask {
  int width = 0, height = 0;
  std::vector<std::uint8_t> bits;  // height * width
  std::size_t Count() const;
};

Mask EmptyMask(int width, int height);

// Nearest-neighbour rules of METRICS.md §1: kFloor = floor(d·in/out) (torch `nearest`, OpenCV
// INTER_NEAREST); kExact = min(floor((d + 0.5)·in/out), in − 1) (torch `nearest-exact`).
enum class ResizeRule { kFloor, kExact };
std::vector<int> NearestSourceIndex(int in, int out, ResizeRule rule);
Gray8 Resize(const Gray8& image, int width, int height, ResizeRule rule);
Mask Resize(const Mask& mask, int width, int height, ResizeRule rule);

// mask = value > threshold (semantic/depth use 0, sim_SAM's object mask 128).
Mask Binarize(const Gray8& image, std::uint8_t threshold);

// PIL `convert("L")` of a decoded PNG: 16-bit grey clipped to 255, 16-bit colour reduced to its high
// byte, 1/2/4-bit grey scaled to 0..255, colour to luma (R·19595 + G·38470 + B·7471 + 2^15) >> 16,
// alpha ignored. `lossy` (optional) is set when the conversion changed a value (clipping/reduction).
Gray8 ToLuma8(const PngData& png, bool* lossy = nullptr);

// Pixel counts of two same-size masks.
struct Overlap {
  std::int64_t a = 0, b = 0, intersection = 0, union_ = 0;
};
Overlap CountOverlap(const Mask& a, const Mask& b);  // throws al::Error on size mismatch

// IoU = |A ∩ B| / |A ∪ B|, 0 when the union is empty.
double IoU(const Mask& a, const Mask& b);
// acc_in(O, P) = |O ∩ P| / |O|, 0 when O is empty.
double AccIn(const Mask& object, const Mask& predicted);

}  // namespace al::metrics
