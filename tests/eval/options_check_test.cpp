// Check() of the evaluator's options structs: defaults pass; an out-of-range value is a usage
// error whose message names the option (the words of the option tables).
#include <gtest/gtest.h>

#include <functional>

#include "al/core/error.hpp"
#include "al/eval/eval.hpp"

namespace al::eval {
namespace {

void ExpectRefused(const std::function<void(EvalOptions&)>& spoil, const std::string& named) {
  EvalOptions o;
  o.out_dir = "out";
  spoil(o);
  try {
    o.Check();
    ADD_FAILURE() << "accepted, expected a message naming " << named;
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ExitCode::kUsage) << e.what();
    EXPECT_NE(std::string(e.what()).find(named), std::string::npos) << e.what();
  }
}

TEST(OptionsCheck, EvalDefaultsPassAndEachNestedRangeIsChecked) {
  EvalOptions ok;
  ok.out_dir = "out";
  EXPECT_NO_THROW(ok.Check());
  ExpectRefused([](EvalOptions& o) { o.out_dir.clear(); }, "--out");
  ExpectRefused([](EvalOptions& o) { o.render.max_sh_degree = 4; }, "'max_sh_degree' = 4 must be in [0, 3]");
  ExpectRefused([](EvalOptions& o) { o.render.scale_modifier = 0; }, "'scale_modifier'");
  ExpectRefused([](EvalOptions& o) { o.render.num_threads = -1; }, "'num_threads'");
  ExpectRefused([](EvalOptions& o) { o.render.background[1] = NAN; }, "'background'");
  ExpectRefused([](EvalOptions& o) { o.ght.nu = -1; }, "'nu'");
  ExpectRefused([](EvalOptions& o) { o.ght.omega = 2; }, "'omega'");
  ExpectRefused([](EvalOptions& o) { o.float_depth.alpha_hit = 1.0f; }, "'alpha_hit'");
  ExpectRefused([](EvalOptions& o) { o.semantic.acc_seg_thresholds.push_back(1.5); }, "'acc_seg_thresholds'");
  ExpectRefused([](EvalOptions& o) { o.sim_sam.min_object_iou = -0.1; }, "'min_object_iou'");
}

TEST(OptionsCheck, RenderRefusesBadOptionsBeforeRendering) {
  Scene scene;  // one Gaussian in front of the camera
  scene.means = MatX3f::Zero(1, 3);
  scene.means(0, 2) = 2.0f;
  scene.log_scales = MatX3f::Constant(1, 3, -2.0f);
  scene.rotations = MatX4f::Zero(1, 4);
  scene.rotations(0, 0) = 1.0f;
  scene.opacity_logits = Eigen::VectorXf::Constant(1, 2.0f);
  scene.sh = RowMatXf::Zero(1, 3);
  Camera cam;
  cam.width = cam.height = 8;
  cam.fx = cam.fy = 8;
  RenderOptions o;
  EXPECT_NO_THROW(Render(scene, cam, o));
  o.max_sh_degree = -1;
  EXPECT_THROW(Render(scene, cam, o), Error);
}

}  // namespace
}  // namespace al::eval
