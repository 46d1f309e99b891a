// FeaturePrior (al/graph/prior.hpp). Every sum runs sequentially in node order, so the result does
// not depend on the thread count.
#include "al/graph/prior.hpp"

#include <algorithm>
#include <cmath>

#include "al/core/error.hpp"

namespace al {
namespace {

// Where the kept candidates' credit ramps, in robust standard deviations below the removed median
// (chosen on the tuning half of the accuracy bench, docs/accuracy.md).
constexpr double kCreditFull = 0.0, kCreditZero = 2.0;
// A removed Gaussian is doubted only when the method kept a clear majority (two thirds) of its
// group: at a bare majority, object parts whose features lean toward a neighbour (CLIP-like
// fields, D = 512) were given back (docs/refine.md). The doubt fades out linearly between a
// removal rate of 1/3 and 0.4 (and a kept Gaussian's credit fades in between 0.45 and 1/2): a
// hard step made two nearly equal graphs (bk and cp after different growth rounds, rates 0.334
// and 0.326) restore 25 or 225 Gaussians.
constexpr double kDoubtRemovedFull = 1.0 / 3.0, kDoubtRemovedZero = 0.4;
constexpr double kDoubtKeptZero = 0.45, kDoubtKeptFull = 0.5;

// 1 at `full`, 0 at `zero`, linear between (either order).
double Ramp(double x, double zero, double full) { return std::clamp((x - zero) / (full - zero), 0.0, 1.0); }

double MedianOf(std::vector<double> v) {
  if (v.empty()) return 0.0;
  const std::size_t h = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + h, v.end());
  if (v.size() % 2) return v[h];
  return 0.5 * (v[h] + *std::max_element(v.begin(), v.begin() + h));
}

// Projections on unit(mean_R − mean_kept); zero rows have none (has = 0).
std::vector<double> Project(const RowMatXf& f, const std::vector<double>& mask, std::vector<std::uint8_t>& has) {
  const Eigen::Index D = f.cols(), V = f.rows();
  Eigen::VectorXd in = Eigen::VectorXd::Zero(D), out = Eigen::VectorXd::Zero(D);
  double n_in = 0, n_out = 0;
  has.assign(std::size_t(V), 0);
  for (Eigen::Index v = 0; v < V; ++v) {
    has[std::size_t(v)] = f.row(v).squaredNorm() > 0.0f;
    if (!has[std::size_t(v)]) continue;
    const bool removed = mask[std::size_t(v)] >= 0.5;
    (removed ? in : out) += f.row(v).transpose().cast<double>();
    (removed ? n_in : n_out) += 1;
  }
  Eigen::VectorXd p = in / std::max(n_in, 1.0) - out / std::max(n_out, 1.0);
  if (p.norm() > 0) p.normalize();
  std::vector<double> c(std::size_t(V), 0.0);
  for (Eigen::Index v = 0; v < V; ++v) c[std::size_t(v)] = f.row(v).cast<double>().dot(p);
  return c;
}

// Two 1-D Gaussians fitted to c by EM, started from the mask (removed = upper group). Returns the
// posterior of the upper group per row.
std::vector<double> UpperPosterior(const std::vector<double>& c, const std::vector<std::uint8_t>& has,
                                   const std::vector<double>& mask, PriorStats& st) {
  const std::size_t V = c.size();
  std::vector<double> q(V);
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
    const double log_odds_prior = std::log(pi1) - std::log(1.0 - pi1);
    for (std::size_t v = 0; v < V; ++v) {
      if (!has[v]) continue;
      double l[2];
      for (int k = 0; k < 2; ++k) l[k] = -0.5 * (c[v] - mu[k]) * (c[v] - mu[k]) / var[k] - 0.5 * std::log(var[k]);
      q[v] = 1.0 / (1.0 + std::exp(-std::clamp(log_odds_prior + l[1] - l[0], -50.0, 50.0)));
    }
    if (it > 0 && change < 1e-7) break;
  }
  st.mean_lower = mu[0], st.mean_upper = mu[1];
  st.sd_lower = std::sqrt(var[0]), st.sd_upper = std::sqrt(var[1]);
  double rem[2] = {0, 0}, all[2] = {0, 0};
  for (std::size_t v = 0; v < V; ++v) {
    if (!has[v]) continue;
    const double r[2] = {1.0 - q[v], q[v]};
    for (int k = 0; k < 2; ++k) all[k] += r[k], rem[k] += mask[v] >= 0.5 ? r[k] : 0.0;
  }
  st.removal_rate_lower = all[0] > 0 ? rem[0] / all[0] : 0.0;
  st.removal_rate_upper = all[1] > 0 ? rem[1] / all[1] : 0.0;
  return q;
}

}  // namespace

