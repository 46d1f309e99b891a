// FGS derived removal mask and decoder (see al/refine/fgs_mask.hpp).
#include <algorithm>
#include <cmath>
#include <limits>

#include "al/core/error.hpp"
#include "al/core/option_table.hpp"
#include "al/io/npy.hpp"
#include "al/refine/fgs_mask.hpp"

namespace al {

RowMatXf ReadMatrixNpy(const std::string& path) {
  const NpyArray a = ReadNpy(path);
  if (!a.is_float()) throw Error(path + ": expected a float array, got dtype " + a.descr, ExitCode::kBadInput);
  if (a.shape.size() != 2 || a.shape[0] <= 0 || a.shape[1] <= 0)
    throw Error(path + ": expected a 2-D (rows, columns) array", ExitCode::kBadInput);
  const std::vector<float> v = a.ToFloat();
  RowMatXf m(a.shape[0], a.shape[1]);
  std::copy(v.begin(), v.end(), m.data());
  return m;
}

RowMatXf ApplyDecoder(Eigen::Ref<const RowMatXf> features, const std::string& weight_npy, const std::string& bias_npy) {
  const NpyArray w = ReadNpy(weight_npy);
  if (!w.is_float()) throw Error(weight_npy + ": decoder weight must be float", ExitCode::kBadInput);
  const bool conv = w.shape.size() == 4 && w.shape[2] == 1 && w.shape[3] == 1;
  if (!(w.shape.size() == 2 || conv))
    throw Error(weight_npy + ": decoder weight must have shape (D', D) or (D', D, 1, 1)", ExitCode::kBadInput);
  const std::int64_t out_dim = w.shape[0], in_dim = w.shape[1];
  if (in_dim != features.cols())
    throw Error(weight_npy + ": decoder expects D = " + std::to_string(in_dim) + ", features have " +
                std::to_string(features.cols()), ExitCode::kBadInput);
  const NpyArray b = ReadNpy(bias_npy);
  if (!b.is_float() || b.shape.size() != 1 || b.shape[0] != out_dim)
    throw Error(bias_npy + ": decoder bias must be float with shape (" + std::to_string(out_dim) + ",)",
                ExitCode::kBadInput);
  const std::vector<float> wv = w.ToFloat(), bv = b.ToFloat();
  const Eigen::Map<const RowMatXf> W(wv.data(), out_dim, in_dim);
  const Eigen::Map<const Eigen::RowVectorXf> B(bv.data(), out_dim);
  RowMatXf out = features * W.transpose();
  out.rowwise() += B;
  return out;
}

void FgsMaskOptions::Check() const {
  if (positives.empty()) throw Error("--positive: at least one prompt row is required", ExitCode::kUsage);
  for (int p : positives) CheckOptionRange("fgs", "positive", p, NumericRange::AtLeast(0), "prompt rows naming the object");
  CheckOptionRange("fgs", "threshold", threshold, NumericRange::Closed(0, 1),
                   "FGS deletion threshold on the positives' summed softmax probability");
}

FgsMaskResult FgsDerivedMask(Eigen::Ref<const RowMatXf> features, const RowMatXf& prompts, const FgsMaskOptions& options) {
  options.Check();
  const auto T = prompts.rows();
  if (T < 1) throw Error("--prompt-embeddings: no prompts", ExitCode::kBadInput);
  if (prompts.cols() != features.cols())
    throw Error("--prompt-embeddings: prompt dimension " + std::to_string(prompts.cols()) +
                " != feature dimension " + std::to_string(features.cols()) +
                " (FGS speed-up models need --decoder W.npy,b.npy)", ExitCode::kBadInput);
  if (options.positives.empty()) throw Error("--positive: at least one prompt row is required", ExitCode::kUsage);
  std::vector<std::uint8_t> is_pos(T, 0);
  for (int p : options.positives) {
    if (p < 0 || p >= T)
      throw Error("--positive: row " + std::to_string(p) + " out of range [0, " + std::to_string(T) + ")",
                  ExitCode::kUsage);
    is_pos[p] = 1;
  }
  const std::size_t N = static_cast<std::size_t>(features.rows());
  FgsMaskResult r;
  r.removed.assign(N, false);
  std::vector<std::uint8_t> removed(N, 0), argmax_pos(N, 0), near(N, 0), zero(N, 0);
  const Eigen::MatrixXd Pm = prompts.cast<double>();
  const auto n = static_cast<std::int64_t>(N);
#pragma omp parallel for schedule(static)
  for (std::int64_t i = 0; i < n; ++i) {
    const Eigen::VectorXd f = features.row(i).cast<double>().transpose();
    const double nrm = f.norm();
    if (!(nrm > 0) || !std::isfinite(nrm)) {
      zero[i] = 1;
      continue;
    }
    const Eigen::VectorXd s = Pm * (f / nrm);
    Eigen::Index best = 0;
    for (Eigen::Index k = 1; k < T; ++k)
      if (s[k] > s[best]) best = k;  // first maximum on ties
    const double mx = s[best];
    double z = 0, pos = 0;
    for (Eigen::Index k = 0; k < T; ++k) {
      const double e = std::exp(s[k] - mx);
      z += e;
      if (is_pos[k]) pos += e;
    }
    const double share = pos / z;
    argmax_pos[i] = is_pos[best];
    removed[i] = is_pos[best] || share >= options.threshold;
    near[i] = std::abs(share - options.threshold) <= 1e-3;
  }
  for (std::size_t i = 0; i < N; ++i) {
    r.removed[i] = removed[i];
    r.num_removed += removed[i];
    r.by_argmax += argmax_pos[i];
    r.by_threshold_only += removed[i] && !argmax_pos[i];
    r.near_threshold += near[i];
    r.zero_norm += zero[i];
  }
  return r;
}

}  // namespace al
