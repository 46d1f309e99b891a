// Per-Gaussian preprocessing (RASTERIZER.md §1-3, §6), in float32 with the operation order of the
// INRIA kernel so that the 2D means, conics and integer radii agree with the CUDA reference.
#include <omp.h>

#include <algorithm>
#include <climits>
#include <cmath>

#include "al/core/error.hpp"
#include "src/render/frame.hpp"

namespace al::render_internal {
namespace {

constexpr float kShC0 = 0.28209479177387814f;
constexpr float kShC1 = 0.4886025119029199f;
constexpr float kShC2[5] = {1.0925484305920792f, -1.0925484305920792f, 0.31539156525252005f,
                            -1.0925484305920792f, 0.5462742152960396f};
constexpr float kShC3[7] = {-0.5900435899266435f, 2.890611442640554f, -0.4570457994644658f,
                            0.3731763325901154f,  -0.4570457994644658f, 1.445305721320277f,
                            -0.5900435899266435f};

// C-style truncation of a float tile coordinate, then clamp to [0, hi]. Done without the
// undefined float->int cast for huge values (radii reach 2.6e5 px just past the near plane).
inline int TruncClamp(float f, int hi) {
  if (!(f > 0.0f)) return 0;  // (int) truncates toward zero: everything <= 0 ends at 0
  if (f >= static_cast<float>(hi)) return hi;
  return static_cast<int>(f);
}

// float -> int as CUDA does it (saturating).
inline int SaturatingInt(float f) {
  if (!(f < 2147483520.0f)) return INT_MAX;
  return static_cast<int>(f);
}

bool RowFinite(const Scene& s, Eigen::Index i) {
  if (!s.means.row(i).allFinite() || !s.log_scales.row(i).allFinite() ||
      !s.rotations.row(i).allFinite() || !std::isfinite(s.opacity_logits[i]))
    return false;
  return s.sh.row(i).allFinite();
}

}  // namespace

int ThreadCount(const RenderOptions& options) {
  return options.num_threads > 0 ? options.num_threads : omp_get_max_threads();
}

ViewParams MakeViewParams(const Camera& camera) {
  ViewParams p;
  p.width = camera.width;
  p.height = camera.height;
  p.grid_x = (camera.width + kTile - 1) / kTile;
  p.grid_y = (camera.height + kTile - 1) / kTile;
  // INRIA: FoV = 2 atan(W / 2fx) in double, tan(FoV/2) passed to the kernel as float.
  const double tanx = std::tan(2.0 * std::atan(camera.width / (2.0 * camera.fx)) * 0.5);
  const double tany = std::tan(2.0 * std::atan(camera.height / (2.0 * camera.fy)) * 0.5);
  p.tan_fovx = static_cast<float>(tanx);
  p.tan_fovy = static_cast<float>(tany);
  p.focal_x = static_cast<float>(camera.width) / (2.0f * p.tan_fovx);
  p.focal_y = static_cast<float>(camera.height) / (2.0f * p.tan_fovy);
  float w2c[3][4];
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) w2c[r][c] = static_cast<float>(camera.R(r, c));
    w2c[r][3] = static_cast<float>(camera.t[r]);
  }
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) p.view[r * 4 + c] = w2c[r][c];
  // Projection matrix of the INRIA code (znear 0.01): P00 = 2 n / (right - left), in double,
  // stored as float32; the product P * W2C is taken in float32. P is sparse, so each entry of the
  // rows used here is a single float product.
  const double znear = 0.01;
  const float p00 = static_cast<float>(2.0 * znear / (2.0 * tanx * znear));
  const float p11 = static_cast<float>(2.0 * znear / (2.0 * tany * znear));
  for (int c = 0; c < 4; ++c) {
    p.proj_x[c] = w2c[0][c] * p00;
    p.proj_y[c] = w2c[1][c] * p11;
    p.proj_w[c] = w2c[2][c];
  }
  const Eigen::Vector3d centre = camera.Centre();
  for (int k = 0; k < 3; ++k) p.campos[k] = static_cast<float>(centre[k]);
  return p;
}

