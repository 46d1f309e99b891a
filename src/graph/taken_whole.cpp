// FindTakenWhole (al/graph/taken_whole.hpp). Sequential: regions are explored in the order of the
// queried rows, so the result is deterministic and independent of the thread count.
#include "al/graph/taken_whole.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <memory>

#include "al/core/timer.hpp"
#include "src/graph/row_tree.hpp"

namespace al {

bool SceneFeatureMap::Row(std::int64_t i, float* out) const {
  Eigen::Map<Eigen::VectorXf> f(out, features.cols());
  f = features.row(Eigen::Index(i)).transpose();
  if (!normalize) return true;
  // Float throughout: the graph and the region search transform every row they touch (up to 512
  // values each), and in double with temporaries that was a sixth of a refine. A row whose squared
  // norm leaves float's range (|f| beyond ~1e19 or below ~1e-19) is scaled by its largest entry
  // first, so huge and tiny features keep their direction instead of becoming zero rows.
  float norm = f.norm();
  if (!(norm > 0) || !std::isfinite(norm)) {
    const float largest = f.cwiseAbs().maxCoeff();
    if (largest > 0 && std::isfinite(largest)) f /= largest;
    norm = f.norm();
  }
  if (norm > 0 && centre) {
    f = f / norm - mean.cast<float>();
    norm = f.norm();
  }
  if (!(norm > 0)) {
    f.setZero();
    return false;
  }
  f /= norm;
  return true;
}

nlohmann::json TakenWholeStats::ToJson() const {
  // No seconds: reports carry the decision's time (timings_s.decide), and records of sweeps must
  // be reproducible.
  return {{"regions", regions}, {"rows", rows}, {"kept", kept}, {"visited", visited}};
}

namespace {

// Each visited row's feature, computed once. Slots, not pointers: a new row may move the storage.
class FeatureCache {
 public:
  FeatureCache(const SceneFeatureMap& map, std::size_t n) : map_(map), slot_(n, -1) {}
  std::size_t Slot(std::int64_t i) {
    std::int64_t& slot = slot_[std::size_t(i)];
    if (slot < 0) {
      const std::size_t D = std::size_t(map_.features.cols());
      slot = static_cast<std::int64_t>(usable_.size());
      data_.resize(data_.size() + D);
      usable_.push_back(map_.Row(i, data_.data() + data_.size() - D) || !map_.normalize);
    }
    return std::size_t(slot);
  }
  bool Usable(std::size_t slot) const { return usable_[slot]; }
  const float* Data(std::size_t slot) const { return data_.data() + slot * std::size_t(map_.features.cols()); }

 private:
  const SceneFeatureMap& map_;
  std::vector<std::int64_t> slot_;
  std::vector<float> data_;
  std::vector<std::uint8_t> usable_;
};

struct Region {
  std::size_t size = 0, removed = 0;
  // Cannot qualify: too large for its removed share, or holding half the removed set (the main
  // region), or joined to such a region. Its search stops there.
  bool open = false;
};

struct Search {
  const TakenWholeInputs& in;
  SceneKnn knn;
  FeatureCache features;
  std::vector<std::int32_t> region_of;  // N, −1 = not visited
  std::vector<Region> regions;
  std::size_t removed_rows = 0;         // |R| among the active rows
  std::size_t limit = 0;                // a region larger than this cannot qualify

  bool Qualifies(const Region& r) const {
    return !r.open && double(r.removed) >= kTakenWholeRatio * double(r.size) &&
           double(r.removed) >= kTakenWholeShare * double(removed_rows) && 2 * r.removed < removed_rows;
  }

  bool Passes(std::int64_t u, std::int64_t v) {
    const std::size_t su = features.Slot(u), sv = features.Slot(v);
    if (!features.Usable(su) || !features.Usable(sv)) return false;
    const Eigen::Index D = in.features.features.cols();
    const Eigen::Map<const Eigen::VectorXf> fu(features.Data(su), D), fv(features.Data(sv), D);
    return double((fu - fv).squaredNorm()) <= in.gate * in.gate;
  }

  // Breadth-first over gated kNN edges from seed; stops as soon as the region cannot qualify.
  void Explore(std::int64_t seed) {
    const auto id = static_cast<std::int32_t>(regions.size());
    regions.emplace_back();
    Region& r = regions.back();
    std::deque<std::int64_t> queue{seed};
    region_of[std::size_t(seed)] = id;
    r.size = 1, r.removed = in.removed[std::size_t(seed)];
    std::vector<std::int64_t> nb;
    while (!queue.empty() && !r.open) {
      const std::int64_t u = queue.front();
      queue.pop_front();
      knn.Neighbours(u, in.k, nb);
      for (std::int64_t v : nb) {
        const std::int32_t other = region_of[std::size_t(v)];
        if (other == id || !Passes(u, v)) continue;
        if (other >= 0) {  // an earlier search's region, reached over a one-way kNN edge
          r.open = r.open || regions[std::size_t(other)].open;
          continue;
        }
        region_of[std::size_t(v)] = id;
        queue.push_back(v);
        r.removed += in.removed[std::size_t(v)];
        if (++r.size > limit || 2 * r.removed >= removed_rows) r.open = true;
      }
    }
  }
};

}  // namespace

std::vector<std::uint8_t> FindTakenWhole(const TakenWholeInputs& in, const std::vector<std::int64_t>& rows,
                                         TakenWholeStats* stats) {
  Timer timer;
  std::vector<std::uint8_t> trusted(rows.size(), 0);
  if (rows.empty()) return trusted;
  std::size_t removed_rows = 0;
  for (std::size_t i = 0; i < in.removed.size(); ++i) removed_rows += in.removed[i] && in.active[i];
  // Qualifying needs removed ≥ ratio · size and removed < |R| / 2, so size < |R| / (2 · ratio).
  Search s{in, SceneKnn(in.xyz, in.active), FeatureCache(in.features, in.removed.size()),
           std::vector<std::int32_t>(in.removed.size(), -1), {}, removed_rows,
           static_cast<std::size_t>(double(removed_rows) / (2 * kTakenWholeRatio))};
  std::vector<std::uint8_t> counted;
  TakenWholeStats st;
  for (std::size_t t = 0; t < rows.size(); ++t) {
    const std::int64_t row = rows[t];
    if (s.region_of[std::size_t(row)] < 0) s.Explore(row);
    const auto id = static_cast<std::size_t>(s.region_of[std::size_t(row)]);
    const Region& r = s.regions[id];
    trusted[t] = s.Qualifies(r);
    st.kept += trusted[t];
    counted.resize(s.regions.size(), 0);
    if (trusted[t] && !counted[id]) counted[id] = 1, ++st.regions, st.rows += r.removed;
  }
  for (const Region& r : s.regions) st.visited += r.size;
  st.seconds = timer.Seconds();
  if (stats) *stats = st;
  return trusted;
}

}  // namespace al
