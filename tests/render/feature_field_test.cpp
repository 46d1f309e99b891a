// PrepareFeatureField: unit rows, centring by the scene mean, PCA projection of wide features.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "al/core/error.hpp"
#include "al/render/feature_field.hpp"

namespace al {
namespace {

// n rows drawn around `classes` random class directions in `dim` dimensions, with a strong shared
// component (CLIP-like: raw cosines between classes ~0.75) and noise; random norms.
RowMatXf ClassFeatures(std::size_t n, int dim, int classes, float noise, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> N(0, 1);
  std::uniform_real_distribution<float> U(0.5f, 3.0f);
  Eigen::MatrixXf centres(classes, dim);
  for (Eigen::Index i = 0; i < centres.size(); ++i) centres.data()[i] = N(rng);
  Eigen::RowVectorXf common(dim);
  for (int d = 0; d < dim; ++d) common[d] = N(rng);
  common.normalize();
  for (int c = 0; c < classes; ++c) centres.row(c) = 1.7f * common + 0.5f * centres.row(c).normalized();
  RowMatXf f(static_cast<Eigen::Index>(n), dim);
  for (Eigen::Index i = 0; i < f.rows(); ++i) {
    Eigen::RowVectorXf e(dim);
    for (int d = 0; d < dim; ++d) e[d] = N(rng);
    f.row(i) = U(rng) * (centres.row(i % classes).normalized() + noise / std::sqrt(float(dim)) * e);
  }
  return f;
}

double Cosine(const Eigen::RowVectorXf& a, const Eigen::RowVectorXf& b) {
  return double(a.dot(b)) / (double(a.norm()) * double(b.norm()));
}

TEST(FeatureField, UnitRowsCentredByTheMean) {
  RowMatXf f = ClassFeatures(5000, 16, 4, 0.3f, 1);
  f.row(7).setZero();
  f(9, 3) = std::nanf("");
  const FeatureField field = PrepareFeatureField(f);
  EXPECT_EQ(field.dim(), 16);
  EXPECT_FALSE(field.projected());
  EXPECT_EQ(field.zero_norm, 2u);
  EXPECT_TRUE(field.channels.row(7).isZero());
  EXPECT_TRUE(field.channels.row(9).isZero());
  // channels = unit row - mean, and the channels' mean over the valid rows is 0.
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(16);
  for (Eigen::Index i = 0; i < f.rows(); ++i) {
    if (i == 7 || i == 9) continue;
    const Eigen::RowVectorXf expected = f.row(i).normalized() - field.mean.transpose();
    ASSERT_LT((field.channels.row(i) - expected).cwiseAbs().maxCoeff(), 1e-6f) << i;
    sum += field.channels.row(i).transpose().cast<double>();
  }
  EXPECT_LT(sum.cwiseAbs().maxCoeff() / double(f.rows()), 1e-6);
  // Centring removes the common component: raw cosines of different classes are high, centred ones not.
  EXPECT_GT(Cosine(f.row(0), f.row(1)), 0.6);
  EXPECT_LT(Cosine(field.channels.row(0), field.channels.row(1)), 0.3);
  FeatureFieldOptions raw;
  raw.centre = false;
  const FeatureField plain = PrepareFeatureField(f, raw);
  EXPECT_LT((plain.channels.row(0) - f.row(0).normalized()).cwiseAbs().maxCoeff(), 1e-6f);
}

// 128-D features with 6 classes projected to 16 channels: nearly all variance kept, cosines kept.
TEST(FeatureField, WideFeaturesAreProjected) {
  const RowMatXf f = ClassFeatures(6000, 128, 6, 0.05f, 2);
  FeatureFieldOptions o;
  o.max_channels = 16;
  const FeatureField field = PrepareFeatureField(f, o);
  ASSERT_TRUE(field.projected());
  EXPECT_EQ(field.dim(), 16);
  EXPECT_EQ(field.input_dim, 128);
  EXPECT_GT(field.kept_variance, 0.9);
  EXPECT_LT(field.kept_variance, 1.0);
  const Eigen::MatrixXf gram = field.basis.transpose() * field.basis;
  EXPECT_LT((gram - Eigen::MatrixXf::Identity(16, 16)).cwiseAbs().maxCoeff(), 1e-5f);
  // Cosines between rows (one per class) survive the projection (the little noise mostly does not).
  for (int a = 0; a < 6; ++a)
    for (int b = 0; b < 6; ++b) {
      const Eigen::RowVectorXf full_a = f.row(a).normalized() - field.mean.transpose();
      const Eigen::RowVectorXf full_b = f.row(b).normalized() - field.mean.transpose();
      EXPECT_NEAR(Cosine(field.channels.row(a), field.channels.row(b)), Cosine(full_a, full_b), 0.05) << a << b;
    }
  // The default keeps up to kMaxFeatureChannels.
  EXPECT_EQ(PrepareFeatureField(f).dim(), kMaxFeatureChannels);
}

TEST(FeatureField, ThreadCountDoesNotChangeIt) {
  const RowMatXf f = ClassFeatures(9000, 96, 5, 0.3f, 3);
  FeatureFieldOptions one, two;
  one.num_threads = 1;
  two.num_threads = 2;
  one.max_channels = two.max_channels = 24;
  const FeatureField a = PrepareFeatureField(f, one), b = PrepareFeatureField(f, two);
  EXPECT_TRUE(a.channels == b.channels);
  EXPECT_TRUE(a.basis == b.basis);
}

TEST(FeatureField, BadInputThrows) {
  EXPECT_THROW(PrepareFeatureField(RowMatXf(10, 0)), Error);
  EXPECT_THROW(PrepareFeatureField(RowMatXf(0, 4)), Error);
  FeatureFieldOptions o;
  o.max_channels = kMaxFeatureChannels + 1;
  EXPECT_THROW(PrepareFeatureField(ClassFeatures(10, 4, 2, 0.1f, 4), o), Error);
  o.max_channels = 0;
  EXPECT_THROW(o.Check(), Error);
}

}  // namespace
}  // namespace al
