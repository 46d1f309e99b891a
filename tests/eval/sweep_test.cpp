// Sweep library (al/refine/sweep.hpp): grid parsing, point order, shard partition, the tolerant
// results.jsonl reader, canonical order, manifests.
#include "al/refine/sweep.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>

#include "al/core/error.hpp"
#include "al/fixtures/synth.hpp"
#include "al/graph/graph.hpp"
#include "test_data.hpp"

namespace al {
namespace {

namespace fs = std::filesystem;

RefineOptions Base() {
  RefineOptions o;
  o.graph.k = 10;
  o.graph.delta = 0.8;
  o.solver = "bk";
  return o;
}

TEST(SweepGrid, ParsesAxesAndFillsTheRestFromTheBase) {
  const SweepGrid g = ParseSweepGrid("k=4,6,10;delta=0.8,1.0;lambda=0.5,1,2;solver=bk,cp", Base());
  EXPECT_EQ(g.k, (std::vector<int>{4, 6, 10}));
  EXPECT_EQ(g.delta, (std::vector<double>{0.8, 1.0}));
  EXPECT_EQ(g.lambda, (std::vector<double>{0.5, 1, 2}));
  EXPECT_EQ(g.solver, (std::vector<std::string>{"bk", "cp"}));
  EXPECT_EQ(g.hops, (std::vector<int>{1}));
  EXPECT_EQ(g.threshold, (std::vector<std::string>{"0.5"}));
  EXPECT_EQ(g.size(), 36u);
  const SweepGrid d = ParseSweepGrid(" k = 4, 4 ;threshold=percentile:95;", Base());
  EXPECT_EQ(d.k, (std::vector<int>{4}));  // duplicates dropped
  EXPECT_EQ(d.threshold, (std::vector<std::string>{"percentile:95"}));
  EXPECT_EQ(d.solver, (std::vector<std::string>{"bk"}));
  EXPECT_EQ(d.segment_share, (std::vector<double>{0.0}));  // the base decision's (rule off)
  EXPECT_EQ(ParseSweepGrid("segment_share=0,0.5", Base()).size(), 2u);
}

TEST(SweepGrid, RejectsBadGrids) {
  for (const char* bad : {"k=", "k=4;k=6", "kk=1", "k=0", "k=2.5", "delta=x", "solver=nope", "lambda=-1",
                          "k", "threshold=percentile:x", "hops=0", "segment_share=1.5"}) {
    try {
      ParseSweepGrid(bad, Base());
      ADD_FAILURE() << "accepted " << bad;
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ExitCode::kUsage) << bad;
    }
  }
}

TEST(SweepGrid, PointsSharingAGraphAreConsecutive) {
  const auto points = EnumeratePoints(ParseSweepGrid("k=4,6;delta=0.8,1;lambda=0.5,2;solver=bk,cp", Base()));
  ASSERT_EQ(points.size(), 16u);
  std::size_t changes = 0;
  for (std::size_t i = 1; i < points.size(); ++i) changes += !SameGraph(points[i - 1], points[i]);
  EXPECT_EQ(changes, 3u);  // 4 graphs, each built once
  std::set<std::string> ids;
  for (const auto& p : points) ids.insert(PointId("s", p));
  EXPECT_EQ(ids.size(), points.size());
  EXPECT_EQ(PointId("s", points[0]),
            "s|k=4|delta=0.8|hops=1|radius_scale=1.0|lambda=0.5|solver=bk|threshold=0.5|segment_share=0.0");
}

TEST(SweepShard, ParsesAndPartitionsContiguously) {
  EXPECT_EQ(ParseShard("2/8").index, 2u);
  EXPECT_EQ(ParseShard("2/8").count, 8u);
  for (const char* bad : {"8/8", "1", "a/2", "-1/2", "1/0", "1/2/3", ""}) EXPECT_THROW(ParseShard(bad), Error) << bad;
  for (std::size_t total : {0u, 1u, 5u, 36u, 1000u})
    for (std::size_t n : {1u, 3u, 7u, 40u}) {
      std::size_t next = 0, lo = SIZE_MAX, hi = 0;
      for (std::size_t i = 0; i < n; ++i) {
        const auto [b, e] = ShardRange(total, {i, n});
        EXPECT_EQ(b, next);  // contiguous, in order, no gap or overlap
        next = e;
        lo = std::min(lo, e - b);
        hi = std::max(hi, e - b);
      }
      EXPECT_EQ(next, total);
      EXPECT_LE(hi - lo, 1u) << total << " / " << n;
    }
}

void Write(const fs::path& p, const std::string& text) {
  std::ofstream(p, std::ios::binary) << text;
}

TEST(SweepJsonl, ToleratesOnlyATruncatedLastLine) {
  const fs::path dir = test::TempDir();
  const fs::path p = dir / "results.jsonl";
  EXPECT_TRUE(ReadResultsJsonl((dir / "missing.jsonl").string()).records.empty());
  const std::string a = R"({"id":"a","x":1})", b = R"({"id":"b","x":2})";
  Write(p, a + "\n" + b + "\n" + R"({"id":"c","x)");
  JsonlContents c = ReadResultsJsonl(p.string());
  ASSERT_EQ(c.records.size(), 2u);
  EXPECT_TRUE(c.truncated_tail);
  EXPECT_EQ(c.good_bytes, a.size() + b.size() + 2);
  Write(p, a + "\n" + b);  // complete record without its newline: kept
  c = ReadResultsJsonl(p.string());
  EXPECT_EQ(c.records.size(), 2u);
  EXPECT_FALSE(c.truncated_tail);
  Write(p, a + "\n{broken\n" + b + "\n");  // damage in the middle is not a killed writer
  EXPECT_THROW(ReadResultsJsonl(p.string()), Error);
  Write(p, a + "\n[1,2]\n");  // valid JSON but not a record
  EXPECT_THROW(ReadResultsJsonl(p.string()), Error);
}

TEST(SweepRecords, CanonicalOrderAndTimingFreeView) {
  auto rec = [](const std::string& scene, int k, double lambda, const std::string& solver) {
    return nlohmann::json{{"id", scene + std::to_string(k) + solver}, {"scene", scene},
                          {"params", {{"k", k}, {"delta", 0.8}, {"hops", 1}, {"radius_scale", 1.0},
                                      {"lambda", lambda}, {"solver", solver}, {"threshold", "0.5"}}},
                          {"seconds", {{"solve", 0.1}}}, {"run", {{"graph_reused", true}}}};
  };
  std::vector<nlohmann::json> r = {rec("b", 4, 1, "bk"), rec("a", 10, 1, "cp"), rec("a", 6, 2, "bk"),
                                   rec("a", 6, 0.5, "cp")};
  SortRecords(r);
  EXPECT_EQ(r[0]["params"]["k"], 6);  // k numerically (6 < 10), then lambda
  EXPECT_EQ(r[0]["params"]["lambda"], 0.5);
  EXPECT_EQ(r[2]["params"]["k"], 10);
  EXPECT_EQ(r[3]["scene"], "b");
  const nlohmann::json t = RecordWithoutTimings(r[0]);
  EXPECT_FALSE(t.contains("seconds"));
  EXPECT_FALSE(t.contains("run"));
  EXPECT_TRUE(t.contains("params"));
  const std::string csv = ResultsCsv(r);
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 5);
  EXPECT_EQ(csv.rfind("id,scene,k,", 0), 0u);
}

