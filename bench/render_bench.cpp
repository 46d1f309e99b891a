// Renderer throughput (SPEC §8): a generated 1M-Gaussian SH3 scene at 1280x720, full render vs
// incremental "after" render with a compact removed object (< 5 % of the image). Counters: per-stage
// median seconds, Gaussian-pixel evaluations (total, per wall second, per compositing second).
// Feature rendering (RenderOptions::features): the same scene with D = 16 and D = 128 semantic
// features (128 are projected to 64 channels once per scene, al/render/feature_field.hpp; the
// projection time is a counter) at 320x240 and 1280x720, against the RGB-only render of the same
// size in the same run (BM_RenderFeature/.../d:0).
// Run: build/bench/render_bench --benchmark_format=json --benchmark_out=render.json
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <vector>

#include <Eigen/Geometry>

#include "al/render/feature_field.hpp"
#include "al/render/render.hpp"

namespace {

constexpr std::size_t kGaussians = 1000000;

struct BenchData {
  al::Scene scene;
  al::Camera camera;
  std::vector<bool> object;  // the removed object
  std::size_t object_size = 0;
  std::vector<std::uint8_t> surface;  // 0 wall, 1 floor, 2 table, 3 object, 4 floater (feature class)
};

// Gaussians sampled on surfaces in front of the camera, flat along the surface normal:
// a back wall, a floor, a table top and a sphere (the removable object), plus a few floaters.
// Deterministic (fixed seed).
const BenchData& Data() {
  static const BenchData data = [] {
    BenchData d;
    al::Scene& s = d.scene;
    const std::size_t n = kGaussians;
    s.means.resize(n, 3);
    s.log_scales.resize(n, 3);
    s.rotations.resize(n, 4);
    s.opacity_logits.resize(n);
    s.sh_degree = 3;
    s.sh = al::RowMatXf::Zero(n, 48);
    d.object.assign(n, false);
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> U(0, 1);
    std::normal_distribution<float> N(0, 1);
    const Eigen::Vector3f sphere_c(0.6f, 0.2f, 6.0f);
    const float sphere_r = 0.45f;
    for (std::size_t i = 0; i < n; ++i) {
      const float pick = U(rng);
      Eigen::Vector3f p, normal;
      Eigen::Vector3f base;
      d.surface.push_back(pick < 0.45f ? 0 : pick < 0.8f ? 1 : pick < 0.93f ? 2 : pick < 0.995f ? 3 : 4);
      if (pick < 0.45f) {  // back wall z = 12
        p << -10 + 20 * U(rng), -6 + 8.5f * U(rng), 12;
        normal << 0, 0, 1;
        base << 0.6f, 0.55f, 0.5f;
      } else if (pick < 0.8f) {  // floor y = 2.5
        p << -10 + 20 * U(rng), 2.5f, 2 + 10 * U(rng);
        normal << 0, 1, 0;
        base << 0.4f, 0.3f, 0.2f;
      } else if (pick < 0.93f) {  // table top y = 0.8
        p << -2 + 4 * U(rng), 0.8f, 4.5f + 3 * U(rng);
        normal << 0, 1, 0;
        base << 0.3f, 0.2f, 0.1f;
      } else if (pick < 0.995f) {  // sphere object
        normal = Eigen::Vector3f(N(rng), N(rng), N(rng)).normalized();
        p = sphere_c + sphere_r * normal;
        base << 0.8f, 0.1f, 0.1f;
        d.object[i] = true;
        ++d.object_size;
      } else {  // floaters
        p << -4 + 8 * U(rng), -3 + 5 * U(rng), 2 + 8 * U(rng);
        normal = Eigen::Vector3f(N(rng), N(rng), N(rng)).normalized();
        base << U(rng), U(rng), U(rng);
      }
      s.means.row(i) = p.transpose();
      // Quaternion rotating +z onto the normal (flat axis = scale_2).
      const Eigen::Vector3f z(0, 0, 1);
      Eigen::Vector3f axis = z.cross(normal);
      const float c = z.dot(normal);
      Eigen::Vector4f q(1 + c, axis.x(), axis.y(), axis.z());
      if (q.norm() < 1e-4f) q << 0, 1, 0, 0;
      s.rotations.row(i) = q.normalized().transpose();
      s.log_scales.row(i) << -4 + 2 * U(rng), -4 + 2 * U(rng), -6.5f;
      s.opacity_logits[i] = -1 + 5 * U(rng);
      for (int ch = 0; ch < 3; ++ch) s.sh(i, ch) = (base[ch] + 0.1f * N(rng) - 0.5f) / 0.28209479f;
      for (int k = 3; k < 48; ++k) s.sh(i, k) = 0.05f * N(rng);
    }
    d.camera.name = "bench";
    d.camera.width = 1280;
    d.camera.height = 720;
    d.camera.fx = d.camera.fy = 1000;
    d.camera.cx = 640;
    d.camera.cy = 360;
    return d;
  }();
  return data;
}

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

// Per-iteration stage times; the counters are their medians (and the aggregates over the
// repetitions are medians of those), so one slow iteration on a loaded machine does not skew them.
struct StageTimes {
  std::vector<double> preprocess, binning, composite;
  void Add(const al::RenderOutput& out) {
    preprocess.push_back(out.seconds_preprocess);
    binning.push_back(out.seconds_binning);
    composite.push_back(out.seconds_composite);
  }
};

void SetCounters(benchmark::State& state, const al::RenderOutput& out, const StageTimes& times) {
  state.counters["visible_gaussians"] = double(out.visible_gaussians);
  state.counters["tiles_rendered"] = double(out.tiles_rendered);
  state.counters["tiles_copied"] = double(out.tiles_copied);
  // Gaussian-pixel pairs in the lists of the re-composited tiles (an upper bound of the per-pixel
  // evaluations: early termination stops some pixels before the end of the list).
  const double pairs = double(out.tile_entries) * 256.0 * (double(out.tiles_rendered) / double(out.tiles_total));
  state.counters["gaussian_pixel_pairs_per_s"] =
      benchmark::Counter(pairs, benchmark::Counter::kIsIterationInvariantRate);
  // Gaussian-pixel evaluations actually done (power computed for a pixel still blending), per
  // second of the whole render and per second of the compositing stage.
  const double evals = double(out.pixel_evaluations);
  state.counters["pixel_evaluations"] = evals;
  state.counters["gaussian_pixel_evals_per_s"] =
      benchmark::Counter(evals, benchmark::Counter::kIsIterationInvariantRate);
  const double composite = Median(times.composite);
  state.counters["composite_evals_per_s"] = composite > 0 ? evals / composite : 0.0;
  state.counters["seconds_preprocess"] = Median(times.preprocess);
  state.counters["seconds_binning"] = Median(times.binning);
  state.counters["seconds_composite"] = composite;
}

void BM_RenderFull(benchmark::State& state) {
  const BenchData& d = Data();
  al::RenderOptions opt;
  opt.num_threads = int(state.range(0));
  al::RenderOutput out;
  StageTimes times;
  for (auto _ : state) {
    out = al::Render(d.scene, d.camera, opt);
    benchmark::DoNotOptimize(out.rgb.data());
    times.Add(out);
  }
  SetCounters(state, out, times);
}

void BM_RenderIncremental(benchmark::State& state) {
  const BenchData& d = Data();
  al::RenderOptions opt;
  opt.num_threads = int(state.range(0));
  al::IncrementalRenderer inc(d.scene, d.camera, opt);
  al::RenderOutput out;
  StageTimes times;
  for (auto _ : state) {
    out = inc.After(d.object);
    benchmark::DoNotOptimize(out.rgb.data());
    times.Add(out);
  }
  SetCounters(state, out, times);
  state.counters["removed_gaussians"] = double(d.object_size);
  // Share of the image the removed object covered in the "before" render.
  std::size_t covered = 0;
  for (std::int32_t id : inc.before().front_id) covered += id >= 0 && d.object[id];
  state.counters["object_image_fraction"] = double(covered) / double(inc.before().front_id.size());
}

// Per-Gaussian semantic features of the bench scene: a unit class direction per surface (floaters
// random) plus noise of norm ~0.3, D channels; deterministic.
al::RowMatXf SceneFeatures(int dim) {
  const BenchData& d = Data();
  std::mt19937 rng(11);
  std::normal_distribution<float> N(0, 1);
  al::RowMatXf classes(5, dim), f(static_cast<Eigen::Index>(d.scene.size()), dim);
  for (Eigen::Index i = 0; i < classes.size(); ++i) classes.data()[i] = N(rng);
  for (Eigen::Index c = 0; c < 5; ++c) classes.row(c).normalize();
  const float noise = 0.3f / std::sqrt(float(dim));
  for (Eigen::Index i = 0; i < f.rows(); ++i) {
    const std::uint8_t s = d.surface[std::size_t(i)];
    for (int k = 0; k < dim; ++k) f(i, k) = (s < 4 ? classes(s, k) : N(rng)) + noise * N(rng);
  }
  return f;
}

// The rendered channels for D input channels (D > 64: projected once), with the preparation time.
struct FeatureInput {
  al::FeatureField field;
  double prepare_seconds = 0;
};
const FeatureInput& Features(int dim) {
  static std::map<int, FeatureInput> cache;
  auto it = cache.find(dim);
  if (it == cache.end()) {
    FeatureInput in;
    const al::RowMatXf raw = SceneFeatures(dim);
    in.field = al::PrepareFeatureField(raw);
    in.prepare_seconds = in.field.seconds;
    it = cache.emplace(dim, std::move(in)).first;
  }
  return it->second;
}

al::Camera CameraOfWidth(int width) {
  al::Camera c = Data().camera;
  const double s = double(width) / c.width;
  c.width = width;
  c.height = int(std::lround(c.height * s));
  if (width == 320) c.height = 240;  // the eval resolution (4:3)
  c.fx *= s;
  c.fy *= s;
  c.cx = c.width / 2.0;
  c.cy = c.height / 2.0;
  return c;
}

// Full render, 2 threads, at width range(0), with range(1) feature channels (0 = RGB only).
void BM_RenderFeature(benchmark::State& state) {
  const BenchData& d = Data();
  const al::Camera cam = CameraOfWidth(int(state.range(0)));
  const int dim = int(state.range(1));
  al::RenderOptions opt;
  opt.num_threads = 2;
  const FeatureInput* in = dim > 0 ? &Features(dim) : nullptr;
  if (in) opt.features = &in->field.channels;
  al::RenderOutput out;
  StageTimes times;
  for (auto _ : state) {
    out = al::Render(d.scene, cam, opt);
    benchmark::DoNotOptimize(out.rgb.data());
    times.Add(out);
  }
  SetCounters(state, out, times);
  state.counters["width"] = cam.width;
  state.counters["height"] = cam.height;
  state.counters["input_dim"] = dim;
  state.counters["rendered_channels"] = in ? in->field.dim() : 0;
  if (in) {
    state.counters["prepare_seconds"] = in->prepare_seconds;  // once per scene (centring, projection)
    state.counters["kept_variance"] = in->field.kept_variance;
  }
}

// Incremental "after" render with 16 feature channels (2 threads, 1280x720).
void BM_RenderIncrementalFeature(benchmark::State& state) {
  const BenchData& d = Data();
  al::RenderOptions opt;
  opt.num_threads = 2;
  opt.features = &Features(int(state.range(0))).field.channels;
  al::IncrementalRenderer inc(d.scene, d.camera, opt);
  al::RenderOutput out;
  StageTimes times;
  for (auto _ : state) {
    out = inc.After(d.object);
    benchmark::DoNotOptimize(out.feature.data());
    times.Add(out);
  }
  SetCounters(state, out, times);
}

BENCHMARK(BM_RenderFull)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->Repetitions(5)->ReportAggregatesOnly(true)->UseRealTime();
BENCHMARK(BM_RenderIncremental)->Arg(2)->Unit(benchmark::kMillisecond)->Repetitions(5)->ReportAggregatesOnly(true)->UseRealTime();
BENCHMARK(BM_RenderFeature)
    ->ArgNames({"w", "d"})
    ->ArgsProduct({{320, 1280}, {0, 16, 128}})
    ->Unit(benchmark::kMillisecond)
    ->Repetitions(5)
    ->ReportAggregatesOnly(true)
    ->UseRealTime();
BENCHMARK(BM_RenderIncrementalFeature)->ArgName("d")->Arg(16)->Unit(benchmark::kMillisecond)->Repetitions(5)->ReportAggregatesOnly(true)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
