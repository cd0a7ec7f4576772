#include "perception/superpixels.h"

#include <gtest/gtest.h>

#include <set>

namespace semvox {
namespace {

ImageRgb8 TwoColourImage(int w, int h, int split_x) {
  ImageRgb8 img(w, h, 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const bool left = x < split_x;
      img.at(x, y, 0) = left ? 200 : 20;
      img.at(x, y, 1) = left ? 40 : 60;
      img.at(x, y, 2) = left ? 40 : 220;
    }
  return img;
}

TEST(Superpixels, IdsAreDenseAndCountNearImageAreaOverRegionArea) {
  SuperpixelOptions options;
  options.region_size_px = 16;
  Result<Superpixels> sp = ComputeSuperpixels(TwoColourImage(160, 128, 70), options);
  ASSERT_TRUE(sp.ok()) << sp.status().message();
  std::set<int> used(sp->label.data.begin(), sp->label.data.end());
  EXPECT_EQ(int(used.size()), sp->count);
  EXPECT_EQ(*used.begin(), 0);
  EXPECT_EQ(*used.rbegin(), sp->count - 1);
  const double expected = 160.0 * 128.0 / (16.0 * 16.0);  // 80 grid cells.
  EXPECT_GT(sp->count, expected * 0.5);
  EXPECT_LT(sp->count, expected * 1.5);
}

TEST(Superpixels, FollowAStrongColourEdge) {
  const ImageRgb8 img = TwoColourImage(160, 128, 70);
  Result<Superpixels> sp = ComputeSuperpixels(img, SuperpixelOptions{.region_size_px = 16});
  ASSERT_TRUE(sp.ok());
  // Every superpixel lies on one side of the edge.
  std::vector<int> side(size_t(sp->count), -1);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      int& s = side[size_t(sp->label.at(x, y))];
      const int here = x < 70 ? 0 : 1;
      if (s < 0) s = here;
      EXPECT_EQ(s, here) << "superpixel " << sp->label.at(x, y) << " crosses the edge at (" << x << ", " << y << ")";
      if (s != here) return;
    }
}

TEST(Superpixels, SameInputSameLabels) {
  const ImageRgb8 img = TwoColourImage(96, 64, 30);
  Result<Superpixels> a = ComputeSuperpixels(img, {});
  Result<Superpixels> b = ComputeSuperpixels(img, {});
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_EQ(a->label.data, b->label.data);
}

TEST(Superpixels, RejectsBadOptionsAndEmptyImages) {
  SuperpixelOptions options;
  options.region_size_px = 2;
  Result<Superpixels> sp = ComputeSuperpixels(TwoColourImage(32, 32, 10), options);
  ASSERT_FALSE(sp.ok());
  EXPECT_NE(sp.status().message().find("region_size_px = 2"), std::string::npos) << sp.status().message();
  EXPECT_FALSE(ComputeSuperpixels(ImageRgb8(), {}).ok());
}

TEST(RgbToLab, MatchesReferenceValues) {
  ImageRgb8 img(3, 1, 3);
  const uint8_t colours[3][3] = {{255, 255, 255}, {0, 0, 0}, {255, 0, 0}};
  for (int x = 0; x < 3; ++x)
    for (int c = 0; c < 3; ++c) img.at(x, 0, c) = colours[x][c];
  const ImageF32 lab = RgbToLab(img);
  EXPECT_NEAR(lab.at(0, 0, 0), 100.0, 0.5);
  EXPECT_NEAR(lab.at(0, 0, 1), 0.0, 0.5);
  EXPECT_NEAR(lab.at(1, 0, 0), 0.0, 0.5);
  // sRGB red: L 53.24, a 80.09, b 67.20.
  EXPECT_NEAR(lab.at(2, 0, 0), 53.24, 0.5);
  EXPECT_NEAR(lab.at(2, 0, 1), 80.09, 0.5);
  EXPECT_NEAR(lab.at(2, 0, 2), 67.20, 0.5);
}

}  // namespace
}  // namespace semvox
