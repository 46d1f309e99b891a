// Mask inputs of the metrics (METRICS.md §1, §3; SPEC §3): PNG masks as 8-bit luma, SAM segment
// lists (dense boolean arrays or COCO RLE, compressed or not), GroundedSAM JSON. Parsers throw
// al::Error "<source>: <problem>" on malformed input and never crash.
#pragma once
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "al/metrics/mask.hpp"

namespace al::metrics {

// PNG (any bit depth / colour type) → 8-bit luma as PIL convert("L"). `lossy` as ToLuma8.
Gray8 LoadGray8Png(const std::string& path, bool* lossy = nullptr);

// COCO compressed RLE string → run lengths (6-bit characters from '0', 5 data bits each, a
// continuation bit 0x20, sign from bit 0x10 of the last character; runs after the second are
// stored as differences to the run two before).
std::vector<std::int64_t> DecodeCocoRleString(const std::string& counts, const std::string& source = "RLE");
// Run lengths (zeros first, column-major over an h × w image) → mask. Runs must sum to h·w.
Mask MaskFromRleCounts(const std::vector<std::int64_t>& counts, int height, int width,
                       const std::string& source = "RLE");
// {"size": [h, w], "counts": "string" | [ints]} → mask.
Mask MaskFromCocoRle(const nlohmann::json& rle, const std::string& source = "RLE");
// A segmentation value: dense 2-D array (rows of 0/1/bool, != 0 is true) or a COCO RLE object.
Mask MaskFromSegmentation(const nlohmann::json& value, const std::string& source = "segment");

// A SAM list: array of objects with "segmentation" (or "mask"); others ignored.
std::vector<Mask> ParseSamList(const nlohmann::json& list, const std::string& source);
// Parses a whole SAM JSON text: either a list (one image) or, legacy merged.json,
// {image_name: [segments]}; the map is keyed by file-name stem ("" for a plain list).
std::map<std::string, std::vector<Mask>> ParseSamJsonText(const std::string& text, const std::string& source);
std::map<std::string, std::vector<Mask>> LoadSamJson(const std::string& path);

// GroundedSAM JSON: {"annotations": [{"class_name", "segmentation": RLE}...], "img_width",
// "img_height"}: the union of the instances of `class_name` (case-insensitive, surrounding spaces and
// a trailing '.' ignored; empty = every instance) as a 0/255 image.
struct GroundedSamMask {
  Gray8 mask;
  std::size_t instances = 0, annotations = 0;
};
GroundedSamMask ParseGroundedSamText(const std::string& text, const std::string& class_name, const std::string& source);
GroundedSamMask LoadGroundedSamJson(const std::string& path, const std::string& class_name);

// File-name stem ("a/b/X.png" → "X").
std::string FileStem(const std::string& path);

}  // namespace al::metrics
