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
  EXPECT_EQ(g.lambda, (std::vector<std::optional<double>>{0.5, 1, 2}));
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
  // λ auto (the base's, unless the grid names it) stays auto in the grid: each scene's preset
  // resolves it per solver; "auto" twice is one value.
  EXPECT_EQ(d.lambda, (std::vector<std::optional<double>>{std::nullopt}));
  EXPECT_EQ(ParseSweepGrid("lambda=auto,1.5,auto", Base()).lambda,
            (std::vector<std::optional<double>>{std::nullopt, 1.5}));
}

TEST(SweepGrid, RejectsBadGrids) {
  for (const char* bad : {"k=", "k=4;k=6", "kk=1", "k=0", "k=2.5", "delta=x", "solver=nope", "lambda=-1",
                          "k", "threshold=percentile:x", "hops=-1", "segment_share=1.5", "threshold=-1",
                          "radius_scale=0", "k=1001"}) {
    try {
      ParseSweepGrid(bad, Base());
      ADD_FAILURE() << "accepted " << bad;
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ExitCode::kUsage) << bad;
    }
  }
}

TEST(SweepGrid, AxesTakeTheRangesAndWordsOfTheOptionsTables) {
  // hops = 0 (candidates = the removed set) is a valid graph option, so it is a valid grid value.
  EXPECT_EQ(ParseSweepGrid("hops=0,2", Base()).hops, (std::vector<int>{0, 2}));
  // A bad value gets the table's message, the one `--k 0` gets on the command line.
  GraphOptions g;
  g.k = 0;
  std::string table_message, grid_message;
  try {
    g.Check();
  } catch (const Error& e) {
    table_message = e.what();
  }
  try {
    ParseSweepGrid("k=0", Base());
  } catch (const Error& e) {
    grid_message = e.what();
  }
  EXPECT_NE(table_message.find("'k' = 0 must be in [1, 1000]"), std::string::npos) << table_message;
  EXPECT_EQ(grid_message, "--grid: " + table_message);
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

// ---- shard.json and merge's checks

SweepOptions TwoPointSweep(const fs::path& dir, const Shard& shard) {
  SweepOptions o;
  SweepScene scene;
  scene.name = "s";
  scene.options = Base();
  scene.options.scene = (dir / "scene.ply").string();  // identity of an absent file: its path
  o.scenes = {scene};
  o.grid = ParseSweepGrid("k=4,6;lambda=1,2", Base());
  o.shard = shard;
  return o;
}

// A shard folder as RunSweep leaves it, with fake records for the ids of `jobs` of its slice.
void WriteShardFolder(const fs::path& dir, const ShardInfo& info, const std::vector<std::size_t>& jobs) {
  fs::create_directories(dir);
  WriteShardInfo(dir.string(), info);
  const std::vector<std::string> ids = SweepPointIds(info, 0, info.points_total);
  std::ofstream out(dir / "results.jsonl");
  for (std::size_t j : jobs) out << nlohmann::json{{"id", ids[j]}, {"scene", "s"}, {"status", "ok"}}.dump() << "\n";
}

TEST(SweepShardInfo, GridRoundTripsAndIdsFollowTheSlices) {
  const fs::path dir = test::TempDir();
  const SweepOptions o = TwoPointSweep(dir, {1, 3});
  const ShardInfo info = MakeShardInfo(o);
  EXPECT_EQ(info.points_total, 4u);
  EXPECT_EQ(std::make_pair(info.first, info.end), ShardRange(4, {1, 3}));
  EXPECT_EQ(GridFromJson(info.grid).size(), o.grid.size());
  const auto points = EnumeratePoints(o.grid);
  const std::vector<std::string> ids = SweepPointIds(info, 0, 4);
  ASSERT_EQ(ids.size(), 4u);
  for (std::size_t j = 0; j < 4; ++j) EXPECT_EQ(ids[j], PointId("s", points[j]));
  WriteShardInfo(dir.string(), info);
  const ShardInfo back = ReadShardInfo(dir.string());
  EXPECT_EQ(back.ToJson(), info.ToJson());
  EXPECT_EQ(info.binary["sha256"].get<std::string>().size(), 64u);  // this test binary's hash
}

TEST(SweepShardInfo, DifferencesNameWhatDiffers) {
  const fs::path dir = test::TempDir();
  const ShardInfo a = MakeShardInfo(TwoPointSweep(dir, {0, 2}));
  EXPECT_TRUE(SweepDifferences(a, MakeShardInfo(TwoPointSweep(dir, {1, 2}))).empty());  // another slice, one sweep
  auto differs = [&](SweepOptions o, const std::string& expected) {
    const std::vector<std::string> d = SweepDifferences(a, MakeShardInfo(o));
    ASSERT_EQ(d.size(), 1u) << expected;
    EXPECT_EQ(d[0], expected);
  };
  SweepOptions o = TwoPointSweep(dir, {0, 3});
  differs(o, "shard count (2 vs 3)");
  o = TwoPointSweep(dir, {0, 2});
  o.grid = ParseSweepGrid("k=4,8;lambda=1,2", Base());
  differs(o, "grid (k: [4,6] vs [4,8])");
  o = TwoPointSweep(dir, {0, 2});
  o.scenes[0].options.graph.spatial = false;
  differs(o, "scenes ([0].flags.spatial: true vs false)");
  o = TwoPointSweep(dir, {0, 2});
  o.scenes[0].name = "t";
  differs(o, "scenes ([0].name: \"s\" vs \"t\")");
  o = TwoPointSweep(dir, {0, 2});
  o.eval_views = "v1";
  differs(o, "fixed flags (eval_views: \"all\" vs \"v1\")");
  ShardInfo other_binary = a;
  other_binary.binary["version"] = "9.9.9";
  EXPECT_EQ(SweepDifferences(a, other_binary), std::vector<std::string>{"binary (version: \"0.1.0\" vs \"9.9.9\")"});
  // A scene file that changed between shards is another sweep even under the same path.
  Write(dir / "scene.ply", "one");
  const ShardInfo before = MakeShardInfo(TwoPointSweep(dir, {0, 2}));
  Write(dir / "scene.ply", "two");
  const std::vector<std::string> d = SweepDifferences(before, MakeShardInfo(TwoPointSweep(dir, {1, 2})));
  ASSERT_EQ(d.size(), 1u);
  EXPECT_EQ(d[0].rfind("scenes ([0].inputs.scene.sha256: ", 0), 0u) << d[0];
}

TEST(SweepShardInfo, RejectsMissingOrInconsistentFiles) {
  const fs::path dir = test::TempDir();
  try {
    ReadShardInfo(dir.string());
    ADD_FAILURE() << "no shard.json accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("no shard.json"), std::string::npos);
    EXPECT_EQ(e.code(), ExitCode::kBadInput);
  }
  nlohmann::json good = MakeShardInfo(TwoPointSweep(dir, {1, 2})).ToJson();
  for (const auto& [key, value] : std::vector<std::pair<std::string, nlohmann::json>>{
           {"format", "x"}, {"points_total", 5}, {"shard_index", 2}, {"first_point", 0},
           {"points_in_shard", 3}, {"scenes", nlohmann::json::array()}, {"grid", {{"k", "four"}}}}) {
    nlohmann::json bad = good;
    bad[key] = value;
    Write(dir / "shard.json", bad.dump());
    EXPECT_THROW(ReadShardInfo(dir.string()), Error) << key;
  }
  Write(dir / "shard.json", "{not json");
  EXPECT_THROW(ReadShardInfo(dir.string()), Error);
}

TEST(SweepMerge, CountsMissingShardsAndPointsAndRefusesAnIncompleteSet) {
  const fs::path dir = test::TempDir();
  const ShardInfo s0 = MakeShardInfo(TwoPointSweep(dir, {0, 3}));  // jobs [0, 1)
  const ShardInfo s1 = MakeShardInfo(TwoPointSweep(dir, {1, 3}));  // [1, 2)
  const ShardInfo s2 = MakeShardInfo(TwoPointSweep(dir, {2, 3}));  // [2, 4)
  WriteShardFolder(dir / "a", s0, {0});
  WriteShardFolder(dir / "c", s2, {2});  // job 3 missing: killed
  MergeOptions o;
  o.shard_dirs = {(dir / "a").string(), (dir / "c").string()};
  o.out_dir = (dir / "out").string();
  MergeResult r = MergeSweeps(o);
  EXPECT_FALSE(r.complete);
  EXPECT_FALSE(r.written);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.missing_shards, std::vector<std::size_t>{1});
  EXPECT_EQ(r.incomplete_shards, (std::vector<std::size_t>{1, 2}));
  EXPECT_EQ(r.points_found, 2u);
  EXPECT_EQ(r.points_total, 4u);
  EXPECT_NE(r.BriefReport().find("incomplete shards: 1 2\n"), std::string::npos) << r.BriefReport();
  EXPECT_FALSE(fs::exists(dir / "out"));
  o.allow_partial = true;
  r = MergeSweeps(o);
  EXPECT_TRUE(r.written);
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_EQ(r.report["complete"], false);
  EXPECT_EQ(r.report["counts"]["points_missing"], 2);
  // Completed, with one foreign record (not a point of the sweep) that is left out, and shard 1
  // given twice (duplicates, no conflict).
  WriteShardFolder(dir / "b", s1, {1});
  WriteShardFolder(dir / "c", s2, {2, 3});
  std::ofstream(dir / "c" / "results.jsonl", std::ios::app) << R"({"id": "s|k=99", "scene": "s"})" << "\n";
  o = {};
  o.shard_dirs = {(dir / "c").string(), (dir / "b").string(), (dir / "a").string(), (dir / "b").string()};
  o.check_only = true;
  r = MergeSweeps(o);
  EXPECT_TRUE(r.complete);
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_EQ(r.records, 4u);
  EXPECT_EQ(r.duplicates, 1u);
  EXPECT_EQ(r.conflicts, 0u);
  EXPECT_EQ(r.foreign_records, 1u);
  EXPECT_FALSE(r.written);
  // A shard of another sweep is refused before anything is counted.
  SweepOptions other = TwoPointSweep(dir, {1, 3});
  other.grid = ParseSweepGrid("k=4,6;lambda=1,3", Base());
  WriteShardFolder(dir / "x", MakeShardInfo(other), {1});
  o.shard_dirs = {(dir / "a").string(), (dir / "x").string()};
  try {
    MergeSweeps(o);
    ADD_FAILURE() << "a shard of another grid was merged";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ExitCode::kBadInput);
    EXPECT_NE(std::string(e.what()).find("grid (lambda: [1.0,2.0] vs [1.0,3.0])"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace al
