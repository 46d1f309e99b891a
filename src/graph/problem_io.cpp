#include "al/graph/problem_io.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "al/core/atomic_file.hpp"
#include "al/core/error.hpp"
#include "al/core/input_file.hpp"
#include "al/io/npy.hpp"

namespace al {

void ExportProblem(const RefineProblem& pb, const std::vector<double>* p, const std::string& dir,
                   std::optional<double> lambda) {
  namespace fs = std::filesystem;
  const std::size_t V = pb.num_nodes(), E = pb.num_edges();
  if (pb.first_edge.size() != V + 1 || pb.edge_weights.size() != E || (!pb.node_weights.empty() && pb.node_weights.size() != V) ||
      (!pb.node_ids.empty() && pb.node_ids.size() != V) || (p && p->size() != V))
    throw Error(dir + ": refine problem has inconsistent array sizes");
  EnsureDirectory(dir);
  const fs::path d(dir);
  const auto V64 = static_cast<std::int64_t>(V), E64 = static_cast<std::int64_t>(E);
  WriteNpy((d / "first_edge.npy").string(), pb.first_edge, {V64 + 1});
  WriteNpy((d / "adj_vertices.npy").string(), std::vector<std::int64_t>(pb.adj_vertices.begin(), pb.adj_vertices.end()), {E64});
  WriteNpy((d / "edge_weights.npy").string(), pb.edge_weights, {E64});
  std::vector<double> y(2 * V);
  for (std::size_t v = 0; v < V; ++v) {
    y[2 * v] = pb.y_remove[v];
    y[2 * v + 1] = 1.0 - pb.y_remove[v];
  }
  WriteNpy((d / "y.npy").string(), y, {V64, 2});
  WriteNpy((d / "node_weights.npy").string(), pb.node_weights.empty() ? std::vector<double>(V, 1.0) : pb.node_weights, {V64});
  std::vector<std::int64_t> ids = pb.node_ids;
  if (ids.empty())
    for (std::size_t v = 0; v < V; ++v) ids.push_back(static_cast<std::int64_t>(v));
  WriteNpy((d / "node_ids.npy").string(), ids, {V64});
  if (p) WriteNpy((d / "p.npy").string(), *p, {V64});
  nlohmann::json params = {{"s", pb.kl_smoothing}, {"metric", "d1"}, {"labels", {"remove", "keep"}}};
  if (lambda) params["lambda"] = *lambda;
  WriteFileAtomically(d / "params.json", params.dump(2) + "\n");
}

namespace {

NpyArray Load(const std::filesystem::path& path, std::size_t rank) {
  NpyArray a = ReadNpy(path.string());
  if (a.shape.size() != rank) throw FileError(path.string(), "expected a " + std::to_string(rank) + "-d array");
  return a;
}

}  // namespace

RefineProblem ImportProblem(const std::string& dir) {
  namespace fs = std::filesystem;
  const fs::path d(dir);
  RefineProblem pb;
  const fs::path params_path = d / "params.json";
  {
    const std::string text = ReadInputFile(params_path.string(), std::uint64_t(1) << 20);  // refuses a FIFO at once
    nlohmann::json params;
    try {
      params = nlohmann::json::parse(text);
    } catch (const std::exception& e) {
      throw FileError(params_path.string(), std::string("invalid JSON: ") + e.what());
    }
    if (!params.is_object() || !params.contains("s") || !params["s"].is_number())
      throw FileError(params_path.string(), "missing number 's'");
    pb.kl_smoothing = params["s"].get<double>();
    if (!(pb.kl_smoothing >= 0.0 && pb.kl_smoothing <= 1.0)) throw FileError(params_path.string(), "'s' must lie in [0, 1]");
    if (params.contains("metric") && params["metric"] != "d1") throw FileError(params_path.string(), "only metric d1 is supported");
  }
  const NpyArray fe = Load(d / "first_edge.npy", 1);
  pb.first_edge = fe.ToInt64();
  if (pb.first_edge.empty()) throw FileError((d / "first_edge.npy").string(), "must hold V + 1 >= 1 entries");
  const std::size_t V = pb.first_edge.size() - 1;
  const NpyArray adj = Load(d / "adj_vertices.npy", 1);
  const std::vector<std::int64_t> adj64 = adj.ToInt64();
  const std::size_t E = adj64.size();
  if (pb.first_edge[0] != 0 || pb.first_edge[V] != static_cast<std::int64_t>(E))
    throw FileError((d / "first_edge.npy").string(), "first_edge[0] must be 0 and first_edge[V] the edge count");
  for (std::size_t v = 0; v < V; ++v)
    if (pb.first_edge[v + 1] < pb.first_edge[v]) throw FileError((d / "first_edge.npy").string(), "not non-decreasing");
  for (std::int64_t a : adj64)
    if (a < 0 || a >= static_cast<std::int64_t>(V)) throw FileError((d / "adj_vertices.npy").string(), "vertex index out of range");
  pb.adj_vertices.assign(adj64.begin(), adj64.end());
  const NpyArray ew = Load(d / "edge_weights.npy", 1);
  if (!ew.is_float() || ew.size() != E) throw FileError((d / "edge_weights.npy").string(), "expected E floats");
  pb.edge_weights = ew.ToDouble();
  for (double w : pb.edge_weights)
    if (!std::isfinite(w) || w < 0.0) throw FileError((d / "edge_weights.npy").string(), "weights must be finite and >= 0");
  const NpyArray y = Load(d / "y.npy", 2);
  if (!y.is_float() || y.shape[0] != static_cast<std::int64_t>(V) || y.shape[1] != 2)
    throw FileError((d / "y.npy").string(), "expected float V x 2");
  const std::vector<double> yd = y.ToDouble();
  pb.y_remove.resize(V);
  for (std::size_t v = 0; v < V; ++v) {
    pb.y_remove[v] = yd[2 * v];
    if (!std::isfinite(yd[2 * v]) || yd[2 * v] < 0.0 || yd[2 * v] > 1.0 || std::fabs(yd[2 * v] + yd[2 * v + 1] - 1.0) > 1e-9)
      throw FileError((d / "y.npy").string(), "rows must be (y, 1 - y) with y in [0, 1]");
  }
  const NpyArray nw = Load(d / "node_weights.npy", 1);
  if (!nw.is_float() || nw.size() != V) throw FileError((d / "node_weights.npy").string(), "expected V floats");
  pb.node_weights = nw.ToDouble();
  for (double w : pb.node_weights)
    if (!std::isfinite(w) || w < 0.0) throw FileError((d / "node_weights.npy").string(), "weights must be finite and >= 0");
  const NpyArray ids = Load(d / "node_ids.npy", 1);
  if (ids.size() != V) throw FileError((d / "node_ids.npy").string(), "expected V entries");
  pb.node_ids = ids.ToInt64();
  return pb;
}

}  // namespace al
