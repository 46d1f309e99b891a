// Bit-identity of two renders, output by output (shared by the render test files).
#pragma once
#include <gtest/gtest.h>

#include "al/render/render.hpp"

namespace al::test {

inline void ExpectIdenticalRenders(const RenderOutput& a, const RenderOutput& b) {
  EXPECT_EQ(a.rgb, b.rgb);
  EXPECT_EQ(a.alpha, b.alpha);
  EXPECT_EQ(a.depth, b.depth);
  EXPECT_EQ(a.invdepth, b.invdepth);
  EXPECT_EQ(a.front_id, b.front_id);
  EXPECT_EQ(a.radii, b.radii);
  EXPECT_EQ(a.visible_gaussians, b.visible_gaussians);
  EXPECT_EQ(a.excluded_nonfinite, b.excluded_nonfinite);
}

}  // namespace al::test
