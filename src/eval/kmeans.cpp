#include "al/eval/kmeans.hpp"

#include <algorithm>
#include <cmath>

#include <random>

#include "al/core/error.hpp"

namespace al::eval {
namespace {

using Matrix = RowMatXf;

// Uniform in [0, 1) from the raw engine output: std::mt19937_64's sequence is fixed by the
// standard, its distributions are not (they differ between standard libraries).
double Uniform(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

// k-means++ on the distance 1 - cos: the first centre uniformly, each next one with probability
// proportional to the squared distance to the nearest chosen centre.
Matrix SeedCentres(const Matrix& unit, int k, std::uint64_t seed) {
  const Eigen::Index n = unit.rows();
  std::mt19937_64 rng(seed);
  auto below = [&](Eigen::Index m) { return static_cast<Eigen::Index>(Uniform(rng) * double(m)); };
  Matrix centres(k, unit.cols());
  centres.row(0) = unit.row(below(n));
  std::vector<double> d2(static_cast<std::size_t>(n));
  for (Eigen::Index i = 0; i < n; ++i) d2[std::size_t(i)] = std::pow(1.0 - unit.row(i).dot(centres.row(0)), 2);
  for (int c = 1; c < k; ++c) {
    double total = 0;
    for (double v : d2) total += v;
    Eigen::Index pick = 0;
    if (total > 0) {
      double r = Uniform(rng) * total;
      for (; pick < n - 1 && r >= d2[std::size_t(pick)]; ++pick) r -= d2[std::size_t(pick)];
    } else {
      pick = below(n);
    }
    centres.row(c) = unit.row(pick);
    for (Eigen::Index i = 0; i < n; ++i)
      d2[std::size_t(i)] = std::min(d2[std::size_t(i)], std::pow(1.0 - unit.row(i).dot(centres.row(c)), 2));
  }
  return centres;
}

// Assigns every point to its most similar centre (lowest index on ties); returns whether any changed.
bool Assign(const Matrix& unit, const Matrix& centres, std::vector<int>& label) {
  const Eigen::Index n = unit.rows();
  int changed = 0;
#pragma omp parallel for schedule(static) reduction(| : changed)
  for (Eigen::Index i = 0; i < n; ++i) {
    Eigen::Index best = 0;
    (centres * unit.row(i).transpose()).maxCoeff(&best);
    if (label[std::size_t(i)] != int(best)) {
      label[std::size_t(i)] = int(best);
      changed = 1;
    }
  }
  return changed != 0;
}

}  // namespace

KMeansResult SphericalKMeans(const RowMatXf& rows, int k, std::uint64_t seed, int max_iterations) {
  if (k < 1) throw Error("k-means: k must be >= 1", ExitCode::kUsage);
  std::vector<Eigen::Index> valid;
  for (Eigen::Index i = 0; i < rows.rows(); ++i) {
    const float norm = rows.row(i).norm();
    if (norm > 0 && std::isfinite(norm)) valid.push_back(i);
  }
  KMeansResult out;
  if (valid.empty()) return out;
  Matrix unit(static_cast<Eigen::Index>(valid.size()), rows.cols());
  for (std::size_t j = 0; j < valid.size(); ++j) unit.row(Eigen::Index(j)) = rows.row(valid[j]).normalized();
  k = static_cast<int>(std::min<std::size_t>(std::size_t(k), valid.size()));
  Matrix centres = SeedCentres(unit, k, seed);
  std::vector<int> label(valid.size(), -1);
  std::vector<std::size_t> sizes(std::size_t(k), 0);
  for (out.iterations = 0; out.iterations < max_iterations;) {
    const bool changed = Assign(unit, centres, label);
    ++out.iterations;
    // Sequential sums in point order: the same bits for any thread count.
    Eigen::MatrixXd sums = Eigen::MatrixXd::Zero(k, unit.cols());
    std::fill(sizes.begin(), sizes.end(), 0);
    for (std::size_t j = 0; j < label.size(); ++j) {
      sums.row(label[j]) += unit.row(Eigen::Index(j)).cast<double>();
      ++sizes[std::size_t(label[j])];
    }
    for (int c = 0; c < k; ++c)
      if (sizes[std::size_t(c)] > 0 && sums.row(c).norm() > 0) centres.row(c) = sums.row(c).normalized().cast<float>();
    if (!changed) break;
  }
  for (int c = 0; c < k; ++c) {
    if (sizes[std::size_t(c)] == 0) continue;
    out.centroids.conservativeResize(out.centroids.rows() + 1, unit.cols());
    out.centroids.row(out.centroids.rows() - 1) = centres.row(c);
    out.sizes.push_back(sizes[std::size_t(c)]);
  }
  return out;
}

}  // namespace al::eval
