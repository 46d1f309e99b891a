// Non-finite value accounting (SPEC §9): such Gaussians load, are reported, and are excluded later.
#include <cmath>

#include "al/io/ply.hpp"

namespace al {
namespace {

template <typename M>
std::size_t RowNonFinite(const M& m, Eigen::Index i) {
  if (m.rows() <= i) return 0;
  std::size_t bad = 0;
  for (Eigen::Index c = 0; c < m.cols(); ++c) bad += std::isfinite(m(i, c)) ? 0 : 1;
  return bad;
}

// 1 when row i has a non-finite value in a column the reader checked but did not decode (f_rest,
// rotations; counted with the SH).
std::size_t Undecoded(const Scene& scene, Eigen::Index i) {
  return scene.nonfinite_undecoded.size() > std::size_t(i) && scene.nonfinite_undecoded[std::size_t(i)] ? 1 : 0;
}

}  // namespace

NonFiniteCounts CountNonFinite(const Scene& scene) {
  NonFiniteCounts out;
  for (Eigen::Index i = 0; i < static_cast<Eigen::Index>(scene.size()); ++i) {
    const std::size_t m = RowNonFinite(scene.means, i), s = RowNonFinite(scene.log_scales, i),
                      r = RowNonFinite(scene.rotations, i), sh = RowNonFinite(scene.sh, i) + Undecoded(scene, i),
                      f = RowNonFinite(scene.features, i);
    const std::size_t o = scene.opacity_logits.size() > i && !std::isfinite(scene.opacity_logits(i)) ? 1 : 0;
    out.means += m;
    out.scales += s;
    out.rotations += r;
    out.opacities += o;
    out.sh += sh;
    out.features += f;
    if (m + s + r + o + sh > 0) ++out.gaussians_with_any;
  }
  return out;
}

std::vector<bool> FiniteMask(const Scene& scene) {
  std::vector<bool> mask(scene.size(), true);
  for (Eigen::Index i = 0; i < static_cast<Eigen::Index>(scene.size()); ++i) {
    const bool opacity_ok = scene.opacity_logits.size() <= i || std::isfinite(scene.opacity_logits(i));
    mask[static_cast<std::size_t>(i)] = opacity_ok && RowNonFinite(scene.means, i) == 0 &&
                                        RowNonFinite(scene.log_scales, i) == 0 &&
                                        RowNonFinite(scene.rotations, i) == 0 && RowNonFinite(scene.sh, i) == 0 &&
                                        Undecoded(scene, i) == 0;
  }
  return mask;
}

}  // namespace al
