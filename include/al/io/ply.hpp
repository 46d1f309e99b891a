// 3DGS PLY reading and writing (RASTERIZER.md §10.1, FORMATS.md §2.1).
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "al/scene/scene.hpp"

namespace al {

struct PlyReadOptions {
  // Feature columns: "auto" finds the first present of semantic_, obj_dc_, f_semantic_, feat_;
  // "none" loads no features; an explicit prefix such as "obj_dc_" must be present; a list
  // "obj_dc_,auto" takes the first present (none present: no features, the caller decides).
  std::string feature_prefix = "auto";
  // Require the columns a renderer needs (opacity, rot_*, f_dc_*); refinement needs only x y z scale_*.
  bool require_render_columns = false;
  // Require scale_0..2 (false only for subset PLYs used for matching, which need just x y z).
  bool require_scales = true;
  // Decode f_rest_* into Scene::sh. false (refine, which never renders): they are only checked,
  // Scene::nonfinite_undecoded flags the rows with a non-finite one, and the scene holds f_dc
  // alone (sh_degree 0) — at 3M Gaussians of SH degree 3 that is 540 MB fewer.
  bool sh_rest = true;
  // Decode rot_* into Scene::rotations. false: checked the same way, the scene's rotations stay
  // empty (has_rotations still says the file has them).
  bool rotations = true;
  // Decode f_dc_* into Scene::sh. false (refine with the scene's own feature columns; only with
  // sh_rest false): checked the same way and Scene::sh stays empty (has_f_dc still says the file
  // has them), 36 MB fewer at 3M. A file without feature columns decodes them regardless: the
  // colour fallback reads them.
  bool f_dc = true;
};

// Reads a PLY (ascii, binary LE/BE, any scalar type, properties by name). Memory-mapped, one pass.
// Throws al::Error naming the file on truncated/corrupt/inconsistent input.
Scene ReadPly(const std::string& path, const PlyReadOptions& options = {});

// Reads an antimatter15 .splat file (32-byte records; SH degree 0). Converted to raw values:
// log_scales = log(scale), opacity logit from a/255 (clamped away from 0 and 1), f_dc from rgb.
Scene ReadSplat(const std::string& path);

// In-memory variants (fuzzing, tests): `name` is used in error messages and as source_path.
Scene ReadPlyFromMemory(const void* data, std::size_t size, const std::string& name,
                        const PlyReadOptions& options = {});
Scene ReadSplatFromMemory(const void* data, std::size_t size, const std::string& name);

// By extension: .ply or .splat.
Scene ReadScene(const std::string& path, const PlyReadOptions& options = {});

// Writes the vertices with keep[i] == true. With scene.ply present: the source header (vertex
// count rewritten) and each kept record copied byte for byte, all properties kept.
// Without it (a generated or .splat scene): a standard binary little-endian INRIA layout with
// features as <prefix><d> (prefix "semantic_" if scene.feature_prefix is empty).
// keep empty = keep everything. Written atomically.
void WritePly(const std::string& path, const Scene& scene, const std::vector<bool>& keep = {});

// One warning per column group a renderer needs that the file lacks, naming the missing
// properties and the default used instead (opacity logit 0 = 50 %, identity rotation, grey f_dc,
// unit scales). Render and eval report these; refine needs none of them.
std::vector<std::string> MissingRenderColumns(const Scene& scene);

// Counts of non-finite values per standard column group (reported by `info`, excluded later).
struct NonFiniteCounts {
  std::size_t means = 0, scales = 0, rotations = 0, opacities = 0, sh = 0, features = 0;
  std::size_t gaussians_with_any = 0;  // Gaussians with at least one non-finite standard value
};
NonFiniteCounts CountNonFinite(const Scene& scene);

// true for Gaussians whose standard parameters (means, scales, rotations, opacity, SH) are all finite.
std::vector<bool> FiniteMask(const Scene& scene);

// What `al-refine info` reports about a scene (finite values only in the statistics).
struct SceneSummary {
  std::size_t num_gaussians = 0;
  int sh_degree = 0;
  std::size_t feature_dim = 0;
  std::string feature_prefix;
  std::string source_format;
  float bbox_min[3] = {0, 0, 0}, bbox_max[3] = {0, 0, 0};  // over finite means
  // min / median / max / mean of max_k exp(scale_k) and of sigmoid(opacity), finite rows only.
  double scale_min = 0, scale_median = 0, scale_max = 0, scale_mean = 0;
  double opacity_min = 0, opacity_median = 0, opacity_max = 0, opacity_mean = 0;
  NonFiniteCounts nonfinite;
};
SceneSummary SummarizeScene(const Scene& scene);
nlohmann::json SummaryToJson(const SceneSummary& summary);
std::string SummaryToText(const SceneSummary& summary);  // several human-readable lines

}  // namespace al
