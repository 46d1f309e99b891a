// FeaturePrior (al/graph/prior.hpp). Every sum runs sequentially in node order, so the result does
// not depend on the thread count.
#include "al/graph/prior.hpp"

#include <algorithm>
#include <cmath>
#include <tuple>
#include <utility>

#include "al/core/error.hpp"
#include "src/graph/robust_stats.hpp"

namespace al {
namespace {

// Where the kept candidates' credit ramps, in robust standard deviations below the removed median
// (chosen on the tuning half of the accuracy bench, docs/accuracy.md).
constexpr double kCreditFull = 0.0, kCreditZero = 2.0;
// ... or half-way to the kept candidates' median, when that reaches further (kCreditGapShare).
constexpr double kCreditGapShare = 0.5;
// The prototype credit ramps from 1.5 robust standard deviations below the trusted removed rows'
// median cosine to 1 below it (B2 of issue 13 stops at about 1). From 2, a look-alike FGS had
// half grabbed was completed (tests/refine/refine_accuracy_test.cpp).
constexpr double kPrototypeFull = 1.0, kPrototypeZero = 1.5;
// Removed Gaussians of the lower group are doubted only when that group stands apart from the
// removed set: its mean at least 1.5 (full doubt from 2.5) of its standard deviations below the
// removed median. Below that the lower group is the object's own tail (fgs-like masks on CLIP-like
// fields restored up to 350 object Gaussians, docs/refine.md).
constexpr double kSeparationZero = 1.5, kSeparationFull = 2.5;
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
#pragma omp parallel for schedule(static)
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
    const double half_log_var[2] = {0.5 * std::log(var[0]), 0.5 * std::log(var[1])};
    // Each node's posterior on its own: parallel, and the same values whatever the thread count.
    // The logistic in blocks through Eigen's vectorised exp (25 iterations over 685k nodes at 3M:
    // one glibc exp per node and iteration was most of the prior's time).
    const auto vv = static_cast<std::int64_t>(V);
    constexpr std::int64_t kBlock = 4096;
#pragma omp parallel for schedule(static)
    for (std::int64_t b = 0; b < vv; b += kBlock) {
      const std::int64_t n = std::min(kBlock, vv - b);
      Eigen::ArrayXd z(n);
      for (std::int64_t i = 0; i < n; ++i) {
        const double x = c[std::size_t(b + i)];
        double l[2];
        for (int k = 0; k < 2; ++k) l[k] = -0.5 * (x - mu[k]) * (x - mu[k]) / var[k] - half_log_var[k];
        z[i] = -std::clamp(log_odds_prior + l[1] - l[0], -50.0, 50.0);
      }
      const Eigen::ArrayXd p = 1.0 / (1.0 + z.exp());
      for (std::int64_t i = 0; i < n; ++i)
        if (has[std::size_t(b + i)]) q[std::size_t(b + i)] = p[i];
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

// Cosine of each row to the prototype: the mean direction of the removed rows marked `trusted`.
// Zero rows get 0.
std::vector<double> PrototypeCosine(const RowMatXf& f, const std::vector<double>& mask,
                                    const std::vector<std::uint8_t>& has, const std::vector<std::uint8_t>& trusted) {
  const std::size_t V = mask.size();
  Eigen::VectorXd proto = Eigen::VectorXd::Zero(f.cols());
  for (std::size_t v = 0; v < V; ++v)
    if (has[v] && mask[v] >= 0.5 && trusted[v]) proto += f.row(Eigen::Index(v)).transpose().cast<double>();
  if (proto.norm() > 0) proto.normalize();
  std::vector<double> c(V, 0.0);
  for (std::size_t v = 0; v < V; ++v) {
    if (!has[v]) continue;
    const auto row = f.row(Eigen::Index(v)).transpose().cast<double>();  // an expression: no copy per row
    c[v] = row.dot(proto) / std::max(row.norm(), 1e-12);
  }
  return c;
}

// The prototype credit of every row: 1 where its cosine to the prototype is within kPrototypeFull
// robust standard deviations of the trusted removed rows' median, 0 beyond kPrototypeZero, linear
// between. Trusted: every removed row, unless the prior doubts a removed group — then only the
// removed rows of the upper ("object") group, so a table top GG's hull took does not become part of
// the prototype.
std::vector<double> CreditFromPrototype(const RowMatXf& f, const std::vector<double>& mask,
                                        const std::vector<std::uint8_t>& has, const std::vector<double>& upper,
                                        double doubt_removed, PriorStats& st) {
  const std::size_t V = mask.size();
  std::vector<std::uint8_t> trusted(V, 1);
  if (doubt_removed > 0.0)
    for (std::size_t v = 0; v < V; ++v) trusted[v] = upper[v] >= 0.5;
  const std::vector<double> cosine = PrototypeCosine(f, mask, has, trusted);
  std::vector<double> trusted_cosines;
  for (std::size_t v = 0; v < V; ++v)
    if (has[v] && mask[v] >= 0.5 && trusted[v]) trusted_cosines.push_back(cosine[v]);
  st.prototype_rows = trusted_cosines.size();
  std::tie(st.prototype_cos_median, st.prototype_cos_sigma) = MedianAndSpread(std::move(trusted_cosines));
  const double full = st.prototype_cos_median - kPrototypeFull * st.prototype_cos_sigma;
  const double zero = st.prototype_cos_median - kPrototypeZero * st.prototype_cos_sigma;
  std::vector<double> credit(V, 0.0);
  if (st.prototype_rows == 0 || !(full > zero)) return credit;
  for (std::size_t v = 0; v < V; ++v)
    if (has[v]) credit[v] = Ramp(cosine[v], zero, full);
  return credit;
}

// The removed candidates' projections: median and spread (PriorStats), and the gap to the kept
// candidates' median.
double RemovedSpreadAndGap(const std::vector<double>& c, const std::vector<std::uint8_t>& has,
                           const std::vector<double>& mask, PriorStats& st) {
  std::vector<double> removed, kept;
  for (std::size_t v = 0; v < c.size(); ++v)
    if (has[v]) (mask[v] >= 0.5 ? removed : kept).push_back(c[v]);
  std::tie(st.median_removed, st.sigma_removed) = MedianAndSpread(std::move(removed));
  st.sigma_removed = std::max(st.sigma_removed, 1e-9);
  return std::max(0.0, st.median_removed - MedianOf(std::move(kept)));
}

// How much the removed Gaussians of the lower group are doubted: only when the method kept most
// of that group (removal rate) and the group stands apart from the removed set (separation) —
// a distinct group such as GG's table top, not the broad lower tail of the object itself.
double DoubtOfRemoved(PriorStats& st) {
  st.separation = (st.median_removed - st.mean_lower) / std::max(st.sd_lower, 1e-12);
  return Ramp(st.removal_rate_lower, kDoubtRemovedZero, kDoubtRemovedFull) *
         Ramp(st.separation, kSeparationZero, kSeparationFull);
}

}  // namespace

void PriorOptions::Check() const {
  if (!(Weight() >= 0.0 && Weight() <= 1.0)) throw Error("--prior-weight must be in [0, 1]", ExitCode::kUsage);
}

std::vector<double> FeaturePrior(const RowMatXf& f, const std::vector<double>& mask, const PriorOptions& o,
                                 PriorStats* stats, KeptCredit kept_credit, std::vector<double>* upper_group) {
  const bool credit_kept = kept_credit == KeptCredit::kAllowed;
  o.Check();
  const std::size_t V = mask.size();
  if (f.rows() != Eigen::Index(V)) throw Error("prior: feature rows do not match the nodes", ExitCode::kInternal);
  std::vector<double> y(mask);
  PriorStats st;
  const double weight = o.Weight();
  st.weight = weight;
  st.kept_credit = credit_kept;
  const auto n_removed = std::size_t(std::count_if(mask.begin(), mask.end(), [](double m) { return m >= 0.5; }));
  if (upper_group) upper_group->clear();
  if (weight == 0.0 || n_removed == 0 || n_removed == V) {
    if (stats) *stats = st;
    return y;
  }
  std::vector<std::uint8_t> has;
  const std::vector<double> c = Project(f, mask, has);
  st.gap = RemovedSpreadAndGap(c, has, mask, st);
  // "Within the removed set's spread" reaches down to 2σ below its median. For a kept Gaussian's
  // credit it reaches half-way to the kept candidates' median when that is further: a tight object
  // (CLIP-like fields) would otherwise deny credit to misses that lie far above everything the
  // method kept. (Widening the removed side too held back GG's table restores.)
  const double full = st.median_removed - kCreditFull * st.sigma_removed;
  const double zero = st.median_removed - kCreditZero * st.sigma_removed;
  const double zero_kept =
      o.wide_credit != PriorSwitch::kOn
          ? zero
          : st.median_removed - std::max(kCreditZero * st.sigma_removed, kCreditGapShare * st.gap);
  const std::vector<double> upper = UpperPosterior(c, has, mask, st);
  const double doubt_removed = DoubtOfRemoved(st);
  if (upper_group) *upper_group = upper;
  const double doubt_kept = credit_kept ? Ramp(st.removal_rate_upper, kDoubtKeptZero, kDoubtKeptFull) : 0.0;
  const std::vector<double> credit = o.prototype_credit != PriorSwitch::kOn || !credit_kept
                                         ? std::vector<double>(V, 0.0)
                                         : CreditFromPrototype(f, mask, has, upper, doubt_removed, st);
  for (std::size_t v = 0; v < V; ++v) {
    if (!has[v]) continue;
    // Within the removed set's own spread a Gaussian looks like the removed ones: credit for a
    // kept one, no doubt for a removed one (whatever group the mixture put it in).
    double q = mask[v];
    if (mask[v] >= 0.5) q += doubt_removed * (std::max(upper[v], Ramp(c[v], zero, full)) - q);
    else q += doubt_kept * (std::max(std::min(upper[v], Ramp(c[v], zero_kept, full)), credit[v]) - q);
    y[v] = (1.0 - weight) * mask[v] + weight * q;
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
          {"gap", gap},
          {"separation", separation},
          {"prototype_rows", prototype_rows},
          {"prototype_cos_median", prototype_cos_median},
          {"prototype_cos_sigma", prototype_cos_sigma},
          {"removed_doubted", removed_doubted},
          {"kept_doubted", kept_doubted},
          {"kept_credit", kept_credit}};
}

}  // namespace al
