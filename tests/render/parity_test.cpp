// Parity with the INRIA CUDA reference renders of the real 9,080-Gaussian scene (refs_9k):
// RGB and radii from CUDA, alpha/depth/invdepth from an independent re-implementation.
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "al/io/cameras.hpp"
#include "al/io/npy.hpp"
#include "al/io/ply.hpp"
#include "al/render/render.hpp"
#include "render/expect_identical.hpp"
#include "test_data.hpp"

namespace al {
namespace {

struct RefCase {
  std::string camera;
  std::string prefix;  // "full", "minus_random25", "minus_sphere"
  std::string mask;    // "" or mask name
  int bg;              // 0 black, 1 white
};

std::string Name(const testing::TestParamInfo<RefCase>& info) {
  return info.param.camera + "_" + info.param.prefix + "_bg" + std::to_string(info.param.bg);
}

class RefParity : public testing::TestWithParam<RefCase> {};

// Relative-error statistics as refs_9k/README.md prescribes for alpha/depth maps.
void ExpectRelativeClose(const std::vector<float>& ours, const std::vector<float>& ref, const char* what) {
  ASSERT_EQ(ours.size(), ref.size()) << what;
  std::size_t over = 0;
  double sum = 0;
  for (std::size_t i = 0; i < ref.size(); ++i) {
    ASSERT_TRUE(std::isfinite(ours[i])) << what << " pixel " << i;
    const double rel = std::abs(double(ours[i]) - ref[i]) / std::max(1e-12, std::abs(double(ref[i])));
    over += rel > 1e-4;
    sum += rel;
  }
  EXPECT_LE(double(over), 1e-3 * ref.size()) << what << ": pixels with relative error > 1e-4";
  EXPECT_LT(sum / ref.size(), 1e-5) << what << ": mean relative error";
}

TEST_P(RefParity, MatchesCudaReference) {
  AL_REQUIRE_SHARED_DATA(data);
  const RefCase c = GetParam();
  const auto refs = data / "refs_9k";
  static const Scene scene = ReadScene((data / "real_ply" / "scene_9k.ply").string());
  ASSERT_EQ(scene.size(), 9080u);
  const auto cams = ReadCameras((refs / "cameras.json").string()).cameras;
  const Camera cam = SelectViews(cams, c.camera).at(0);

  std::vector<bool> removed;
  if (!c.mask.empty()) {
    const NpyArray m = ReadNpy((refs / "masks" / (c.mask + ".npy")).string());
    const auto v = m.ToInt64();
    removed.assign(v.begin(), v.end());
  }
  RenderOptions opt;
  opt.background = Eigen::Vector3f::Constant(float(c.bg));
  const RenderOutput out = Render(scene, cam, opt, removed);
  const std::string stem = (refs / c.camera / (c.prefix + "_bg" + std::to_string(c.bg))).string();

  // RGB.
  const std::vector<float> ref = ReadNpy(stem + "_rgb.npy").ToFloat();
  ASSERT_EQ(ref.size(), out.rgb.size());
  double se = 0, sa = 0, maxabs = 0;
  std::size_t over = 0;
  for (std::size_t i = 0; i < ref.size(); ++i) {
    ASSERT_TRUE(std::isfinite(out.rgb[i]));
    const double d = std::abs(double(out.rgb[i]) - ref[i]);
    se += d * d;
    sa += d;
    maxabs = std::max(maxabs, d);
    over += d > 1e-4;
  }
  const double psnr = 10 * std::log10(1.0 / std::max(1e-30, se / ref.size()));
  EXPECT_GT(psnr, 60.0);
  EXPECT_LT(sa / ref.size(), 1e-5);
  EXPECT_LT(maxabs, 5e-3);
  EXPECT_LE(double(over), 1e-3 * ref.size());
  RecordProperty("psnr_db", std::to_string(psnr));

  if (c.bg != 0) return;  // radii, alpha and depth exist for bg0 only
  // Radii: one per kept Gaussian, in scene order.
  const auto ref_radii = ReadNpy(stem + "_radii.npy").ToInt64();
  std::vector<std::int64_t> ours;
  for (std::size_t i = 0; i < scene.size(); ++i)
    if (removed.empty() || !removed[i]) ours.push_back(out.radii[i]);
  ASSERT_EQ(ours.size(), ref_radii.size());
  std::size_t visible = 0;
  for (std::size_t i = 0; i < ours.size(); ++i) {
    ASSERT_EQ(ours[i] > 0, ref_radii[i] > 0) << "visibility of kept Gaussian " << i;
    visible += ours[i] > 0;
    if (ref_radii[i] <= 100000)
      EXPECT_EQ(ours[i], ref_radii[i]) << "radius of kept Gaussian " << i;
    else
      EXPECT_LE(std::abs(double(ours[i] - ref_radii[i])), 1e-5 * ref_radii[i]) << "kept Gaussian " << i;
  }
  EXPECT_EQ(visible, out.visible_gaussians);

  ExpectRelativeClose(out.alpha, ReadNpy(stem + "_alpha.npy").ToFloat(), "alpha");
  ExpectRelativeClose(out.depth, ReadNpy(stem + "_depth_expected.npy").ToFloat(), "depth");
  ExpectRelativeClose(out.invdepth, ReadNpy(stem + "_invdepth.npy").ToFloat(), "invdepth");
}

INSTANTIATE_TEST_SUITE_P(Refs9k, RefParity,
                         testing::Values(RefCase{"cam0", "full", "", 0}, RefCase{"cam0", "full", "", 1},
                                         RefCase{"cam0", "minus_random25", "random25", 0},
                                         RefCase{"cam0", "minus_sphere", "sphere", 0},
                                         RefCase{"cam1", "full", "", 0}, RefCase{"cam1", "full", "", 1},
                                         RefCase{"cam1", "minus_random25", "random25", 0},
                                         RefCase{"cam1", "minus_sphere", "sphere", 0}),
                         Name);

// The incremental "after" render of the real scene equals the full render of the remaining
// Gaussians bit for bit, and re-renders only tiles touched by removed Gaussians.
TEST(RefParity, IncrementalAfterOnRealScene) {
  AL_REQUIRE_SHARED_DATA(data);
  const auto refs = data / "refs_9k";
  const Scene scene = ReadScene((data / "real_ply" / "scene_9k.ply").string());
  const Camera cam = SelectViews(ReadCameras((refs / "cameras.json").string()).cameras, "cam1").at(0);
  const auto v = ReadNpy((refs / "masks" / "sphere.npy").string()).ToInt64();
  const std::vector<bool> removed(v.begin(), v.end());
  IncrementalRenderer inc(scene, cam);
  const RenderOutput after = inc.After(removed);
  const RenderOutput full = Render(scene, cam, {}, removed);
  test::ExpectIdenticalRenders(after, full);
  EXPECT_EQ(after.tiles_rendered + after.tiles_copied, after.tiles_total);
}

}  // namespace
}  // namespace al
