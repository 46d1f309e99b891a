// Level-set partition by recursive level cuts over connected pieces (level_set_partition.hpp).
// Pieces are independent, so worker threads take them from one queue, largest first (the chain of
// cuts of a giant piece overlaps with everything else). A piece reads only its neighbours' owner
// and interval start, whose classification (same piece / above / below) never changes while it
// is cut; it writes only its own nodes. Each piece's outcome therefore depends on the piece alone,
// never on the schedule or the number of threads.
#include "solvers/level_sets/level_set_partition.hpp"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <condition_variable>
#include <mutex>
#include <numeric>

#include "al/core/default_init_allocator.hpp"

namespace al::levelset {
namespace {

struct Piece {
  std::vector<std::int32_t> members;
  double lo = 0.0, hi = 1.0;
  int depth = 0;
  std::int32_t id = 0;  // unique among all pieces of the run (the owner_ of its nodes)
  std::int32_t parent = -1;  // id of the piece whose cut made it (-1: a connected component)
};

bool SmallerPiece(const Piece& a, const Piece& b) { return a.members.size() < b.members.size(); }

// What cutting one piece gave: final (at level t, plateau or not) or child pieces.
struct Outcome {
  bool final = false, plateau = false;
  double t = 0.0;
  std::vector<Piece> children;
};

// Per-thread scratch, reused by every piece the thread cuts.
struct Workspace {
  MaxFlow* mf = nullptr;
  std::vector<double> bnd;
  std::vector<std::int32_t> queue;
  std::vector<char> visited;
  std::int64_t inner_arcs = 0;  // arcs between nodes of the piece (both directions)
  std::int64_t flows = 0;
  // The piece's terms for PlateauLevel (smoothed KL): weight, q + c·y per label, and per step the
  // derivatives of every node before they are summed in order.
  std::vector<double> wv, a0, a1, d1, d2;
  // The piece's edges for the network (MaxFlow::SetEdges): each once, at its smaller local end.
  std::vector<std::int64_t> first;
  std::vector<std::int32_t> adj;
  std::vector<double> cap;
};

class Run {
 public:
  Run(const TwoLabelTv& pb, const Options& opt)
      : pb_(pb), opt_(opt), V_(pb.num_nodes()), owner_(V_, 0), local_(V_, 0), side_(V_, 0),
        lo_(V_, 0.0), final_of_(V_, -1) {
    if (pb.adjacency) {
      Renumber(*pb.adjacency);
    } else {
      Renumber(BuildSymmetricAdjacency(pb.first_edge, pb.adj_vertices, pb.edge_weights));
    }
  }
  Partition Solve(std::vector<MaxFlow>* networks);

