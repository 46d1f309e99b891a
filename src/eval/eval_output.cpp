#include "al/eval/output.hpp"

#include <omp.h>
#include <unistd.h>

#include "al/core/atomic_file.hpp"
#include "al/core/error.hpp"

namespace al::eval {

namespace fs = std::filesystem;

StagedOutput::StagedOutput(const fs::path& out) : out_(out) {
  const fs::path abs = fs::absolute(out).lexically_normal();
  const fs::path parent = abs.has_filename() ? abs.parent_path() : abs.parent_path().parent_path();
  const std::string name = abs.has_filename() ? abs.filename().string() : abs.parent_path().filename().string();
  EnsureDirectory(parent);
  dir_ = parent / ("." + name + ".eval-tmp-" + std::to_string(::getpid()));
  std::error_code ec;
  fs::remove_all(dir_, ec);
  EnsureDirectory(dir_);
}

StagedOutput::~StagedOutput() {
  std::error_code ec;
  if (!committed_) fs::remove_all(dir_, ec);
}

void StagedOutput::Commit() {
  EnsureDirectory(out_);
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir_)) {
    const fs::path target = out_ / entry.path().filename();
    if (fs::exists(target, ec)) fs::remove_all(target, ec);
    fs::rename(entry.path(), target, ec);
    if (ec) throw FileError(target.string(), "cannot move evaluation output into place: " + ec.message());
  }
  fs::remove_all(dir_, ec);
  committed_ = true;
}

void WritePngsParallel(const std::vector<std::pair<fs::path, Image8>>& jobs, int num_threads) {
  // Exceptions must not leave an OpenMP region: collect them per job.
  std::vector<std::string> errors(jobs.size());
  const int threads = num_threads > 0 ? num_threads : omp_get_max_threads();
#pragma omp parallel for schedule(dynamic) num_threads(threads)
  for (std::ptrdiff_t i = 0; i < std::ptrdiff_t(jobs.size()); ++i) {
    try {
      WritePng8(jobs[std::size_t(i)].first.string(), jobs[std::size_t(i)].second);
    } catch (const std::exception& e) {
      errors[std::size_t(i)] = e.what();
    }
  }
  for (const auto& e : errors)
    if (!e.empty()) throw Error(e);
}

std::string SafeName(std::string name) {
  for (char& ch : name)
    if (ch == '/' || ch == '\\' || ch == ':') ch = '_';
  return name.empty() ? "view" : name;
}

}  // namespace al::eval
