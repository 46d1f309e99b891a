// Matching a subset scene back to the full scene's indices by exact float32 bit patterns
// (FORMATS.md §2.4): order-preserving walk, then key groups (hash pass), then an optional
// centre-distance tolerance pass.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>
#include <unordered_map>

#include "al/io/masks.hpp"

namespace al {
namespace {

// Flattened keys: row r occupies words [r*width, (r+1)*width).
struct KeyTable {
  std::size_t width = 0;
  std::vector<std::uint32_t> words;
  const std::uint32_t* Row(std::size_t r) const { return words.data() + r * width; }
};

struct KeyLayout {
  bool opacity = false, scales = false, rotations = false, f_dc = false;
  std::size_t Width() const { return 3 + (opacity ? 1 : 0) + (scales ? 3 : 0) + (rotations ? 4 : 0) + (f_dc ? 3 : 0); }
};

std::uint32_t Bits(float v) { return std::bit_cast<std::uint32_t>(v); }

// Key order: x y z opacity scale_0..2 rot_0..3 f_dc_0..2 (only the groups both files have).
KeyTable BuildKeys(const Scene& s, const KeyLayout& layout) {
  KeyTable t;
  t.width = layout.Width();
  const std::size_t n = s.size();
  t.words.resize(n * t.width);
  for (std::size_t i = 0; i < n; ++i) {
    std::uint32_t* w = t.words.data() + i * t.width;
    for (int c = 0; c < 3; ++c) *w++ = Bits(s.means(i, c));
    if (layout.opacity) *w++ = Bits(s.opacity_logits(i));
    if (layout.scales)
      for (int c = 0; c < 3; ++c) *w++ = Bits(s.log_scales(i, c));
    if (layout.rotations)
      for (int c = 0; c < 4; ++c) *w++ = Bits(s.rotations(i, c));
    if (layout.f_dc)
      for (int c = 0; c < 3; ++c) *w++ = Bits(s.sh(i, c));
  }
  return t;
}

bool Equal(const std::uint32_t* a, const std::uint32_t* b, std::size_t w) {
  return std::memcmp(a, b, w * sizeof(std::uint32_t)) == 0;
}

int Compare(const std::uint32_t* a, const std::uint32_t* b, std::size_t w) {
  for (std::size_t k = 0; k < w; ++k)
    if (a[k] != b[k]) return a[k] < b[k] ? -1 : 1;
  return 0;
}

// Scene rows sorted by (key, index): equal keys form contiguous groups in ascending index order.
struct KeyGroups {
  const KeyTable* keys = nullptr;
  std::vector<std::int64_t> order;
  std::vector<std::size_t> group_end;   // per position in `order`: end of its group
  std::vector<std::size_t> cursor;      // per group start: first possibly-unused position

  explicit KeyGroups(const KeyTable& k, std::size_t n) : keys(&k), order(n) {
    std::iota(order.begin(), order.end(), std::int64_t{0});
    const std::size_t w = k.width;
    std::sort(order.begin(), order.end(), [&](std::int64_t a, std::int64_t b) {
      const int c = Compare(k.Row(a), k.Row(b), w);
      return c != 0 ? c < 0 : a < b;
    });
    group_end.resize(n);
    cursor.resize(n);
    for (std::size_t p = 0; p < n;) {
      std::size_t q = p + 1;
      while (q < n && Equal(k.Row(order[p]), k.Row(order[q]), w)) ++q;
      for (std::size_t r = p; r < q; ++r) group_end[r] = q;
      cursor[p] = p;
      p = q;
    }
  }

  // Start of the group holding `key`, or npos.
  std::size_t Find(const std::uint32_t* key) const {
    const std::size_t w = keys->width;
    auto it = std::lower_bound(order.begin(), order.end(), key, [&](std::int64_t row, const std::uint32_t* k) {
      return Compare(keys->Row(row), k, w) < 0;
    });
    if (it == order.end() || !Equal(keys->Row(*it), key, w)) return npos;
    return static_cast<std::size_t>(it - order.begin());
  }
  std::size_t GroupSize(std::size_t start) const { return group_end[start] - start; }