TEST(SweepManifest, ResolvesRelativePathsAndRejectsBadEntries) {
  const fs::path dir = test::TempDir();
  Write(dir / "m.json", R"([{"name": "a", "scene": "s/scene.ply", "removed": "/abs/r.npy", "method": "fgs",
                             "labels": "s/labels.npy", "object_id": 3, "cameras": "s/cameras.json"}])");
  const auto scenes = ReadSweepManifest((dir / "m.json").string(), Base());
  ASSERT_EQ(scenes.size(), 1u);
  EXPECT_EQ(scenes[0].options.scene, (dir / "s/scene.ply").string());
  EXPECT_EQ(scenes[0].options.removed, "/abs/r.npy");
  EXPECT_EQ(scenes[0].options.method, "fgs");
  EXPECT_EQ(scenes[0].options.object_id.value_or(-1), 3);
  EXPECT_EQ(scenes[0].options.graph.k, 10);  // from the base
  EXPECT_EQ(scenes[0].cameras, (dir / "s/cameras.json").string());
  for (const char* bad : {R"([])", R"({"name": "a"})", R"([{"name": "a", "scene": "x"}])",
                          R"([{"name": "a", "scene": "x", "removed": "y", "colour": 1}])",
                          R"([{"name": "a", "scene": "x", "removed": "y"}, {"name": "a", "scene": "x", "removed": "y"}])",
                          R"([{"name": "a|b", "scene": "x", "removed": "y"}])", "[not json"}) {
    Write(dir / "bad.json", bad);
    EXPECT_THROW(ReadSweepManifest((dir / "bad.json").string(), Base()), Error) << bad;
  }
  EXPECT_THROW(ReadSweepManifest((dir / "none.json").string(), Base()), Error);
}

// The sweep builds each graph at λ = 1 and rescales the weights per λ instead of rebuilding; that
// is only valid if λ changes nothing but the weights, by exactly the factor.
TEST(SweepLambda, RescalingEqualsRebuilding) {
  fixtures::SynthOptions so;
  so.preset = "counter";
  so.num_gaussians = 6000;
  so.num_views = 1;
  so.width = 16;
  so.height = 12;
  so.run_simulators = false;
  so.compute_masks = false;
  const fixtures::SynthScene synth = fixtures::Synthesize(so);
  std::vector<bool> removed(synth.labels.size());
  for (std::size_t i = 0; i < removed.size(); ++i) removed[i] = synth.labels[i] == synth.target_id && i % 3 != 0;
  GraphOptions go;
  go.lambda = 1.0;
  const GraphResult unit = BuildRefineGraph(synth.scene, synth.scene.features, removed, go);
  ASSERT_GT(unit.stats.edges, 100u);
  for (double lambda : {0.5, 2.0, 0.3, 1.7}) {
    go.lambda = lambda;
    const GraphResult g = BuildRefineGraph(synth.scene, synth.scene.features, removed, go);
    ASSERT_EQ(g.problem.first_edge, unit.problem.first_edge) << lambda;
    ASSERT_EQ(g.problem.adj_vertices, unit.problem.adj_vertices) << lambda;
    EXPECT_EQ(g.stats.sigma_x, unit.stats.sigma_x);
    const bool power_of_two = lambda == 0.5 || lambda == 2.0;
    for (std::size_t e = 0; e < g.problem.edge_weights.size(); ++e) {
      const double rescaled = unit.problem.edge_weights[e] * lambda;
      if (power_of_two) ASSERT_EQ(g.problem.edge_weights[e], rescaled) << lambda << " edge " << e;
      else ASSERT_NEAR(g.problem.edge_weights[e], rescaled, 4e-16 * std::abs(rescaled)) << lambda << " edge " << e;
    }
  }
}

}  // namespace
}  // namespace al
