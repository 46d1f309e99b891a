// How the evaluator writes: outputs go to a hidden staging folder beside the output folder and are
// moved in only when the whole run succeeded (a failure in view 37 leaves nothing half-written),
// and the many small PNGs of a view are encoded in parallel (compression dominates the I/O time).
#pragma once
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "al/io/image.hpp"

namespace al::eval {

class StagedOutput {
 public:
  // Creates "<parent of out>/.<name of out>.eval-tmp-<pid>" (emptied first).
  explicit StagedOutput(const std::filesystem::path& out);
  ~StagedOutput();  // removes the staging folder unless committed
  StagedOutput(const StagedOutput&) = delete;
  StagedOutput& operator=(const StagedOutput&) = delete;
  const std::filesystem::path& dir() const { return dir_; }
  // Moves every top-level entry into out (replacing same-named entries), then drops the staging.
  void Commit();

 private:
  std::filesystem::path out_, dir_;
  bool committed_ = false;
};

// Writes the PNGs on `num_threads` threads (0 = OpenMP default); the first error in job order is
// rethrown as al::Error after all jobs ran.
void WritePngsParallel(const std::vector<std::pair<std::filesystem::path, Image8>>& jobs, int num_threads);

// File-name-safe view name (camera names may hold path separators).
std::string SafeName(std::string name);

}  // namespace al::eval