void PriorOptions::Check() const {
  if (!(weight >= 0.0 && weight <= 1.0)) throw Error("--prior-weight must be in [0, 1]", ExitCode::kUsage);
}

std::vector<double> FeaturePrior(const RowMatXf& f, const std::vector<double>& mask, const PriorOptions& o,
                                 PriorStats* stats) {
  o.Check();
  const std::size_t V = mask.size();
  if (f.rows() != Eigen::Index(V)) throw Error("prior: feature rows do not match the nodes", ExitCode::kInternal);
  std::vector<double> y(mask);
  PriorStats st;
  st.weight = o.weight;
  const auto n_removed = std::size_t(std::count_if(mask.begin(), mask.end(), [](double m) { return m >= 0.5; }));
  if (o.weight == 0.0 || n_removed == 0 || n_removed == V) {
    if (stats) *stats = st;
    return y;
  }
  std::vector<std::uint8_t> has;
  const std::vector<double> c = Project(f, mask, has);
  std::vector<double> c_removed;
  for (std::size_t v = 0; v < V; ++v)
    if (has[v] && mask[v] >= 0.5) c_removed.push_back(c[v]);
  st.median_removed = MedianOf(c_removed);
  for (double& x : c_removed) x = std::abs(x - st.median_removed);
  st.sigma_removed = std::max(1.4826 * MedianOf(std::move(c_removed)), 1e-9);
  const double full = st.median_removed - kCreditFull * st.sigma_removed;
  const double zero = st.median_removed - kCreditZero * st.sigma_removed;
  const std::vector<double> upper = UpperPosterior(c, has, mask, st);
  const double doubt_removed = Ramp(st.removal_rate_lower, kDoubtRemovedZero, kDoubtRemovedFull);
  const double doubt_kept = Ramp(st.removal_rate_upper, kDoubtKeptZero, kDoubtKeptFull);
  for (std::size_t v = 0; v < V; ++v) {
    if (!has[v]) continue;
    // Within the removed set's own spread a Gaussian looks like the removed ones: credit for a
    // kept one, no doubt for a removed one (whatever group the mixture put it in).
    const double within = std::clamp((c[v] - zero) / (full - zero), 0.0, 1.0);
    double q = mask[v];
    if (mask[v] >= 0.5) q += doubt_removed * (std::max(upper[v], within) - q);
    else q += doubt_kept * (std::min(upper[v], within) - q);
    y[v] = (1.0 - o.weight) * mask[v] + o.weight * q;
    st.removed_doubted += mask[v] >= 0.5 && q < 0.5;
    st.kept_doubted += mask[v] < 0.5 && q > 0.5;
  }
  if (stats) *stats = st;
  return y;
}

nlohmann::json PriorStats::ToJson() const {
  return {{"weight", weight},
          {"mean_lower", mean_lower},
          {"mean_upper", mean_upper},
          {"sd_lower", sd_lower},
          {"sd_upper", sd_upper},
          {"removal_rate_lower", removal_rate_lower},
          {"removal_rate_upper", removal_rate_upper},
          {"median_removed", median_removed},
          {"sigma_removed", sigma_removed},
          {"removed_doubted", removed_doubted},
          {"kept_doubted", kept_doubted}};
}

}  // namespace al