void CheckInputs(const Scene& scene, const Camera& camera, const std::vector<bool>& exclude) {
  const Eigen::Index n = scene.means.rows();
  if (scene.log_scales.rows() != n || scene.rotations.rows() != n || scene.opacity_logits.size() != n ||
      scene.sh.rows() != n)
    throw Error(scene.source_path + ": scene arrays have inconsistent lengths (means " + std::to_string(n) + ")");
  if (scene.sh_degree < 0 || scene.sh_degree > 3)
    throw Error(scene.source_path + ": SH degree " + std::to_string(scene.sh_degree) + " not in 0..3");
  const int k = (scene.sh_degree + 1) * (scene.sh_degree + 1);
  if (scene.sh.cols() < 3 * k)
    throw Error(scene.source_path + ": SH array has " + std::to_string(scene.sh.cols()) + " columns, degree " +
                std::to_string(scene.sh_degree) + " needs " + std::to_string(3 * k));
  if (!(camera.width > 0 && camera.height > 0 && camera.width <= 65536 && camera.height <= 65536))
    throw Error("camera " + camera.name + ": invalid image size " + std::to_string(camera.width) + "x" +
                std::to_string(camera.height));
  if (!(std::isfinite(camera.fx) && std::isfinite(camera.fy) && camera.fx > 0 && camera.fy > 0))
    throw Error("camera " + camera.name + ": focal lengths must be finite and positive");
  if (!camera.R.allFinite() || !camera.t.allFinite())
    throw Error("camera " + camera.name + ": non-finite pose");
  if (!exclude.empty() && exclude.size() != static_cast<std::size_t>(n))
    throw Error("removal mask has " + std::to_string(exclude.size()) + " entries, scene has " +
                std::to_string(n) + " Gaussians");
}