  static constexpr std::size_t npos = std::numeric_limits<std::size_t>::max();
};

struct CellKey {
  std::int64_t x, y, z;
  bool operator==(const CellKey&) const = default;
};
struct CellHash {
  std::size_t operator()(const CellKey& c) const {
    std::uint64_t h = static_cast<std::uint64_t>(c.x) * 0x9E3779B97F4A7C15ull;
    h ^= static_cast<std::uint64_t>(c.y) * 0xC2B2AE3D27D4EB4Full + (h << 6) + (h >> 2);
    h ^= static_cast<std::uint64_t>(c.z) * 0x165667B19E3779F9ull + (h << 6) + (h >> 2);
    return static_cast<std::size_t>(h);
  }
};

// Cell coordinate, clamped so huge coordinates / tiny tolerances cannot overflow.
std::int64_t Cell(double v, double t) {
  const double c = std::floor(v / t);
  const double lim = 4.0e18;
  return static_cast<std::int64_t>(std::clamp(c, -lim, lim));
}

// Only the column groups both scenes carry (with the row counts they claim) enter the key.
KeyLayout SharedLayout(const Scene& scene, const Scene& subset) {
  const auto n = Eigen::Index(scene.size()), m = Eigen::Index(subset.size());
  KeyLayout layout;
  layout.opacity = scene.has_opacity && subset.has_opacity && scene.opacity_logits.size() == n &&
                   subset.opacity_logits.size() == m;
  layout.scales = scene.has_scales && subset.has_scales && scene.log_scales.rows() == n &&
                  subset.log_scales.rows() == m;
  layout.rotations = scene.has_rotations && subset.has_rotations && scene.rotations.rows() == n &&
                     subset.rotations.rows() == m;
  layout.f_dc = scene.has_f_dc && subset.has_f_dc && scene.sh.rows() == n && scene.sh.cols() >= 3 &&
                subset.sh.rows() == m && subset.sh.cols() >= 3;
  return layout;
}

// Pass 1: order-preserving walk; stops at the first subset row not found further on.
void MatchInOrder(const KeyTable& skeys, const KeyTable& qkeys, std::vector<bool>& used, SubsetMatch& m) {
  const std::size_t n = used.size(), w = skeys.width;
  std::size_t i = 0;
  for (std::size_t j = 0; j < m.scene_index.size(); ++j) {
    std::size_t k = i;
    while (k < n && !Equal(skeys.Row(k), qkeys.Row(j), w)) ++k;
    if (k == n) break;
    m.scene_index[j] = static_cast<std::int64_t>(k);
    used[k] = true;
    ++m.matched_in_order;
    i = k + 1;
  }
}

std::size_t CountAmbiguous(const KeyGroups& groups, const KeyTable& qkeys, std::size_t rows) {
  std::size_t ambiguous = 0;
  for (std::size_t j = 0; j < rows; ++j) {
    const std::size_t g = groups.Find(qkeys.Row(j));
    if (g != KeyGroups::npos && groups.GroupSize(g) > 1) ++ambiguous;
  }
  return ambiguous;
}

// Pass 2: each remaining row takes the smallest unused scene index with its key.
void MatchByKey(KeyGroups& groups, const KeyTable& qkeys, std::vector<bool>& used, SubsetMatch& m) {
  for (std::size_t j = 0; j < m.scene_index.size(); ++j) {
    if (m.scene_index[j] >= 0) continue;
    const std::size_t g = groups.Find(qkeys.Row(j));
    if (g == KeyGroups::npos) continue;
    std::size_t& c = groups.cursor[g];
    const std::size_t end = groups.group_end[g];
    while (c < end && used[static_cast<std::size_t>(groups.order[c])]) ++c;
    if (c == end) continue;
    const auto idx = groups.order[c];
    used[static_cast<std::size_t>(idx)] = true;
    m.scene_index[j] = idx;
    ++m.matched_by_hash;
  }
}

bool FiniteCentre(const Scene& s, std::size_t i) {
  return std::isfinite(s.means(i, 0)) && std::isfinite(s.means(i, 1)) && std::isfinite(s.means(i, 2));
}

using CentreGrid = std::unordered_map<CellKey, std::vector<std::int64_t>, CellHash>;

// Unused finite scene centres bucketed in cells of size t.
CentreGrid BuildCentreGrid(const Scene& scene, const std::vector<bool>& used, double t) {
  CentreGrid grid;
  for (std::size_t i = 0; i < scene.size(); ++i) {
    if (used[i] || !FiniteCentre(scene, i)) continue;
    grid[{Cell(scene.means(i, 0), t), Cell(scene.means(i, 1), t), Cell(scene.means(i, 2), t)}].push_back(
        static_cast<std::int64_t>(i));
  }
  return grid;
}

// Nearest unused scene centre to subset row j within distance t (ties: the smaller index), or -1.
std::int64_t NearestUnused(const Scene& scene, const Scene& subset, std::size_t j, const CentreGrid& grid,
                           const std::vector<bool>& used, double t) {
  const double x = subset.means(j, 0), y = subset.means(j, 1), z = subset.means(j, 2);
  const CellKey c{Cell(x, t), Cell(y, t), Cell(z, t)};
  std::int64_t best = -1;
  double best_d2 = t * t;
  for (int dx = -1; dx <= 1; ++dx)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dz = -1; dz <= 1; ++dz) {
        auto it = grid.find({c.x + dx, c.y + dy, c.z + dz});
        if (it == grid.end()) continue;
        for (std::int64_t i : it->second) {
          if (used[static_cast<std::size_t>(i)]) continue;
          const double ex = scene.means(i, 0) - x, ey = scene.means(i, 1) - y, ez = scene.means(i, 2) - z;
          const double d2 = ex * ex + ey * ey + ez * ez;
          if (d2 < best_d2 || (d2 == best_d2 && (best < 0 || i < best))) {
            best_d2 = d2;
            best = i;
          }
        }
      }
  return best;
}

// Pass 3: nearest unused scene centre within the tolerance (grid of cell size t).
void MatchByTolerance(const Scene& scene, const Scene& subset, double t, std::vector<bool>& used, SubsetMatch& m) {
  const CentreGrid grid = BuildCentreGrid(scene, used, t);
  for (std::size_t j = 0; j < subset.size(); ++j) {
    if (m.scene_index[j] >= 0 || !FiniteCentre(subset, j)) continue;
    const std::int64_t best = NearestUnused(scene, subset, j, grid, used, t);
    if (best < 0) continue;
    used[static_cast<std::size_t>(best)] = true;
    m.scene_index[j] = best;
    ++m.matched_by_tolerance;
  }
}

}  // namespace

SubsetMatch MatchSubset(const Scene& scene, const Scene& subset, double match_tolerance) {
  SubsetMatch m;
  const std::size_t n = scene.size(), mrows = subset.size();
  m.scene_index.assign(mrows, -1);
  if (mrows == 0) return m;

  const KeyLayout layout = SharedLayout(scene, subset);
  const KeyTable skeys = BuildKeys(scene, layout);
  const KeyTable qkeys = BuildKeys(subset, layout);
  std::vector<bool> used(n, false);
  MatchInOrder(skeys, qkeys, used, m);
  KeyGroups groups(skeys, n);  // serves both the ambiguity count and pass 2
  m.ambiguous = CountAmbiguous(groups, qkeys, mrows);
  if (m.matched_in_order < mrows) MatchByKey(groups, qkeys, used, m);
  if (match_tolerance > 0 && std::isfinite(match_tolerance) && m.matched_in_order + m.matched_by_hash < mrows)
    MatchByTolerance(scene, subset, match_tolerance, used, m);
  m.unmatched = mrows - m.matched_in_order - m.matched_by_hash - m.matched_by_tolerance;
  return m;
}

}  // namespace al