 private:
  // φ'_v(t) and φ''_v(t) (§11), v in the internal numbering.
  double Dphi(std::int32_t v, double t) const {
    return w_[v] * (pb_.loss.Grad(y_[2 * v], t) - pb_.loss.Grad(y_[2 * v + 1], 1.0 - t));
  }
  double Ddphi(std::int32_t v, double t) const {
    return w_[v] * (pb_.loss.Hess(y_[2 * v], t) + pb_.loss.Hess(y_[2 * v + 1], 1.0 - t));
  }
  // Per adjacency entry: 1 if it is kept (positive weight, not a self-loop), found once on both
  // threads; the serial walk below read the weight of every entry (at 3M, at a random edge id:
  // 8M cache misses on one thread were a tenth of the level-set start).
  std::vector<std::uint8_t> KeptEntries(const SymmetricAdjacency& adj) const;
  double Weight(const SymmetricAdjacency& adj, std::int64_t k) const {
    return adj.weight.empty() ? pb_.edge_weights[adj.edge[k]] : adj.weight[k];
  }
  void Renumber(const SymmetricAdjacency& adj);
  void Walk(const SymmetricAdjacency& adj, const std::vector<std::uint8_t>& kept, std::vector<std::int32_t>& perm);
  void SizeRenumbered(const std::vector<std::uint8_t>& kept);
  void RenumberedAdjacency(const SymmetricAdjacency& adj, const std::vector<std::uint8_t>& kept,
                           const std::vector<std::int32_t>& perm);
  // owner_ and lo_ of other pieces' nodes change while a piece is cut (never their classification).
  std::int32_t Owner(std::int32_t v) const { return std::atomic_ref(owner_[v]).load(std::memory_order_relaxed); }
  double Lo(std::int32_t v) const { return std::atomic_ref(lo_[v]).load(std::memory_order_relaxed); }
  void Own(std::int32_t v, std::int32_t id, double lo) {
    std::atomic_ref(owner_[v]).store(id, std::memory_order_relaxed);
    std::atomic_ref(lo_[v]).store(lo, std::memory_order_relaxed);
  }
  void InitialPieces();
  void Boundary(const Piece& g, Workspace& ws);
  double PlateauLevel(const Piece& g, Workspace& ws) const;
  void GatherKlTerms(const Piece& g, Workspace& ws) const;
  double SummedKlDerivatives(Workspace& ws, double x, double* df) const;
  bool LevelCut(const Piece& g, double t, Workspace& ws);
  void SideComponents(const Piece& g, double t, Workspace& ws, std::vector<Piece>& out);
  Outcome Process(const Piece& g, Workspace& ws);
  void Record(Piece& g, Outcome& o);
  void Work(Workspace& ws);
  Partition Number() const;

