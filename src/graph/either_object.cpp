// TrimOneSidedAdditions (al/graph/either_object.hpp). Sequential and closed-form: the two readings'
// F1 depend only on counts, so the search over how many additions to take back is a scan.
#include "al/graph/either_object.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>

#include "src/graph/nearest_row.hpp"

namespace al {
namespace {

struct Addition {
  std::int64_t row = 0;
  int part = 0;        // 0 = A, 1 = B
  float sq_dist = 0;   // to the nearest row of that part
};

// Each row's nearest row of part A ∪ B (ties: the smaller row) and that row's part. The queries
// are independent: split over the threads, each writing its own slot.
std::vector<Addition> AssignToParts(const EitherObjectInputs& in, const NearestRowTree& tree,
                                    const std::vector<std::int64_t>& rows) {
  std::vector<Addition> out(rows.size());
  const auto n = static_cast<std::int64_t>(rows.size());
#pragma omp parallel for schedule(dynamic, 256)
  for (std::int64_t t = 0; t < n; ++t) {
    const std::int64_t row = rows[std::size_t(t)];
    const NearestRowTree::Hit hit = tree.Nearest(&in.xyz[3 * std::size_t(row)]);
    out[std::size_t(t)] = {row, hit.index < in.part_a.size() ? 0 : 1, hit.sq_dist};
  }
  return out;
}

// F1 against "the object is part h plus what was added to it", before and after, from counts.
struct Readings {
  double removed = 0, restored = 0;      // |R|, rows of R given back
  double part[2] = {0, 0}, part_restored[2] = {0, 0}, added[2] = {0, 0};
  double Delta(int h, double kept_a, double kept_b) const {
    const double object = part[h] + added[h];
    const double before = 2.0 * part[h] / (removed + object);
    const double kept = h == 0 ? kept_a : kept_b;
    const double after = 2.0 * (part[h] - part_restored[h] + kept) / (removed - restored + kept_a + kept_b + object);
    return after - before;
  }
  double Worst(double kept_a, double kept_b) const { return std::min(Delta(0, kept_a, kept_b), Delta(1, kept_a, kept_b)); }
};

// Parts A and B with the removed fragments nearest to each (a fragment lies beside the object it
// broke from; the readings would otherwise miss the restores among them).
Readings CountReadings(const EitherObjectInputs& in, const std::vector<bool>& refined,
                       const std::vector<Addition>& adds, const std::vector<Addition>& fragments) {
  Readings r;
  for (std::size_t i = 0; i < in.removed.size(); ++i) {
    r.removed += in.removed[i];
    r.restored += in.removed[i] && !refined[i];
  }
  const std::vector<std::int64_t>* parts[2] = {&in.part_a, &in.part_b};
  for (int h = 0; h < 2; ++h) {
    r.part[h] = double(parts[h]->size());
    for (std::int64_t row : *parts[h]) r.part_restored[h] += !refined[std::size_t(row)];
  }
  for (const Addition& f : fragments) {
    r.part[f.part] += 1;
    r.part_restored[f.part] += !refined[std::size_t(f.row)];
  }
  for (const Addition& a : adds) r.added[a.part] += 1;
  return r;
}

// How many of part `o`'s additions to take back: the fewest that lift both readings to ≥ −tol,
// else the count that lifts the worse reading highest (the fewest among equals).
std::size_t TrimCount(const Readings& r, int o, double tol) {
  const auto kept = [&](std::size_t t, int h) { return r.added[h] - (h == o ? double(t) : 0.0); };
  double best_worst = -std::numeric_limits<double>::infinity();
  std::size_t best = 0;
  for (std::size_t t = 0; t <= std::size_t(r.added[o]); ++t) {
    const double worst = r.Worst(kept(t, 0), kept(t, 1));
    if (worst >= -tol) return t;
    if (worst > best_worst) best_worst = worst, best = t;
  }
  return best;
}

}  // namespace

nlohmann::json EitherObjectStats::ToJson() const {
  static const char* kPart[] = {"largest", "second"};
  return {{"parts", {parts[0], parts[1]}},
          {"added", {added[0], added[1]}},
          {"restored", {restored[0], restored[1]}},
          {"trimmed", trimmed},
          {"trimmed_part", trimmed_part < 0 ? nlohmann::json(nullptr) : nlohmann::json(kPart[trimmed_part])},
          {"worst_reading_dF1_before", worst_before},
          {"worst_reading_dF1_after", worst_after}};
}

std::vector<std::int64_t> TrimOneSidedAdditions(const EitherObjectInputs& in, const std::vector<bool>& refined,
                                                EitherObjectStats* stats) {
  EitherObjectStats st;
  std::vector<std::int64_t> back;
  std::vector<std::uint8_t> in_part(in.removed.size(), 0);
  for (const auto* part : {&in.part_a, &in.part_b})
    for (std::int64_t row : *part) in_part[std::size_t(row)] = 1;
  std::vector<std::int64_t> added, fragments;  // rows with a finite position (graph nodes are)
  for (std::size_t i = 0; i < refined.size(); ++i) {
    const float* p = &in.xyz[3 * i];
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) continue;
    if (refined[i] && !in.removed[i]) added.push_back(std::int64_t(i));
    if (in.removed[i] && !in_part[i]) fragments.push_back(std::int64_t(i));
  }
  if (!in.part_a.empty() && !in.part_b.empty() && !added.empty()) {
    std::vector<std::int64_t> part_rows(in.part_a);
    part_rows.insert(part_rows.end(), in.part_b.begin(), in.part_b.end());
    const NearestRowTree tree(in.xyz, part_rows);
    const std::vector<Addition> adds = AssignToParts(in, tree, added);
    const Readings r = CountReadings(in, refined, adds, AssignToParts(in, tree, fragments));
    for (int h = 0; h < 2; ++h) {
      st.parts[h] = std::size_t(r.part[h]);
      st.added[h] = std::size_t(r.added[h]);
      st.restored[h] = std::size_t(r.part_restored[h]);
    }
    st.worst_before = st.worst_after = r.Worst(r.added[0], r.added[1]);
    // The worse reading is hurt by the other part's additions: those are the ones to take back.
    const int o = r.Delta(0, r.added[0], r.added[1]) <= r.Delta(1, r.added[0], r.added[1]) ? 1 : 0;
    const std::size_t t = in.tolerance >= 1.0 ? 0 : TrimCount(r, o, in.tolerance);
    if (t > 0) {
      std::vector<Addition> own;
      for (const Addition& a : adds)
        if (a.part == o) own.push_back(a);
      std::sort(own.begin(), own.end(), [](const Addition& x, const Addition& y) {
        return std::tie(y.sq_dist, y.row) < std::tie(x.sq_dist, x.row);  // farthest first
      });
      for (std::size_t j = 0; j < t; ++j) back.push_back(own[j].row);
      std::sort(back.begin(), back.end());
      st.trimmed = t;
      st.trimmed_part = o;
      st.worst_after = r.Worst(r.added[0] - (o == 0 ? double(t) : 0.0), r.added[1] - (o == 1 ? double(t) : 0.0));
    }
  }
  if (stats) *stats = st;
  return back;
}

}  // namespace al
