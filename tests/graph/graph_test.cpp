// Properties of the refinement graph: stored once, no self loops, the gate, the weights, the
// edge set = brute-force kNN with the index tie rule, invariance to input order, to a global
// scale and to the thread count; zero-norm features, non-finite Gaussians, empty sets.
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <random>
#include <set>

#include <gtest/gtest.h>

#include "al/core/error.hpp"
#include "al/graph/candidates.hpp"
#include "al/graph/graph.hpp"
#include "graph_test_util.hpp"

namespace {

using EdgeMap = std::map<std::pair<std::int64_t, std::int64_t>, double>;  // scene ids -> weight

EdgeMap Edges(const al::RefineProblem& p) {
  EdgeMap m;
  for (std::size_t u = 0; u < p.num_nodes(); ++u)
    for (auto e = p.first_edge[u]; e < p.first_edge[u + 1]; ++e) {
      auto a = p.node_ids[u], b = p.node_ids[p.adj_vertices[e]];
      m[{std::min(a, b), std::max(a, b)}] = p.edge_weights[e];
    }
  return m;
}

void ExpectSameGraph(const EdgeMap& a, const EdgeMap& b, double rel) {
  ASSERT_EQ(a.size(), b.size());
  for (auto ia = a.begin(), ib = b.begin(); ia != a.end(); ++ia, ++ib) {
    ASSERT_EQ(ia->first, ib->first);
    EXPECT_NEAR(ia->second, ib->second, rel * std::abs(ia->second));
  }
}

TEST(Graph, StructureGateWeightsAndBruteForceKnn) {
  auto g = al::test::MakeGraphScene(3000, 11);
  al::GraphOptions o;
  o.k = 6;
  o.delta = 0.9;
  const auto r = al::BuildRefineGraph(g.scene, g.features, g.removed, o);
  const auto& p = r.problem;
  ASSERT_GT(p.num_nodes(), 100u);
  ASSERT_GT(p.num_edges(), 100u);
  EXPECT_EQ(p.first_edge.size(), p.num_nodes() + 1);
  EXPECT_TRUE(std::is_sorted(p.node_ids.begin(), p.node_ids.end()));
  for (std::size_t u = 0; u < p.num_nodes(); ++u) {
    // The feature prior (weight 1/2) can make a label neutral, never flip it on its own.
    if (g.removed[p.node_ids[u]]) {
      EXPECT_GE(p.y_remove[u], 0.5);
      EXPECT_LE(p.y_remove[u], 1.0);
    } else {
      EXPECT_GE(p.y_remove[u], 0.0);
      EXPECT_LE(p.y_remove[u], 0.5);
    }
    for (auto e = p.first_edge[u]; e < p.first_edge[u + 1]; ++e) {
      EXPECT_GT(p.adj_vertices[e], static_cast<std::int32_t>(u));  // no self loop, stored once
      if (e > p.first_edge[u]) {
        EXPECT_GT(p.adj_vertices[e], p.adj_vertices[e - 1]);
      }
    }
  }
  // Brute-force kNN among nodes (FLANN's float distance, ties by smaller index), then gate/weights.
  const std::size_t V = p.num_nodes();
  auto fd = [&](std::size_t u, std::size_t v) {
    float s = 0;
    for (int a = 0; a < 3; ++a) {
      const float d = g.scene.means(p.node_ids[u], a) - g.scene.means(p.node_ids[v], a);
      s += d * d;
    }
    return s;
  };
  std::set<std::pair<std::size_t, std::size_t>> knn_pairs;
  std::vector<double> nonzero;
  for (std::size_t u = 0; u < V; ++u) {
    std::vector<std::size_t> idx;
    for (std::size_t v = 0; v < V; ++v)
      if (v != u) idx.push_back(v);
    std::partial_sort(idx.begin(), idx.begin() + o.k, idx.end(), [&](std::size_t a, std::size_t b) {
      const float da = fd(u, a), db = fd(u, b);
      return da < db || (da == db && a < b);
    });
    for (int c = 0; c < o.k; ++c) {
      knn_pairs.insert({std::min(u, idx[c]), std::max(u, idx[c])});
      const double d = std::sqrt(double(fd(u, idx[c])));
      if (d > 0) nonzero.push_back(d);
    }
  }
  EXPECT_EQ(r.stats.edges_knn, knn_pairs.size());
  std::sort(nonzero.begin(), nonzero.end());
  const std::size_t h = nonzero.size() / 2;
  const double sigma_x = nonzero.size() % 2 ? nonzero[h] : 0.5 * (nonzero[h - 1] + nonzero[h]);
  EXPECT_NEAR(r.stats.sigma_x, sigma_x, 1e-5 * sigma_x);
  // Centred features: unit rows minus the scene mean of unit rows (all 3000 rows: below the
  // sampling stride), normalised again.
  Eigen::VectorXd mean = Eigen::VectorXd::Zero(g.features.cols());
  for (Eigen::Index i = 0; i < g.features.rows(); ++i)
    mean += g.features.row(i).cast<double>().transpose().normalized();
  mean /= double(g.features.rows());
  auto centred = [&](std::int64_t id) {
    return Eigen::VectorXd(g.features.row(id).cast<double>().transpose().normalized() - mean).normalized();
  };
  EdgeMap expected;
  for (auto [u, v] : knn_pairs) {
    const double df = (centred(p.node_ids[u]) - centred(p.node_ids[v])).norm();
    if (df > o.delta) continue;
    double dx2 = 0;
    for (int a = 0; a < 3; ++a) {
      const double d = double(g.scene.means(p.node_ids[u], a)) - g.scene.means(p.node_ids[v], a);
      dx2 += d * d;
    }
    expected[{p.node_ids[u], p.node_ids[v]}] =
        std::exp(-df * df / (o.delta * o.delta)) * std::exp(-dx2 / (sigma_x * sigma_x));
  }
  ExpectSameGraph(Edges(p), expected, 1e-5);
  EXPECT_DOUBLE_EQ(r.stats.sigma_f, o.delta);
  EXPECT_EQ(r.stats.edges, p.num_edges());
  EXPECT_LT(r.stats.edges, r.stats.edges_knn);  // the gate removed something
  EXPECT_TRUE(r.stats.centred);

  // SPEC §4 literally (no centring, no prior): y is the mask, the gate uses the unit rows.
  al::GraphOptions literal = o;
  literal.centre = al::Centring::kOff;
  literal.prior.weight = 0.0;
  const auto lit = al::BuildRefineGraph(g.scene, g.features, g.removed, literal).problem;
  for (std::size_t u = 0; u < lit.num_nodes(); ++u)
    EXPECT_EQ(lit.y_remove[u], g.removed[lit.node_ids[u]] ? 1.0 : 0.0);
  for (auto [e, w] : Edges(lit)) {
    const double df = (g.features.row(e.first).cast<double>().normalized() -
                       g.features.row(e.second).cast<double>().normalized()).norm();
    EXPECT_LE(df, o.delta + 1e-6);
  }
}

// Mean of the unit rows' norm: what kShared compares with kSharedComponentNorm.
double CommonComponent(const al::RowMatXf& f) {
  Eigen::VectorXd mean = Eigen::VectorXd::Zero(f.cols());
  for (Eigen::Index i = 0; i < f.rows(); ++i) mean += f.row(i).cast<double>().transpose().normalized();
  return (mean / double(f.rows())).norm();
}

// kShared centres only a field whose rows share a strong component (CLIP-like); on any other
// field it builds exactly the uncentred graph.
TEST(Graph, SharedCentringFollowsTheCommonComponent) {
  auto g = al::test::MakeGraphScene(3000, 11);
  al::GraphOptions o;
  o.k = 6;
  const double weak = CommonComponent(g.features);
  ASSERT_LT(weak, al::kSharedComponentNorm);  // the fixture's field has no strong shared part
  o.centre = al::Centring::kShared;
  const auto shared = al::BuildRefineGraph(g.scene, g.features, g.removed, o);
  o.centre = al::Centring::kOff;
  const auto off = al::BuildRefineGraph(g.scene, g.features, g.removed, o);
  EXPECT_FALSE(shared.stats.centred);
  EXPECT_NEAR(shared.stats.common_component, weak, 1e-9);
  ExpectSameGraph(Edges(shared.problem), Edges(off.problem), 0.0);
  EXPECT_EQ(shared.problem.y_remove, off.problem.y_remove);

  // The same field plus one direction every row shares (as distilled CLIP features have).
  al::RowMatXf clip = g.features;
  for (Eigen::Index i = 0; i < clip.rows(); ++i) {
    clip.row(i) = clip.row(i).normalized();
    clip(i, 0) += 3.0f;
  }
  ASSERT_GE(CommonComponent(clip), al::kSharedComponentNorm);
  o.centre = al::Centring::kShared;
  const auto clip_shared = al::BuildRefineGraph(g.scene, clip, g.removed, o);
  o.centre = al::Centring::kOn;
  const auto clip_on = al::BuildRefineGraph(g.scene, clip, g.removed, o);
  EXPECT_TRUE(clip_shared.stats.centred);
  ExpectSameGraph(Edges(clip_shared.problem), Edges(clip_on.problem), 0.0);
  o.centre = al::Centring::kOff;  // uncentred, the shared part passes more edges through the gate
  EXPECT_GT(al::BuildRefineGraph(g.scene, clip, g.removed, o).stats.edges, clip_on.stats.edges);
}

TEST(Graph, InvariantToPermutationScaleAndThreads) {
  auto g = al::test::MakeGraphScene(4000, 5, 8, 2, 0);  // no duplicates: no distance ties
  al::GraphOptions o;
  const EdgeMap base = Edges(al::BuildRefineGraph(g.scene, g.features, g.removed, o).problem);
  ASSERT_GT(base.size(), 500u);

  // Permutation of the input order.
  const int n = static_cast<int>(g.scene.size());
  std::vector<int> perm(n);
  std::iota(perm.begin(), perm.end(), 0);
  std::shuffle(perm.begin(), perm.end(), std::mt19937(3));
  al::test::GraphScene q = g;
  for (int i = 0; i < n; ++i) {
    q.scene.means.row(i) = g.scene.means.row(perm[i]);
    q.scene.log_scales.row(i) = g.scene.log_scales.row(perm[i]);
    q.features.row(i) = g.features.row(perm[i]);
    q.removed[i] = g.removed[perm[i]];
  }
  EdgeMap permuted;
  for (auto [e, w] : Edges(al::BuildRefineGraph(q.scene, q.features, q.removed, o).problem))
    permuted[{std::min(perm[e.first], perm[e.second]), std::max(perm[e.first], perm[e.second])}] = w;
  ExpectSameGraph(base, permuted, 1e-12);

  // Global scale of the coordinates (radii scale with them).
  for (double s : {1e-6, 1e-3, 1e3, 1e6}) {
    al::test::GraphScene t = g;
    t.scene.means *= static_cast<float>(s);
    t.scene.log_scales.array() += static_cast<float>(std::log(s));
    ExpectSameGraph(base, Edges(al::BuildRefineGraph(t.scene, t.features, t.removed, o).problem), 1e-4);
  }

  // Global scale of the features (rows are normalised): tiny and huge rows whose squared norms
  // leave float's range give the same graph.
  for (float s : {1e-30f, 1e-3f, 1e3f, 1e30f}) {
    al::test::GraphScene t = g;
    t.features *= s;
    ExpectSameGraph(base, Edges(al::BuildRefineGraph(t.scene, t.features, t.removed, o).problem), 1e-4);
  }

  // Thread count: bit-identical.
  const int saved = omp_get_max_threads();
  omp_set_num_threads(1);
  const auto one = al::BuildRefineGraph(g.scene, g.features, g.removed, o).problem;
  omp_set_num_threads(2);
  const auto two = al::BuildRefineGraph(g.scene, g.features, g.removed, o).problem;
  omp_set_num_threads(saved);
  EXPECT_EQ(one.adj_vertices, two.adj_vertices);
  EXPECT_EQ(one.edge_weights, two.edge_weights);
  EXPECT_EQ(one.first_edge, two.first_edge);
}

TEST(Graph, DuplicatesAreNeighboursAtZeroAndTiesGoToSmallerIndex) {
  // Node 0 removed; 1..4 are exact duplicates of each other at distance 1; k = 2 must pick 1, 2.
  al::test::GraphScene g = al::test::MakeGraphScene(5, 1, 2, 0, 0);
  for (int i = 0; i < 5; ++i) {
    g.scene.means.row(i) << (i == 0 ? 0.f : 1.f), 0.f, 0.f;
    g.scene.log_scales.row(i).setConstant(std::log(2.0f));
    g.features.row(i) << 1.f, 0.f;
    g.removed[i] = i == 0;
  }
  al::GraphOptions o;
  o.k = 2;
  const auto p = al::BuildRefineGraph(g.scene, g.features, g.removed, o).problem;
  const EdgeMap m = Edges(p);
  ASSERT_EQ(p.num_nodes(), 5u);
  // 0's two nearest: 1, 2 (tie by index). 1's: 2, 3 (distance 0). 2's: 1, 3. 3's: 1, 2. 4's: 1, 2.
  std::set<std::pair<std::int64_t, std::int64_t>> got, want{{0, 1}, {0, 2}, {1, 2}, {1, 3}, {2, 3}, {1, 4}, {2, 4}};
  for (auto& [e, w] : m) got.insert(e);
  EXPECT_EQ(got, want);
}

TEST(Graph, ZeroNormFeaturesAndNonFiniteGaussians) {
  auto g = al::test::MakeGraphScene(2000, 8);
  std::vector<std::int64_t> zero, nan_ids;
  for (int i = 0; i < 2000; ++i) {
    if (g.removed[i] && zero.size() < 5) { g.features.row(i).setZero(); zero.push_back(i); }
    else if (g.removed[i] && nan_ids.size() < 3) { g.scene.means(i, 1) = NAN; nan_ids.push_back(i); }
  }
  g.features(1999, 0) = INFINITY;
  const auto r = al::BuildRefineGraph(g.scene, g.features, g.removed, {});
  EXPECT_EQ(r.stats.zero_norm_features, zero.size());
  EXPECT_EQ(r.stats.excluded_nonfinite, nan_ids.size() + 1);
  const auto& p = r.problem;
  for (auto id : nan_ids) EXPECT_FALSE(std::binary_search(p.node_ids.begin(), p.node_ids.end(), id));
  EXPECT_FALSE(std::binary_search(p.node_ids.begin(), p.node_ids.end(), 1999));
  for (auto [e, w] : Edges(p))
    for (auto id : zero) EXPECT_TRUE(e.first != id && e.second != id);
  for (auto id : zero) EXPECT_TRUE(std::binary_search(p.node_ids.begin(), p.node_ids.end(), id));
  EXPECT_GE(r.stats.isolated, zero.size());
  EXPECT_FALSE(r.warnings.empty());
}

// A row whose undecoded f_rest held a non-finite value (PlyReadOptions::sh_rest = false) is
// excluded like one with a non-finite decoded value; the other rows' graph does not change.
TEST(Graph, RowsFlaggedByTheReaderAreExcluded) {
  auto g = al::test::MakeGraphScene(2000, 9);
  const auto before = al::BuildRefineGraph(g.scene, g.features, g.removed, {});
  std::vector<std::int64_t> flagged;
  for (int i = 0; i < 2000 && flagged.size() < 4; ++i)
    if (!g.removed[i] && std::binary_search(before.problem.node_ids.begin(), before.problem.node_ids.end(), i))
      flagged.push_back(i);
  ASSERT_EQ(flagged.size(), 4u);
  g.scene.nonfinite_undecoded.assign(2000, 0);
  for (auto id : flagged) g.scene.nonfinite_undecoded[std::size_t(id)] = 1;
  const auto r = al::BuildRefineGraph(g.scene, g.features, g.removed, {});
  EXPECT_EQ(r.stats.excluded_nonfinite, before.stats.excluded_nonfinite + flagged.size());
  for (auto id : flagged) {
    EXPECT_TRUE(r.excluded[std::size_t(id)]);
    EXPECT_FALSE(std::binary_search(r.problem.node_ids.begin(), r.problem.node_ids.end(), id));
  }
  EXPECT_EQ(r.problem.node_ids.size(), before.problem.node_ids.size() - flagged.size());
}

TEST(Graph, DisconnectedEmptyAndCosineMode) {
  auto g = al::test::MakeGraphScene(1000, 9);
  // Two far-apart removed groups: at least two components.
  for (int i = 0; i < 1000; ++i) {
    g.removed[i] = i < 20 || (i >= 500 && i < 520);
    if (i >= 500) g.scene.means(i, 0) += 1000.f;
    g.scene.log_scales.row(i).setConstant(std::log(0.05f));
  }
  al::GraphOptions o;
  o.delta = 2.0;  // gate open
  const auto r = al::BuildRefineGraph(g.scene, g.features, g.removed, o);
  EXPECT_GE(r.stats.components, 2u);
  // Cosine mode: δ_cos = 1 - d²/2 gives the same graph as distance mode with d.
  al::GraphOptions a, b;
  a.delta = 0.8;
  b.delta_mode = al::DeltaMode::kCosine;
  b.delta = 1.0 - 0.8 * 0.8 / 2.0;
  const auto ra = al::BuildRefineGraph(g.scene, g.features, g.removed, a);
  const auto rb = al::BuildRefineGraph(g.scene, g.features, g.removed, b);
  EXPECT_NEAR(rb.stats.gate_distance, 0.8, 1e-12);
  ExpectSameGraph(Edges(ra.problem), Edges(rb.problem), 1e-9);
  // Empty removal set: empty graph.
  std::vector<bool> none(1000, false);
  const auto e = al::BuildRefineGraph(g.scene, g.features, none, o);
  EXPECT_EQ(e.problem.num_nodes(), 0u);
  EXPECT_EQ(e.stats.edges, 0u);
  // Bad sizes are errors, not crashes.
  EXPECT_THROW(al::BuildRefineGraph(g.scene, g.features, std::vector<bool>(3), o), al::Error);
}

TEST(Graph, ColourFallbackUsesRawDistance) {
  auto g = al::test::MakeGraphScene(1500, 4);
  const al::RowMatXf rgb = al::ColourFeatures(g.scene);
  ASSERT_EQ(rgb.cols(), 3);
  EXPECT_NEAR(rgb(0, 0), 0.5 + 0.28209479177387814 * g.scene.sh(0, 0), 1e-6);
  al::GraphOptions o;
  o.normalize_features = false;
  o.delta = 0.3;
  const auto r = al::BuildRefineGraph(g.scene, rgb, g.removed, o);
  for (auto [e, w] : Edges(r.problem)) {
    const double d = (rgb.row(e.first) - rgb.row(e.second)).cast<double>().norm();
    EXPECT_LE(d, 0.3 + 1e-9);
  }
  EXPECT_EQ(r.stats.zero_norm_features, 0u);
}

// o.Check() throws al::Error whose message contains `message`.
void ExpectCheckRefuses(const al::GraphOptions& o, const std::string& message) {
  try {
    o.Check();
    ADD_FAILURE() << "accepted; expected: " << message;
  } catch (const al::Error& e) {
    EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
  }
}

// --prior-weight: auto (the preset's) or a number; out of [0, 1] or not a number is a usage error
// that says what is accepted.
TEST(Graph, PriorWeightTakesAutoOrAWeight) {
  const auto& table = al::GraphOptions::Table();
  al::GraphOptions o;
  table.SetText(o, "prior_weight", "0.3");
  EXPECT_EQ(o.prior.weight, 0.3);
  table.SetText(o, "prior_weight", "auto");
  EXPECT_FALSE(o.prior.weight.has_value());
  table.SetText(o, "prior_weight", "1.5");
  ExpectCheckRefuses(o, "'prior_weight' = 1.5 must be auto|[0, 1]");
  EXPECT_THROW(table.SetText(o, "prior_weight", "half"), al::Error);
}

// --feature-width W widens the feature kernel, not the gate: the same edges, and without the
// spatial factor each weight exp(-d_f^2 / (W delta)^2) is the width-1 weight to the power 1/W^2.
TEST(Graph, FeatureWidthWidensTheKernelNotTheGate) {
  auto g = al::test::MakeGraphScene(3000, 11);
  al::GraphOptions o;
  o.k = 6;
  o.delta = 0.9;
  o.spatial = false;
  const auto narrow = al::BuildRefineGraph(g.scene, g.features, g.removed, o);
  o.feature_width = 2.0;
  const auto wide = al::BuildRefineGraph(g.scene, g.features, g.removed, o);
  EXPECT_DOUBLE_EQ(narrow.stats.sigma_f, 0.9);
  EXPECT_DOUBLE_EQ(wide.stats.sigma_f, 1.8);
  EXPECT_EQ(wide.stats.gate_distance, narrow.stats.gate_distance);
  EdgeMap expected;
  for (const auto& [pair, w] : Edges(narrow.problem)) expected[pair] = std::pow(w, 0.25);
  ASSERT_GT(expected.size(), 100u);
  ExpectSameGraph(Edges(wide.problem), expected, 1e-9);
}

// --feature-width: auto (the preset's; a direct caller gets 1) or a number > 0.
TEST(Graph, FeatureWidthTakesAutoOrAWidth) {
  const auto& table = al::GraphOptions::Table();
  al::GraphOptions o;
  EXPECT_EQ(o.FeatureWidth(), 1.0);
  EXPECT_EQ(table.ToJson(o)["feature_width"], "auto");
  table.SetText(o, "feature_width", "2");
  EXPECT_EQ(o.FeatureWidth(), 2.0);
  table.SetText(o, "feature_width", "0");
  ExpectCheckRefuses(o, "'feature_width' = 0 must be auto|> 0");
  EXPECT_THROW(table.SetText(o, "feature_width", "wide"), al::Error);
}

// --lambda: auto (the preset's for the solver; a direct caller gets 1) or a number >= 0.
TEST(Graph, LambdaTakesAutoOrAScale) {
  const auto& table = al::GraphOptions::Table();
  al::GraphOptions o;
  EXPECT_FALSE(o.lambda.has_value());
  EXPECT_EQ(o.Lambda(), 1.0);
  EXPECT_EQ(table.ToJson(o)["lambda"], "auto");
  table.SetText(o, "lambda", "2");
  EXPECT_EQ(o.Lambda(), 2.0);
  EXPECT_EQ(table.ToJson(o)["lambda"], 2.0);
  table.SetText(o, "lambda", "auto");
  EXPECT_FALSE(o.lambda.has_value());
  table.SetText(o, "lambda", "-1");
  ExpectCheckRefuses(o, "'lambda' = -1 must be auto|>= 0");
  EXPECT_THROW(table.SetText(o, "lambda", "heavy"), al::Error);
  EXPECT_THROW(table.SetText(o, "lambda", "inf"), al::Error);
}

}  // namespace
