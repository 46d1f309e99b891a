// PrepareFeatureField (al/render/feature_field.hpp): unit rows, scene-mean centring, PCA projection.
// Rows are processed in fixed chunks whose partial results are combined in chunk order, so the
// output does not depend on the thread count; the N x D unit rows are never held at once (a 1M x
// 512 scene would need 2 GB), only N x d channels.
#include "al/render/feature_field.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include <Eigen/Eigenvalues>

#include "al/core/error.hpp"
#include "al/core/timer.hpp"

namespace al {
namespace {

constexpr Eigen::Index kChunk = 2048;  // rows per work item (fixed: results do not depend on threads)

int Threads(int requested) { return requested > 0 ? requested : omp_get_max_threads(); }

// Row i divided by its norm; false (and row untouched) when the norm is zero or not finite.
bool UnitRow(const RowMatXf& f, Eigen::Index i, Eigen::VectorXd& out) {
  out = f.row(i).transpose().cast<double>();
  const double norm = out.norm();
  if (!(norm > 0) || !std::isfinite(norm)) return false;
  out /= norm;
  return true;
}

// Mean of the unit rows over the valid ones (double, chunk sums added in chunk order).
Eigen::VectorXd UnitMean(const RowMatXf& f, int threads, std::size_t& zero_norm) {
  const Eigen::Index n = f.rows(), chunks = (n + kChunk - 1) / kChunk;
  std::vector<Eigen::VectorXd> sums(static_cast<std::size_t>(chunks), Eigen::VectorXd::Zero(f.cols()));
  std::vector<std::size_t> invalid(static_cast<std::size_t>(chunks), 0);
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
  for (Eigen::Index c = 0; c < chunks; ++c) {
    Eigen::VectorXd u;
    for (Eigen::Index i = c * kChunk, e = std::min(n, i + kChunk); i < e; ++i) {
      if (UnitRow(f, i, u)) sums[std::size_t(c)] += u;
      else ++invalid[std::size_t(c)];
    }
  }
  Eigen::VectorXd total = Eigen::VectorXd::Zero(f.cols());
  zero_norm = 0;
  for (Eigen::Index c = 0; c < chunks; ++c) {
    total += sums[std::size_t(c)];
    zero_norm += invalid[std::size_t(c)];
  }
  const double valid = double(n) - double(zero_norm);
  return valid > 0 ? Eigen::VectorXd(total / valid) : total;
}

// Leading principal axes (D x d, descending variance, sign fixed so each axis's largest-magnitude
// entry is positive) of the centred unit rows sampled at evenly spaced indices.
Eigen::MatrixXd PrincipalAxes(const RowMatXf& f, const Eigen::VectorXd& mean, int d, std::size_t sample_rows,
                              double& kept) {
  const Eigen::Index n = f.rows(), D = f.cols();
  const Eigen::Index m = std::min<Eigen::Index>(n, std::max<Eigen::Index>(Eigen::Index(sample_rows), D));
  Eigen::MatrixXd X = Eigen::MatrixXd::Zero(m, D);
  Eigen::VectorXd u;
  for (Eigen::Index k = 0; k < m; ++k) {
    const Eigen::Index i = static_cast<Eigen::Index>((static_cast<double>(k) * double(n)) / double(m));
    if (UnitRow(f, i, u)) X.row(k) = (u - mean).transpose();
  }
  const Eigen::MatrixXd cov = (X.transpose() * X) / double(m);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(cov);
  const Eigen::VectorXd values = eig.eigenvalues().reverse();  // descending
  Eigen::MatrixXd axes = eig.eigenvectors().rowwise().reverse().leftCols(d);
  for (Eigen::Index j = 0; j < d; ++j) {
    Eigen::Index at = 0;
    axes.col(j).cwiseAbs().maxCoeff(&at);
    if (axes(at, j) < 0) axes.col(j) = -axes.col(j);
  }
  const double total = values.cwiseMax(0.0).sum();
  kept = total > 0 ? values.head(d).cwiseMax(0.0).sum() / total : 1.0;
  return axes;
}

// channels = (unit rows - mean) * basis (or without the product when basis is empty); invalid rows 0.
void FillChannels(const RowMatXf& f, const Eigen::VectorXd& mean, const Eigen::MatrixXf& basis, int threads,
                  RowMatXf& out) {
  const Eigen::Index n = f.rows(), D = f.cols(), chunks = (n + kChunk - 1) / kChunk;
  const Eigen::Index d = basis.size() > 0 ? basis.cols() : D;
  out.resize(n, d);
  const Eigen::VectorXf mean_f = mean.cast<float>();
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
  for (Eigen::Index c = 0; c < chunks; ++c) {
    const Eigen::Index begin = c * kChunk, rows = std::min(n, begin + kChunk) - begin;
    RowMatXf centred(rows, D);
    Eigen::VectorXd u;
    for (Eigen::Index r = 0; r < rows; ++r) {
      if (UnitRow(f, begin + r, u)) centred.row(r) = u.cast<float>().transpose() - mean_f.transpose();
      else centred.row(r).setZero();  // no feature: exactly 0 (centring would make it -mean)
    }
    // Inside the parallel region Eigen's product runs on this thread alone; the chunk shape is
    // fixed, so each row gets the same arithmetic for any thread count.
    if (basis.size() > 0) out.middleRows(begin, rows).noalias() = centred * basis;
    else out.middleRows(begin, rows) = centred;
  }
}

}  // namespace

const OptionTable<FeatureFieldOptions>& FeatureFieldOptions::Table() {
  using O = FeatureFieldOptions;
  using R = NumericRange;
  static const auto table =
      OptionTable<O>("feature field")
          .Flag("feature_centre", &O::centre, "subtract the scene's mean unit feature before cosines")
          .Int("feature_channels", &O::max_channels, R::Closed(1, kMaxFeatureChannels),
               "rendered feature channels; wider features are projected on their principal axes")
          .Int("feature_pca_rows", &O::pca_rows, R::AtLeast(1), "rows the projection's covariance is estimated from");
  return table;
}

void FeatureFieldOptions::Check() const { Table().Check(*this); }

nlohmann::json FeatureField::ToJson() const {
  return {{"input_dim", input_dim},
          {"channels", dim()},
          {"centred", centred},
          {"projection", projected() ? "pca" : "none"},
          {"kept_variance", kept_variance},
          {"zero_norm", zero_norm},
          {"seconds", seconds}};
}

FeatureField PrepareFeatureField(const RowMatXf& features, const FeatureFieldOptions& options) {
  options.Check();
  if (features.rows() == 0 || features.cols() == 0) throw Error("feature field: the scene has no features");
  Timer timer;
  const int threads = Threads(options.num_threads);
  FeatureField field;
  field.input_dim = static_cast<int>(features.cols());
  Eigen::VectorXd mean = UnitMean(features, threads, field.zero_norm);
  if (!options.centre) mean.setZero();
  field.centred = options.centre;
  if (features.cols() > options.max_channels)
    field.basis = PrincipalAxes(features, mean, options.max_channels, std::size_t(options.pca_rows), field.kept_variance)
                      .cast<float>();
  FillChannels(features, mean, field.basis, threads, field.channels);
  field.mean = mean.cast<float>();
  field.seconds = timer.Seconds();
  return field;
}

}  // namespace al