  const TwoLabelTv& pb_;
  const Options& opt_;
  const std::int32_t V_;
  // Internally nodes are numbered in breadth-first order (order_[internal] = caller's id), so that
  // neighbours sit close in memory: the caller's order is often spatially random (a kNN graph over
  // a scene's Gaussians) and every pass below walks neighbourhoods.
  std::vector<std::int32_t> order_;
  std::vector<std::int32_t> component_start_;  // first internal id of each connected component
  // Filled by parallel loops right after their resize: no serial zero-fill (default_init_allocator.hpp).
  template <class T>
  using Filled = std::vector<T, DefaultInitAllocator<T>>;
  Filled<double> y_, w_;
  // Symmetric adjacency without zero-weight edges and self-loops, om = omega_scale · w_e.
  std::vector<std::int64_t> ff_;
  Filled<std::int32_t> nbr_;
  Filled<double> om_;
  std::vector<std::int32_t> owner_;  // id of the node's piece, -1 once final
  std::vector<std::int32_t> local_;  // position of the node in its piece
  std::vector<char> side_;           // 1 = above the last level cut of its piece
  std::vector<double> lo_;           // lower end of the node's interval (its value once final)
  std::vector<std::int32_t> final_of_;  // index into the finals below
  std::vector<double> fin_t_, fin_lo_, fin_hi_;
  std::vector<std::uint8_t> fin_plateau_;
  int max_depth_ = 0;
  // The queue of pieces to cut (a max-heap by size) and the workers' bookkeeping, under mu_.
  std::mutex mu_;
  std::condition_variable cv_;
  std::vector<Piece> queue_;
  int busy_ = 0;
  std::int32_t next_id_ = 0;
};

std::vector<std::uint8_t> Run::KeptEntries(const SymmetricAdjacency& adj) const {
  std::vector<std::uint8_t> kept(adj.nbr.size());
  const int threads = std::max(1, opt_.num_threads);
#pragma omp parallel for schedule(static) num_threads(threads)
  for (std::int32_t v = 0; v < V_; ++v)
    for (std::int64_t k = adj.first[v]; k < adj.first[v + 1]; ++k)
      kept[k] = adj.nbr[k] != v && Weight(adj, k) > 0.0;
  return kept;
}

// Breadth-first order over the whole graph (edges of positive weight between distinct nodes) from
// the caller's smallest unvisited node: each connected component becomes a contiguous range.
void Run::Walk(const SymmetricAdjacency& adj, const std::vector<std::uint8_t>& kept, std::vector<std::int32_t>& perm) {
  order_.reserve(V_);
  for (std::int32_t s = 0; s < V_; ++s) {
    if (perm[s] >= 0) continue;
    perm[s] = static_cast<std::int32_t>(order_.size());
    component_start_.push_back(perm[s]);
    order_.push_back(s);
    for (std::size_t h = perm[s]; h < order_.size(); ++h) {
      const std::int32_t v = order_[h];
      for (std::int64_t k = adj.first[v]; k < adj.first[v + 1]; ++k) {
        const std::int32_t u = adj.nbr[k];
        if (perm[u] >= 0 || !kept[k]) continue;
        perm[u] = static_cast<std::int32_t>(order_.size());
        order_.push_back(u);
      }
    }
  }
}

namespace {

template <class T, class A>
void TouchPages(std::vector<T, A>& v) {
  auto* bytes = reinterpret_cast<unsigned char*>(v.data());
  for (std::size_t at = 0; at < v.size() * sizeof(T); at += 4096) bytes[at] = 0;
}

}  // namespace

// The renumbered arrays at their final sizes (allocated here, on the calling thread: memory a
// helper thread allocated would come from its own malloc arena, which the later stages, on the
// main thread, cannot reuse: +90 MB of peak RSS at 3M).
void Run::SizeRenumbered(const std::vector<std::uint8_t>& kept) {
  std::int64_t entries = 0;
  const auto m = static_cast<std::int64_t>(kept.size());
#pragma omp parallel for schedule(static) reduction(+ : entries) num_threads(std::max(1, opt_.num_threads))
  for (std::int64_t k = 0; k < m; ++k) entries += kept[k];
  y_.resize(2 * static_cast<std::size_t>(V_));
  w_.resize(V_);
  nbr_.resize(static_cast<std::size_t>(entries));
  om_.resize(static_cast<std::size_t>(entries));
}

// The walk is serial: meanwhile a second thread writes one byte of every page of the arrays it will
// fill (3M scene, 685k nodes: ~100 MB, whose first-touch page faults were most of
// RenumberedAdjacency's 0.08 s).
void Run::Renumber(const SymmetricAdjacency& adj) {
  const std::vector<std::uint8_t> kept = KeptEntries(adj);
  std::vector<std::int32_t> perm(V_, -1);
  SizeRenumbered(kept);
  if (opt_.num_threads > 1) {
#pragma omp parallel sections num_threads(2)
    {
#pragma omp section
      Walk(adj, kept, perm);
#pragma omp section
      TouchPages(y_), TouchPages(w_), TouchPages(nbr_), TouchPages(om_);
    }
  } else {
    Walk(adj, kept, perm);
  }
  RenumberedAdjacency(adj, kept, perm);
}

// The kept edges, observations and weights in the internal numbering, om = omega_scale · w_e;
// each node's row is written by one thread (rows are independent).
void Run::RenumberedAdjacency(const SymmetricAdjacency& adj, const std::vector<std::uint8_t>& kept,
                              const std::vector<std::int32_t>& perm) {
  ff_.assign(static_cast<std::size_t>(V_) + 1, 0);  // y_, w_, nbr_ and om_ are sized (SizeRenumbered)
  const int threads = std::max(1, opt_.num_threads);
#pragma omp parallel for schedule(static) num_threads(threads)
  for (std::int32_t i = 0; i < V_; ++i) {
    const std::int32_t v = order_[i];
    std::int64_t count = 0;
    for (std::int64_t k = adj.first[v]; k < adj.first[v + 1]; ++k) count += kept[k];
    ff_[i + 1] = count;
    y_[2 * i] = pb_.y[2 * static_cast<std::size_t>(v)];
    y_[2 * i + 1] = pb_.y[2 * static_cast<std::size_t>(v) + 1];
    w_[i] = pb_.node_weights.empty() ? 1.0 : pb_.node_weights[v];
  }
  for (std::int32_t i = 0; i < V_; ++i) ff_[i + 1] += ff_[i];
#pragma omp parallel for schedule(static) num_threads(threads)
  for (std::int32_t i = 0; i < V_; ++i) {
    const std::int32_t v = order_[i];
    std::int64_t pos = ff_[i];
    for (std::int64_t k = adj.first[v]; k < adj.first[v + 1]; ++k) {
      if (!kept[k]) continue;
      nbr_[pos] = perm[adj.nbr[k]];
      om_[pos++] = pb_.omega_scale * Weight(adj, k);
    }
  }
}

// The connected components of the whole graph are the first pieces: the ranges of the internal
// numbering that Renumber's walks covered, one walk per component (kept edges join the same nodes
// as nbr_ does).
void Run::InitialPieces() {
  component_start_.push_back(V_);
  for (std::size_t c = 0; c + 1 < component_start_.size(); ++c) {
    Piece p;
    p.members.resize(component_start_[c + 1] - component_start_[c]);
    std::iota(p.members.begin(), p.members.end(), component_start_[c]);
    p.id = next_id_++;
    for (std::int32_t v : p.members) owner_[v] = p.id;
    queue_.push_back(std::move(p));
  }
  std::make_heap(queue_.begin(), queue_.end(), SmallerPiece);
}

// Numbers the piece's nodes and sums each one's boundary term: a neighbour outside the piece lies
// entirely above (lo_ >= hi) or below it, and pulls the node towards its side by ω.
void Run::Boundary(const Piece& g, Workspace& ws) {
  const std::int32_t n = static_cast<std::int32_t>(g.members.size());
  for (std::int32_t i = 0; i < n; ++i) local_[g.members[i]] = i;
  ws.bnd.assign(n, 0.0);
  ws.inner_arcs = 0;
  for (std::int32_t i = 0; i < n; ++i) {
    const std::int32_t v = g.members[i];
    double b = 0.0;
    for (std::int64_t k = ff_[v]; k < ff_[v + 1]; ++k) {
      const std::int32_t u = nbr_[k];
      if (Owner(u) == g.id) {
        ++ws.inner_arcs;
        continue;
      }
      b += Lo(u) >= g.hi ? -om_[k] : om_[k];
    }
    ws.bnd[i] = b;
  }
}

// The level where the piece's summed derivative crosses zero (safeguarded Newton), within [lo, hi]:
// the best constant value of the piece given its boundary.
double Run::PlateauLevel(const Piece& g, Workspace& ws) const {
  const std::int32_t n = static_cast<std::int32_t>(g.members.size());
  const bool kl = !pb_.loss.linear() && !pb_.loss.quadratic();
  if (kl) GatherKlTerms(g, ws);
  auto f = [&](double x, double* df) {
    if (kl) return SummedKlDerivatives(ws, x, df);
    double s = 0.0, ds = 0.0;
    for (std::int32_t i = 0; i < n; ++i) {
      s += Dphi(g.members[i], x) + ws.bnd[i];
      if (df) ds += Ddphi(g.members[i], x);
    }
    if (df) *df = ds;
    return s;
  };
  if (f(g.lo, nullptr) >= 0.0) return g.lo;
  if (f(g.hi, nullptr) <= 0.0) return g.hi;
  double a0 = g.lo, b0 = g.hi;
  double t = 0.5 * (a0 + b0);
  for (int iter = 0; iter < 200; ++iter) {
    double df;
    const double ft = f(t, &df);
    if (ft == 0.0) break;
    if (ft < 0.0) a0 = t; else b0 = t;
    double next = df > 0.0 ? t - ft / df : 0.5 * (a0 + b0);
    if (!(next > a0 && next < b0)) next = 0.5 * (a0 + b0);
    if (std::fabs(next - t) <= 1e-16 * std::max(1.0, std::fabs(t)) || b0 - a0 <= 1e-16) return next;
    t = next;
  }
  return t;
}

// The piece's weights and q + c·y in member order, contiguous: the Newton steps of PlateauLevel
// (8-63 per piece at 3M, each a pass over the piece) then stream them instead of gathering them by
// node id, and their divisions run two at a time.
void Run::GatherKlTerms(const Piece& g, Workspace& ws) const {
  const std::size_t n = g.members.size();
  const double q = pb_.loss.q(), c = pb_.loss.c();
  ws.wv.resize(n), ws.a0.resize(n), ws.a1.resize(n), ws.d1.resize(n), ws.d2.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::int32_t v = g.members[i];
    ws.wv[i] = w_[v];
    ws.a0[i] = q + c * y_[2 * v];
    ws.a1[i] = q + c * y_[2 * v + 1];
  }
}

// Σ (φ'_v(x) + boundary) and, with df, Σ φ''_v(x), in member order: the very operations of Dphi
// and Ddphi (Loss::Grad and Loss::Hess with q + c·y gathered), so the same doubles.
double Run::SummedKlDerivatives(Workspace& ws, double x, double* df) const {
  const std::size_t n = ws.wv.size();
  const double q = pb_.loss.q(), c = pb_.loss.c(), cc = c * c;
  const double b0 = q / c + x, b1 = q / c + (1.0 - x);
  const double* w = ws.wv.data();
  const double* a0 = ws.a0.data();
  const double* a1 = ws.a1.data();
  double* d1 = ws.d1.data();
  for (std::size_t i = 0; i < n; ++i) d1[i] = w[i] * (-a0[i] / b0 - -a1[i] / b1);
  double s = 0.0;
  for (std::size_t i = 0; i < n; ++i) s += d1[i] + ws.bnd[i];
  if (df) {
    const double h0 = q + c * x, h1 = q + c * (1.0 - x);
    double* d2 = ws.d2.data();
    for (std::size_t i = 0; i < n; ++i) d2[i] = w[i] * (cc * a0[i] / (h0 * h0) + cc * a1[i] / (h1 * h1));
    double ds = 0.0;
    for (std::size_t i = 0; i < n; ++i) ds += d2[i];
    *df = ds;
  }
  return s;
}

// Level cut at t: the sink side ("above", side_ = 1) pays a_v = φ'_v(t) + boundary. Returns true
// when the cut gains nothing (min cut energy = flow − Σ negative unaries >= 0 up to rounding).
bool Run::LevelCut(const Piece& g, double t, Workspace& ws) {
  const std::int32_t n = static_cast<std::int32_t>(g.members.size());
  MaxFlow& mf = *ws.mf;
  mf.Reset(n);
  // A piece made by a cut is cut again at a level close to its parent's, where its unaries nearly
  // balance and the flow has to cross the piece: the hybrid's BK phase then mostly runs out its
  // budget before handing over (3M scene: the 405k-node child 0.18 s hybrid, 0.11-0.14 s
  // pseudoflow first), so under the hybrid a child goes to pseudoflow at once. A connected
  // component's first cut keeps the hybrid (the 449k one: 0.10 s, pseudoflow 0.12-0.13 s). The
  // same cuts either way (docs/solvers.md "Fast at scale: stop 40").
  const bool child = g.parent >= 0 && opt_.max_flow == MaxFlow::Algorithm::kHybrid;
  mf.set_algorithm(child ? MaxFlow::Algorithm::kPseudoflowThenBk : opt_.max_flow);
  // The network reads the piece's edges in place (SetEdges): no edge list to copy and sort into
  // adjacency, and no second breadth-first order (a piece's members already are in one). At 3M
  // the list's arrays and passes were a quarter of the level-set start (its pages first touched).
  ws.first.resize(static_cast<std::size_t>(n) + 1);
  ws.adj.clear();
  ws.cap.clear();
  ws.adj.reserve(ws.inner_arcs / 2);
  ws.cap.reserve(ws.inner_arcs / 2);
  double neg = 0.0, scale = 0.0;
  for (std::int32_t i = 0; i < n; ++i) {
    const std::int32_t v = g.members[i];
    const double a = Dphi(v, t) + ws.bnd[i];
    mf.AddUnary(i, a);
    if (a < 0.0) neg -= a;
    scale += std::fabs(a);
    ws.first[i] = static_cast<std::int64_t>(ws.adj.size());
    for (std::int64_t k = ff_[v]; k < ff_[v + 1]; ++k) {
      const std::int32_t u = nbr_[k];
      if (Owner(u) != g.id || local_[u] <= i) continue;
      ws.adj.push_back(local_[u]);
      ws.cap.push_back(om_[k]);
    }
  }
  ws.first[n] = static_cast<std::int64_t>(ws.adj.size());
  mf.SetEdges(ws.first, ws.adj, ws.cap);
  const double flow = mf.Solve();
  ++ws.flows;
  for (std::int32_t i = 0; i < n; ++i) side_[g.members[i]] = mf.SourceSide(i) ? 0 : 1;
  return flow - neg >= -1e-12 * std::max(scale, 1e-300);
}

// The connected components of each side of the cut (edges inside the piece joining nodes on the
// same side): above in [t, hi], below in [lo, t].
void Run::SideComponents(const Piece& g, double t, Workspace& ws, std::vector<Piece>& out) {
  const std::int32_t n = static_cast<std::int32_t>(g.members.size());
  ws.visited.assign(n, 0);
  for (std::int32_t i0 = 0; i0 < n; ++i0) {
    if (ws.visited[i0]) continue;
    const std::int32_t s = g.members[i0];
    const char side = side_[s];
    Piece p{{s}, side ? t : g.lo, side ? g.hi : t, g.depth + 1, -1, g.id};
    ws.visited[i0] = 1;
    for (std::size_t h = 0; h < p.members.size(); ++h) {
      const std::int32_t v = p.members[h];
      for (std::int64_t k = ff_[v]; k < ff_[v + 1]; ++k) {
        const std::int32_t u = nbr_[k];
        if (Owner(u) != g.id || side_[u] != side || ws.visited[local_[u]]) continue;
        ws.visited[local_[u]] = 1;
        p.members.push_back(u);
      }
    }
    out.push_back(std::move(p));
  }
}

Outcome Run::Process(const Piece& g, Workspace& ws) {
  Boundary(g, ws);
  Outcome out;
  const bool plateau_pivot = !opt_.bisection;
  out.t = plateau_pivot ? PlateauLevel(g, ws) : 0.5 * (g.lo + g.hi);
  if (g.hi - g.lo <= opt_.epsilon) {
    out.final = true;
    return out;
  }
  // One node: its best constant is exact (a cut could only confirm it).
  if (plateau_pivot && g.members.size() == 1) {
    out.final = out.plateau = true;
    return out;
  }
  const bool no_gain = LevelCut(g, out.t, ws);
  std::int64_t above = 0;
  for (std::int32_t v : g.members) above += side_[v];
  const bool one_sided = above == 0 || above == static_cast<std::int64_t>(g.members.size());
  if (plateau_pivot && (one_sided || no_gain)) {
    out.final = out.plateau = true;
    return out;
  }
  SideComponents(g, out.t, ws, out.children);
  return out;
}

// Publishes a cut piece (caller holds no lock): a final piece's value, or its children with fresh
// ids, their nodes' owner and interval start set before they are queued.
void Run::Record(Piece& g, Outcome& o) {
  if (o.final) {
    std::int32_t f;
    {
      std::lock_guard<std::mutex> lock(mu_);
      f = static_cast<std::int32_t>(fin_t_.size());
      fin_t_.push_back(o.t);
      fin_lo_.push_back(g.lo);
      fin_hi_.push_back(g.hi);
      fin_plateau_.push_back(o.plateau ? 1 : 0);
      max_depth_ = std::max(max_depth_, g.depth);
    }
    for (std::int32_t v : g.members) { final_of_[v] = f; Own(v, -1, o.t); }
    return;
  }
  std::int32_t first_id;
  {
    std::lock_guard<std::mutex> lock(mu_);
    first_id = next_id_;
    next_id_ += static_cast<std::int32_t>(o.children.size());
  }
  for (std::size_t j = 0; j < o.children.size(); ++j) {
    Piece& c = o.children[j];
    c.id = first_id + static_cast<std::int32_t>(j);
    for (std::int32_t v : c.members) Own(v, c.id, c.lo);
  }
}

// A worker: cuts the largest queued piece until none is queued and none is being cut. The largest
// child of a cut stays with the worker that cut its parent, whose network is already sized for
// it: when another worker could take it, both networks grew to the giant piece's size (the 3M
// scene's peak RSS then varied from run to run by one network, ~160 MB). Outcomes do not depend on
// which worker cuts a piece.
void Run::Work(Workspace& ws) {
  Piece g;
  bool kept = false;
  for (;;) {
    if (!kept) {
      std::unique_lock<std::mutex> lock(mu_);
      cv_.wait(lock, [&] { return !queue_.empty() || busy_ == 0; });
      if (queue_.empty()) return;
      std::pop_heap(queue_.begin(), queue_.end(), SmallerPiece);
      g = std::move(queue_.back());
      queue_.pop_back();
      ++busy_;
    }
    Outcome o = Process(g, ws);
    Record(g, o);
    const auto largest = std::max_element(o.children.begin(), o.children.end(), SmallerPiece);
    kept = largest != o.children.end();
    if (kept) {
      g = std::move(*largest);
      o.children.erase(largest);
    }
    {
      std::lock_guard<std::mutex> lock(mu_);
      for (Piece& c : o.children) {
        queue_.push_back(std::move(c));
        std::push_heap(queue_.begin(), queue_.end(), SmallerPiece);
      }
      if (!kept) --busy_;
    }
    cv_.notify_all();
  }
}

// Final pieces numbered by their smallest node (the caller's numbering).
Partition Run::Number() const {
  Partition part;
  part.piece.assign(V_, -1);
  std::vector<std::int32_t> id(fin_t_.size(), -1);
  std::vector<std::int32_t> perm(V_);
  for (std::int32_t i = 0; i < V_; ++i) perm[order_[i]] = i;
  for (std::int32_t v = 0; v < V_; ++v) {
    const std::int32_t f = final_of_[perm[v]];
    std::int32_t& c = id[f];
    if (c < 0) {
      c = static_cast<std::int32_t>(part.value.size());
      part.value.push_back(fin_t_[f]);
      part.lo.push_back(fin_lo_[f]);
      part.hi.push_back(fin_hi_[f]);
      part.plateau.push_back(fin_plateau_[f]);
    }
    part.piece[v] = c;
  }
  part.max_depth = max_depth_;
  return part;
}

Partition Run::Solve(std::vector<MaxFlow>* networks) {
  const int threads = std::max(1, opt_.num_threads);
  std::vector<MaxFlow> own;
  if (networks == nullptr || static_cast<int>(networks->size()) < threads) {
    own.resize(threads);
    networks = &own;
  }
  std::vector<Workspace> ws(threads);
  for (int k = 0; k < threads; ++k) ws[k].mf = &(*networks)[k];  // LevelCut sets each cut's algorithm
  InitialPieces();
  if (threads == 1) {
    Work(ws[0]);
  } else {
#pragma omp parallel num_threads(threads)
    Work(ws[omp_get_thread_num()]);
  }
  Partition part = Number();
  for (const Workspace& w : ws) part.max_flows += w.flows;
  return part;
}

}  // namespace

Partition SolveLevelSets(const TwoLabelTv& problem, const Options& options, std::vector<MaxFlow>* networks) {
  if (problem.num_nodes() <= 0) return {};
  return Run(problem, options).Solve(networks);
}

}  // namespace al::levelset
