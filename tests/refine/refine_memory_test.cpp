// RunRefine from memory (RefineData, the Python module's path) and from files give the same
// refinement: one code path after loading. Float32 features are read in place.
#include <unistd.h>

#include <filesystem>
#include <memory>

#include <gtest/gtest.h>

#include "al/core/error.hpp"
#include "al/fixtures/synth.hpp"
#include "al/refine/refine.hpp"

namespace al {
namespace {

namespace fs = std::filesystem;

NpyArray View(const void* data, const char* descr, std::size_t item, std::vector<std::int64_t> shape) {
  NpyArray a;
  a.descr = descr;
  a.item_size = item;
  a.shape = std::move(shape);
  a.data = static_cast<const std::uint8_t*>(data);
  return a;
}

TEST(RefineMemory, SameMaskAsFromFiles) {
  fixtures::SynthOptions so;
  so.num_gaussians = 12000;
  so.seed = 5;
  so.num_views = 1;
  so.width = 32;
  so.height = 24;
  so.compute_masks = false;
  fixtures::SynthScene synth = fixtures::Synthesize(so);
  const fs::path dir = fs::temp_directory_path() / ("al_refine_memory_" + std::to_string(::getpid()));
  fixtures::WriteSynthScene(synth, dir.string(), false);

  RefineOptions o;
  o.method = "fgs";
  o.solver = "bk";
  o.scene = (dir / "scene.ply").string();
  o.removed = (dir / "removed_fgs.npy").string();
  o.out_dir = (dir / "out").string();
  const RefineResult from_files = RunRefine(o);

  const std::vector<bool>& removed = synth.removed.at("fgs");
  std::vector<std::uint8_t> mask(removed.begin(), removed.end());
  RowMatXf features = synth.scene.features;  // the caller's buffer
  RefineData d;
  d.scene = std::make_shared<Scene>(std::move(synth.scene));
  d.removed = View(mask.data(), "u1", 1, {std::int64_t(mask.size())});
  d.features = View(features.data(), "f4", 4, {features.rows(), features.cols()});
  RefineOptions mo;
  mo.method = "fgs";
  mo.solver = "bk";
  const RefineResult from_memory = RunRefine(d, mo);
  EXPECT_EQ(from_memory.refined, from_files.refined);
  EXPECT_FALSE(from_memory.added.empty());
  EXPECT_EQ(from_memory.report["counts"], from_files.report["counts"]);

  // In place: zeroing the caller's features leaves no semantic edge.
  features.setZero();
  EXPECT_EQ(RunRefine(d, mo).status, "empty_graph");
  // A mask of the wrong length is bad input, named.
  mask.resize(10);
  d.removed = View(mask.data(), "u1", 1, {10});
  try {
    RunRefine(d, mo);
    ADD_FAILURE() << "expected an error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ExitCode::kBadInput);
    EXPECT_NE(std::string(e.what()).find("mask length 10"), std::string::npos);
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace al
