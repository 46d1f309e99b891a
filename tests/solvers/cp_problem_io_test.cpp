// Round trip of the RefineProblem .npy export (problem_io.hpp) and rejection of corrupt exports.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "al/core/error.hpp"
#include "al/graph/problem_io.hpp"
#include "al/io/npy.hpp"
#include "al/fixtures/knn_problem.hpp"
#include "test_data.hpp"

namespace al {
namespace {

TEST(CpProblemIo, RoundTrip) {
  RefineProblem pb = fixtures::MakeKnnProblem(200, 5, 0.1, 0.25, true, 8);
  for (std::size_t v = 0; v < pb.num_nodes(); ++v) pb.node_ids[v] = 1000 + 3 * v;
  pb.node_weights[3] = 2.5;
  std::vector<double> p(pb.num_nodes());
  for (std::size_t v = 0; v < p.size(); ++v) p[v] = v / double(p.size());
  const auto dir = test::TempDir();
  ExportProblem(pb, &p, dir.string(), 0.7);
  const RefineProblem back = ImportProblem(dir.string());
  EXPECT_EQ(back.first_edge, pb.first_edge);
  EXPECT_EQ(back.adj_vertices, pb.adj_vertices);
  EXPECT_EQ(back.edge_weights, pb.edge_weights);
  EXPECT_EQ(back.y_remove, pb.y_remove);
  EXPECT_EQ(back.node_weights, pb.node_weights);
  EXPECT_EQ(back.node_ids, pb.node_ids);
  EXPECT_EQ(back.kl_smoothing, pb.kl_smoothing);
  EXPECT_EQ(ReadNpy((dir / "p.npy").string()).ToDouble(), p);
  const NpyArray y = ReadNpy((dir / "y.npy").string());
  ASSERT_EQ(y.shape, (std::vector<std::int64_t>{static_cast<std::int64_t>(pb.num_nodes()), 2}));
  EXPECT_EQ(y.ToDouble()[1], 1.0 - pb.y_remove[0]);
  std::ifstream params(dir / "params.json");
  const auto j = nlohmann::json::parse(params);
  EXPECT_EQ(j["metric"], "d1");
  EXPECT_EQ(j["lambda"], 0.7);
}

TEST(CpProblemIo, RejectsCorruptExport) {
  const RefineProblem pb = fixtures::MakeKnnProblem(50, 4, 0.1, 0.1, false, 9);
  const auto dir = test::TempDir();
  ExportProblem(pb, nullptr, dir.string());
  EXPECT_FALSE(std::filesystem::exists(dir / "p.npy"));
  std::vector<std::int64_t> adj(pb.adj_vertices.begin(), pb.adj_vertices.end());
  adj[0] = 50;  // out of range
  WriteNpy((dir / "adj_vertices.npy").string(), adj, {static_cast<std::int64_t>(adj.size())});
  EXPECT_THROW(ImportProblem(dir.string()), Error);
  EXPECT_THROW(ImportProblem((dir / "missing").string()), Error);
}

}  // namespace
}  // namespace al