void Preprocess(const Scene& scene, const ViewParams& view, const RenderOptions& options,
                const std::vector<bool>& exclude, Projected& out) {
  const std::size_t n = scene.size();
  for (auto* v : {&out.u, &out.v, &out.conic_a, &out.conic_b, &out.conic_c, &out.opacity, &out.red,
                  &out.green, &out.blue, &out.tz})
    v->assign(n, 0.0f);
  for (auto* v : {&out.radius, &out.xmin, &out.ymin, &out.xmax, &out.ymax}) v->assign(n, 0);
  out.status.assign(n, kCulled);
  const int deg = std::max(0, std::min(scene.sh_degree, options.max_sh_degree));
  const float mod = options.scale_modifier;
  const float limx = 1.3f * view.tan_fovx, limy = 1.3f * view.tan_fovy;
  const float* vm = view.view;
  const bool has_exclude = !exclude.empty();
  std::size_t visible = 0, nonfinite = 0, degenerate = 0;

#pragma omp parallel for schedule(static) num_threads(ThreadCount(options)) \
    reduction(+ : visible, nonfinite, degenerate)
  for (std::int64_t ii = 0; ii < static_cast<std::int64_t>(n); ++ii) {
    const Eigen::Index i = ii;
    if (has_exclude && exclude[i]) {
      out.status[i] = kExcluded;
      continue;
    }
    if (!RowFinite(scene, i)) {
      out.status[i] = kNonFinite;
      ++nonfinite;
      continue;
    }
    const float px = scene.means(i, 0), py = scene.means(i, 1), pz = scene.means(i, 2);
    // View-space point (transformPoint4x3) and near cull.
    const float tx = vm[0] * px + vm[1] * py + vm[2] * pz + vm[3];
    const float ty = vm[4] * px + vm[5] * py + vm[6] * pz + vm[7];
    const float tz = vm[8] * px + vm[9] * py + vm[10] * pz + vm[11];
    if (!(tz > 0.2f)) continue;

    // 3D covariance: M = S * R (glm column-major), Sigma = M^T M.
    float qw = scene.rotations(i, 0), qx = scene.rotations(i, 1), qy = scene.rotations(i, 2),
          qz = scene.rotations(i, 3);
    float qn = std::sqrt(qw * qw + qx * qx + qy * qy + qz * qz);
    if (!std::isfinite(qn)) {
      // Finite components whose squares overflow (|q| > 1.8e19): scale down first. Only here, so
      // every other quaternion takes exactly torch's arithmetic (parity).
      const float big = std::max(std::max(std::abs(qw), std::abs(qx)), std::max(std::abs(qy), std::abs(qz)));
      qw /= big; qx /= big; qy /= big; qz /= big;
      qn = std::sqrt(qw * qw + qx * qx + qy * qy + qz * qz);
    }
    const float qd = std::max(qn, 1e-12f);  // torch.nn.functional.normalize eps
    qw /= qd; qx /= qd; qy /= qd; qz /= qd;
    const float s[3] = {mod * std::exp(scene.log_scales(i, 0)), mod * std::exp(scene.log_scales(i, 1)),
                        mod * std::exp(scene.log_scales(i, 2))};
    // rg[c][r]: column c, row r of the glm rotation matrix.
    const float rg[3][3] = {
        {1.f - 2.f * (qy * qy + qz * qz), 2.f * (qx * qy - qw * qz), 2.f * (qx * qz + qw * qy)},
        {2.f * (qx * qy + qw * qz), 1.f - 2.f * (qx * qx + qz * qz), 2.f * (qy * qz - qw * qx)},
        {2.f * (qx * qz - qw * qy), 2.f * (qy * qz + qw * qx), 1.f - 2.f * (qx * qx + qy * qy)}};
    float m[3][3];
    for (int c = 0; c < 3; ++c)
      for (int r = 0; r < 3; ++r) m[c][r] = s[r] * rg[c][r];
    float sig[3][3];
    for (int c = 0; c < 3; ++c)
      for (int r = 0; r < 3; ++r) sig[c][r] = m[r][0] * m[c][0] + m[r][1] * m[c][1] + m[r][2] * m[c][2];
    const float v3[3][3] = {{sig[0][0], sig[0][1], sig[0][2]},
                            {sig[0][1], sig[1][1], sig[1][2]},
                            {sig[0][2], sig[1][2], sig[2][2]}};

    // EWA projection with the clamped Jacobian (clamp enters J only).
    const float txc = std::min(limx, std::max(-limx, tx / tz)) * tz;
    const float tyc = std::min(limy, std::max(-limy, ty / tz)) * tz;
    const float fx = view.focal_x, fy = view.focal_y;
    const float jg[2][3] = {{fx / tz, 0.0f, -(fx * txc) / (tz * tz)},
                            {0.0f, fy / tz, -(fy * tyc) / (tz * tz)}};
    // wg[c][r] = W2C rotation R[c][r] (glm W built from the transposed view matrix).
    // T = W * J: t2[c][r] = sum_k wg[k][r] * J[c][k] (columns c = 0, 1; column 2 is zero).
    float t2[2][3];
    for (int c = 0; c < 2; ++c)
      for (int r = 0; r < 3; ++r)
        t2[c][r] = vm[0 * 4 + r] * jg[c][0] + vm[1 * 4 + r] * jg[c][1] + vm[2 * 4 + r] * jg[c][2];
    // A = T^T * V^T: a[c][r] = sum_k T[r][k] * V[k][c]  (r in {0,1} needed).
    float a2[3][2];
    for (int c = 0; c < 3; ++c)
      for (int r = 0; r < 2; ++r) a2[c][r] = t2[r][0] * v3[0][c] + t2[r][1] * v3[1][c] + t2[r][2] * v3[2][c];
    // cov = A * T: cov[c][r] = sum_k A[k][r] * T[c][k].
    auto cov_at = [&](int c, int r) { return a2[0][r] * t2[c][0] + a2[1][r] * t2[c][1] + a2[2][r] * t2[c][2]; };
    const float ca = cov_at(0, 0) + 0.3f, cb = cov_at(0, 1), cc = cov_at(1, 1) + 0.3f;

    const float det = ca * cc - cb * cb;
    if (det == 0.0f) continue;
    const float det_inv = 1.0f / det;
    const float conic_a = cc * det_inv, conic_b = -cb * det_inv, conic_c = ca * det_inv;
    const float mid = 0.5f * (ca + cc);
    const float l1 = mid + std::sqrt(std::max(0.1f, mid * mid - det));
    const float l2 = mid - std::sqrt(std::max(0.1f, mid * mid - det));
    const float radius_f = std::ceil(3.0f * std::sqrt(std::max(l1, l2)));

    // 2D mean through the float32 full projection matrix, then NDC -> pixel in double.
    const float* pxr = view.proj_x;
    const float* pyr = view.proj_y;
    const float* pwr = view.proj_w;
    const float hx = pxr[0] * px + pxr[1] * py + pxr[2] * pz + pxr[3];
    const float hy = pyr[0] * px + pyr[1] * py + pyr[2] * pz + pyr[3];
    const float hw = pwr[0] * px + pwr[1] * py + pwr[2] * pz + pwr[3];
    const float pw = 1.0f / (hw + 0.0000001f);
    const float ndc_x = hx * pw, ndc_y = hy * pw;
    const float u = static_cast<float>(((ndc_x + 1.0) * view.width - 1.0) * 0.5);
    const float v = static_cast<float>(((ndc_y + 1.0) * view.height - 1.0) * 0.5);

    if (!std::isfinite(conic_a) || !std::isfinite(conic_b) || !std::isfinite(conic_c) ||
        !std::isfinite(radius_f) || !std::isfinite(u) || !std::isfinite(v)) {
      // Finite parameters whose projection overflowed (e.g. log-scale 60): INRIA would write
      // garbage; we never render them.
      out.status[i] = kDegenerate;
      ++degenerate;
      continue;
    }
    const int radius = SaturatingInt(radius_f);
    const float rf = static_cast<float>(radius);
    const int x0 = TruncClamp((u - rf) / kTile, view.grid_x);
    const int y0 = TruncClamp((v - rf) / kTile, view.grid_y);
    const int x1 = TruncClamp((u + rf + (kTile - 1)) / kTile, view.grid_x);
    const int y1 = TruncClamp((v + rf + (kTile - 1)) / kTile, view.grid_y);
    if (static_cast<std::int64_t>(x1 - x0) * (y1 - y0) == 0) continue;

    // Colour from SH in direction (p - campos) / |p - campos|.
    float dx = px - view.campos[0], dy = py - view.campos[1], dz = pz - view.campos[2];
    const float len = std::sqrt(dx * dx + dy * dy + dz * dz);
    dx = dx / len; dy = dy / len; dz = dz / len;
    float rgb[3];
    const float* sh = &scene.sh(i, 0);
    const float x = dx, y = dy, z = dz;
    const float xx = x * x, yy = y * y, zz = z * z, xy = x * y, yz = y * z, xz = x * z;
    for (int ch = 0; ch < 3; ++ch) {
      auto c = [&](int k) { return sh[k * 3 + ch]; };
      float col = kShC0 * c(0);
      if (deg > 0) {
        col = col - kShC1 * y * c(1) + kShC1 * z * c(2) - kShC1 * x * c(3);
        if (deg > 1) {
          col = col + kShC2[0] * xy * c(4) + kShC2[1] * yz * c(5) + kShC2[2] * (2.0f * zz - xx - yy) * c(6) +
                kShC2[3] * xz * c(7) + kShC2[4] * (xx - yy) * c(8);
          if (deg > 2) {
            col = col + kShC3[0] * y * (3.0f * xx - yy) * c(9) + kShC3[1] * xy * z * c(10) +
                  kShC3[2] * y * (4.0f * zz - xx - yy) * c(11) +
                  kShC3[3] * z * (2.0f * zz - 3.0f * xx - 3.0f * yy) * c(12) +
                  kShC3[4] * x * (4.0f * zz - xx - yy) * c(13) + kShC3[5] * z * (xx - yy) * c(14) +
                  kShC3[6] * x * (xx - 3.0f * yy) * c(15);
          }
        }
      }
      col += 0.5f;
      rgb[ch] = std::max(col, 0.0f);
    }
    if (!std::isfinite(rgb[0]) || !std::isfinite(rgb[1]) || !std::isfinite(rgb[2])) {
      out.status[i] = kDegenerate;
      ++degenerate;
      continue;
    }

    out.u[i] = u;
    out.v[i] = v;
    out.conic_a[i] = conic_a;
    out.conic_b[i] = conic_b;
    out.conic_c[i] = conic_c;
    out.opacity[i] = 1.0f / (1.0f + std::exp(-scene.opacity_logits[i]));
    out.red[i] = rgb[0];
    out.green[i] = rgb[1];
    out.blue[i] = rgb[2];
    out.tz[i] = tz;
    out.radius[i] = radius;
    out.xmin[i] = x0;
    out.ymin[i] = y0;
    out.xmax[i] = x1;
    out.ymax[i] = y1;
    out.status[i] = kVisible;
    ++visible;
  }
  out.visible = visible;
  out.nonfinite = nonfinite;
  out.degenerate = degenerate;
}

}  // namespace al::render_internal
