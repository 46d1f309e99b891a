// FeaturePrior (al/graph/prior.hpp). Sums run sequentially in node order, so the result does not
// depend on the thread count.
#include "al/graph/prior.hpp"

#include <algorithm>
#include <cmath>

#include "al/core/error.hpp"

namespace al {
namespace {

double MedianOf(std::vector<double> v) {
  if (v.empty()) return 0.0;
  const std::size_t h = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + h, v.end());
  if (v.size() % 2) return v[h];
  return 0.5 * (v[h] + *std::max_element(v.begin(), v.begin() + h));
}

// The separating direction: mean of the removed rows minus (optionally) the mean of the kept ones.
Eigen::VectorXd Direction(const RowMatXf& f, const std::vector<double>& mask, bool contrast) {
  const Eigen::Index D = f.cols();
  Eigen::VectorXd in = Eigen::VectorXd::Zero(D), out = Eigen::VectorXd::Zero(D);
  std::size_t n_in = 0, n_out = 0;
  for (Eigen::Index v = 0; v < f.rows(); ++v) {
    const bool removed = mask[std::size_t(v)] >= 0.5;
    (removed ? in : out) += f.row(v).transpose().cast<double>();
    ++(removed ? n_in : n_out);
  }
  Eigen::VectorXd p = in / double(std::max<std::size_t>(n_in, 1));
  if (contrast) p -= out / double(std::max<std::size_t>(n_out, 1));
  const double norm = p.norm();
  return norm > 0 ? Eigen::VectorXd(p / norm) : Eigen::VectorXd::Zero(D);
}

// Two 1-D Gaussians fitted to c over the candidates by EM, started from the mask (removed = the
// high component); q = posterior of the high one. Sequential sums: deterministic.
void Mixture2(const std::vector<double>& c, const std::vector<std::uint8_t>& has, const std::vector<double>& mask,
              std::vector<double>& q, PriorStats& st) {
  const std::size_t V = c.size();
  for (std::size_t v = 0; v < V; ++v) q[v] = mask[v] >= 0.5 ? 1.0 : 0.0;
  double mu[2] = {0, 0}, var[2] = {1, 1}, pi1 = 0.5;
  for (int it = 0; it < 100; ++it) {
    double w[2] = {0, 0}, s1[2] = {0, 0}, s2[2] = {0, 0};
    for (std::size_t v = 0; v < V; ++v) {
      if (!has[v]) continue;
      const double r[2] = {1.0 - q[v], q[v]};
      for (int k = 0; k < 2; ++k) w[k] += r[k], s1[k] += r[k] * c[v], s2[k] += r[k] * c[v] * c[v];
    }
    if (w[0] <= 0 || w[1] <= 0) break;
    double change = 0;
    for (int k = 0; k < 2; ++k) {
      const double m = s1[k] / w[k];
      change = std::max(change, std::abs(m - mu[k]));
      mu[k] = m;
      var[k] = std::max(s2[k] / w[k] - m * m, 1e-6);
    }
    pi1 = std::clamp(w[1] / (w[0] + w[1]), 1e-9, 1.0 - 1e-9);
    for (std::size_t v = 0; v < V; ++v) {
      if (!has[v]) continue;
      double l[2];
      for (int k = 0; k < 2; ++k)
        l[k] = -0.5 * (c[v] - mu[k]) * (c[v] - mu[k]) / var[k] - 0.5 * std::log(var[k]);
      const double a = std::log(pi1) + l[1] - std::log(1.0 - pi1) - l[0];
      q[v] = 1.0 / (1.0 + std::exp(-std::clamp(a, -50.0, 50.0)));
    }
    if (it > 0 && change < 1e-7) break;
  }
  // High component must be the removed-like one; otherwise there is no usable signal.
  if (mu[1] <= mu[0])
    for (std::size_t v = 0; v < V; ++v) q[v] = mask[v] >= 0.5 ? 1.0 : 0.0;
  st.lo = mu[0];
  st.hi = mu[1];
}

}  // namespace

void PriorOptions::Check() const {
  if (!(weight >= 0.0 && weight <= 1.0)) throw Error("--prior-weight must be in [0, 1]", ExitCode::kUsage);
  if (!(width > full) || !std::isfinite(width) || !(full >= 0.0))
    throw Error("--prior-width must be > --prior-full >= 0", ExitCode::kUsage);
}

std::vector<double> FeaturePrior(const RowMatXf& f, const std::vector<double>& mask, const PriorOptions& o,
                                 PriorStats* stats) {
  o.Check();
  const std::size_t V = mask.size();
  if (f.rows() != Eigen::Index(V)) throw Error("prior: feature rows do not match the nodes", ExitCode::kInternal);
  std::vector<double> y(mask);
  PriorStats st;
  st.weight = o.weight;
  const std::size_t n_removed = std::count_if(mask.begin(), mask.end(), [](double m) { return m >= 0.5; });
  if (o.weight == 0.0 || n_removed == 0 || n_removed == V) {
    if (stats) *stats = st;
    return y;
  }
  const Eigen::VectorXd p = Direction(f, mask, o.contrast);
  std::vector<double> c(V), c_removed;
  std::vector<std::uint8_t> has(V);
  for (std::size_t v = 0; v < V; ++v) {
    has[v] = f.row(Eigen::Index(v)).squaredNorm() > 0.0f;
    c[v] = f.row(Eigen::Index(v)).cast<double>().dot(p);
    if (has[v] && mask[v] >= 0.5) c_removed.push_back(c[v]);
  }
  st.median_removed = MedianOf(c_removed);
  for (double& x : c_removed) x = std::abs(x - st.median_removed);
  st.sigma_removed = 1.4826 * MedianOf(std::move(c_removed));
  std::vector<double> q(V, 0.0);
  if (o.mixture) {
    Mixture2(c, has, mask, q, st);
  } else {
    st.hi = st.median_removed - o.full * std::max(st.sigma_removed, 1e-9);
    st.lo = st.median_removed - o.width * std::max(st.sigma_removed, 1e-9);
    for (std::size_t v = 0; v < V; ++v) q[v] = std::clamp((c[v] - st.lo) / (st.hi - st.lo), 0.0, 1.0);
  }
  for (std::size_t v = 0; v < V; ++v) {
    if (!has[v]) continue;
    y[v] = (1.0 - o.weight) * mask[v] + o.weight * q[v];
    st.removed_unlike += mask[v] >= 0.5 && q[v] < 0.5;
    st.kept_like += mask[v] < 0.5 && q[v] > 0.5;
  }
  if (stats) *stats = st;
  return y;
}

nlohmann::json PriorStats::ToJson() const {
  return {{"weight", weight}, {"median_removed", median_removed}, {"sigma_removed", sigma_removed},
          {"q0_at", lo}, {"q1_at", hi}, {"removed_unlike", removed_unlike}, {"kept_like", kept_like}};
}

}  // namespace al
