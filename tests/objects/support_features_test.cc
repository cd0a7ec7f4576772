#include "objects/support_features.h"

#include <gtest/gtest.h>

#include <cmath>

#include "render/camera.h"
#include "objects/support_truth.h"
#include "tests/perception/test_views.h"

namespace semvox {
namespace {

TEST(LocalEntropy, ConstantIsZeroAndTwoEqualValuesAreOneBit) {
  Image<uint8_t> flat(20, 15, 1, 7), stripes(20, 15, 1, 0);
  for (int y = 0; y < 15; ++y)
    for (int x = 0; x < 20; ++x) stripes.at(x, y) = (x + y) % 2 ? 200 : 10;
  const ImageF32 a = LocalEntropy(flat, 9), b = LocalEntropy(stripes, 9);
  for (float v : a.data) EXPECT_NEAR(v, 0.f, 1e-6f);
  // A 9 x 9 checkerboard window holds 41 and 40 pixels: entropy just under 1 bit.
  const double p = 41.0 / 81, expected = -(p * std::log2(p) + (1 - p) * std::log2(1 - p));
  EXPECT_NEAR(b.at(10, 7), expected, 1e-5);
  // Brute force at a border pixel (clipped window 5 x 5 at the corner).
  int n200 = 0, n = 0;
  for (int y = 0; y <= 4; ++y)
    for (int x = 0; x <= 4; ++x) n200 += stripes.at(x, y) == 200, ++n;
  const double q = double(n200) / n;
  EXPECT_NEAR(b.at(0, 0), -(q * std::log2(q) + (1 - q) * std::log2(1 - q)), 1e-5);
}

// A camera 1.6 m high looking level along +x at a horizontal surface (lower half, normal up, world z from
// the depth) and a wall (upper half): the lower superpixel's height and normal come out right.
TEST(SupportFeatures, HeightAndNormalOfAFlatTop) {
  const Eigen::Isometry3d pose = WorldFromCameraYawPitch(Eigen::Vector3d(0, 0, 1.6), 0, 0);
  RenderedView view = testing::MakeView(40, 30, pose, [&](int x, int y) {
    testing::PixelSample s;
    s.color = Rgb8{uint8_t(100 + x), 80, 60};
    if (y >= 15) {
      // The table top at z = 0.75 seen below the horizon: depth where the ray meets it.
      const double ray_down = (y + 0.5 - 15.0) / (20.0);  // camera's cy = 15, fy = 20 for 90 deg at 40 px.
      s.depth = float(0.85 / ray_down);
      s.normal = Eigen::Vector3f(0, 0, 1);
    } else {
      s.depth = 3.0f;
      s.normal = Eigen::Vector3f(-1, 0, 0);
    }
    return s;
  });
  Superpixels sp;
  sp.label = Image<int32_t>(40, 30, 1, 0);
  sp.count = 2;
  for (int y = 15; y < 30; ++y)
    for (int x = 0; x < 40; ++x) sp.label.at(x, y) = 1;
  Result<SupportFeatures> f = ComputeSupportFeatures(view, sp, SupportFeatureOptions{});
  ASSERT_TRUE(f.ok()) << f.status().message();
  const float* top = &f->rows[size_t(1) * kSupportFeatureDims];
  const float* wall = &f->rows[0];
  EXPECT_NEAR(top[kSupportHeight], 0.75f, 0.01f);
  EXPECT_NEAR(top[kSupportNormalUp], 1.f, 1e-5f);
  EXPECT_NEAR(wall[kSupportNormalForward], -1.f, 1e-5f);  // Facing the camera.
  EXPECT_NEAR(wall[kSupportNormalUp], 0.f, 1e-5f);
  EXPECT_TRUE(f->has_depth[0] && f->has_depth[1]);
  EXPECT_GT(top[kSupportEntropyR], 0.5f);   // R varies along x.
  EXPECT_NEAR(top[kSupportEntropyG], 0.f, 1e-5f);
}

}  // namespace
}  // namespace semvox

namespace semvox {
namespace {

// Two passes over the same generated views give bit-identical features (training is deterministic). This
// caught the sliding histogram adding the entering column before removing the leaving one: a bin could
// hold 90 counts in a 9 x 9 window and the c log c table was read past its end.
TEST(SupportFeatures, DeterministicOnGeneratedViews) {
  std::vector<std::vector<float>> first;
  for (int pass = 0; pass < 2; ++pass) {
    int k = 0;
    ASSERT_TRUE(ForEachSupportView(0, TrainingViewsOptions{}, SupportTruthOptions{}, [&](const SupportView& v) {
      if (k >= 6) return Status::Ok();
      Result<Superpixels> sp = ComputeSuperpixels(v.view->rgb, SuperpixelOptions{});
      if (!sp.ok()) return sp.status();
      Result<SupportFeatures> f = ComputeSupportFeatures(*v.view, *sp, SupportFeatureOptions{});
      if (!f.ok()) return f.status();
      Result<SupportFeatures> again = ComputeSupportFeatures(*v.view, *sp, SupportFeatureOptions{});
      EXPECT_TRUE(again->rows == f->rows) << "view " << k << ": same input, different features";
      if (pass == 0) first.push_back(f->rows);
      else EXPECT_TRUE(first[size_t(k)] == f->rows) << "view " << k << ": second pass differs";
      ++k;
      return Status::Ok();
    }).ok());
  }
}

// Window counts stay within window^2 everywhere, also on the worst case (one value everywhere): entropy 0.
TEST(LocalEntropy, MatchesBruteForceOnRandomImage) {
  Image<uint8_t> img(37, 23, 1);
  uint32_t state = 12345;
  for (auto& v : img.data) v = uint8_t((state = state * 1664525u + 1013904223u) >> 29);  // 8 values
  const ImageF32 e = LocalEntropy(img, 9);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      int hist[256] = {0}, n = 0;
      for (int yy = std::max(0, y - 4); yy <= std::min(img.height - 1, y + 4); ++yy)
        for (int xx = std::max(0, x - 4); xx <= std::min(img.width - 1, x + 4); ++xx) ++hist[img.at(xx, yy)], ++n;
      double h = 0;
      for (int c : hist)
        if (c > 0) h -= double(c) / n * std::log2(double(c) / n);
      ASSERT_NEAR(e.at(x, y), h, 1e-5) << x << "," << y;
    }
}

}  // namespace
}  // namespace semvox
