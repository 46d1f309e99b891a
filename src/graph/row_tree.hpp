// A kd-tree (FLANN, exact) over chosen scene rows of a 3N position array, queried by position:
// the whole-scene searches of the refine stages' last step (taken_whole.cpp's region walk,
// either_object.cpp's nearest part) need neighbours among rows the graph's kNN never saw.
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include <flann/flann.hpp>

namespace al {

class RowTree {
 public:
  // xyz must outlive the tree; rows index its points (3 floats each).
  RowTree(const std::vector<float>& xyz, std::vector<std::int64_t> rows) : rows_(std::move(rows)) {
    points_.resize(3 * rows_.size());
    for (std::size_t r = 0; r < rows_.size(); ++r)
      for (std::size_t a = 0; a < 3; ++a) points_[3 * r + a] = xyz[3 * std::size_t(rows_[r]) + a];
    if (rows_.empty()) return;
    tree_ = std::make_unique<Tree>(flann::Matrix<float>(points_.data(), rows_.size(), 3),
                                   flann::KDTreeSingleIndexParams(10));
    tree_->buildIndex();
  }
  const std::vector<std::int64_t>& rows() const { return rows_; }

  // Up to `want` nearest of the tree's rows to point p, nearest first: their positions in rows()
  // and squared distances.
  void Nearest(const float* p, std::size_t want, std::vector<std::size_t>& index, std::vector<float>& sq_dist) const {
    want = tree_ ? std::min(want, rows_.size()) : 0;
    index.resize(want);
    sq_dist.resize(want);
    if (want == 0) return;
    flann::KNNSimpleResultSet<float> rs(want);
    tree_->findNeighbors(rs, p, flann::SearchParams(flann::FLANN_CHECKS_UNLIMITED, 0, false));
    index.resize(rs.size());
    sq_dist.resize(rs.size());
    if (!index.empty()) rs.copy(index.data(), sq_dist.data(), index.size());
  }

 private:
  using Tree = flann::KDTreeSingleIndex<flann::L2_Simple<float>>;
  std::vector<std::int64_t> rows_;
  std::vector<float> points_;
  std::unique_ptr<Tree> tree_;
};

// kNN queries of single scene rows among the active ones (the graph's kNN only covers candidates):
// taken_whole.cpp's region walk and continuing_body.cpp's walk beyond the additions.
class SceneKnn {
 public:
  SceneKnn(const std::vector<float>& xyz, const std::vector<std::uint8_t>& active)
      : xyz_(xyz), tree_(xyz, ActiveRows(active)) {}
  // Up to k nearest active rows of scene row i, i itself excluded.
  void Neighbours(std::int64_t i, int k, std::vector<std::int64_t>& out) {
    out.clear();
    tree_.Nearest(&xyz_[3 * std::size_t(i)], std::size_t(k) + 1, index_, sq_dist_);
    for (std::size_t t = 0; t < index_.size() && out.size() < std::size_t(k); ++t)
      if (tree_.rows()[index_[t]] != i) out.push_back(tree_.rows()[index_[t]]);
  }

 private:
  static std::vector<std::int64_t> ActiveRows(const std::vector<std::uint8_t>& active) {
    std::vector<std::int64_t> rows;
    for (std::size_t i = 0; i < active.size(); ++i)
      if (active[i]) rows.push_back(static_cast<std::int64_t>(i));
    return rows;
  }
  const std::vector<float>& xyz_;
  RowTree tree_;
  std::vector<std::size_t> index_;
  std::vector<float> sq_dist_;
};


}  // namespace al
