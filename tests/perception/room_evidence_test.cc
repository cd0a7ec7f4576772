#include "perception/room_evidence.h"

#include <gtest/gtest.h>

#include <cmath>

#include "tests/perception/test_views.h"

namespace semvox {
namespace {

// 40x20 view: the top 5 rows see nothing; of the 600 hit pixels, the left 10 columns are class 2, the rest
// class 0; all at depth 2 m in one grey.
RenderedView GreyView() {
  return testing::MakeView(40, 20, Eigen::Isometry3d::Identity(), [](int x, int y) {
    testing::PixelSample s;
    if (y < 5) return s;
    s.depth = 2.0f;
    s.normal = {0, 0, -1};
    s.color = {128, 128, 128};
    return s;
  });
}

Image<int32_t> Classes() {
  Image<int32_t> c(40, 20, 1, 0);
  for (int y = 0; y < 20; ++y)
    for (int x = 0; x < 10; ++x) c.at(x, y) = 2;
  return c;
}

TEST(RoomViewDescriptor, ClassFractionsAndStatisticsOverHitPixels) {
  const RenderedView view = GreyView();
  const std::vector<float> d = RoomViewDescriptor(view, Classes(), 3);
  ASSERT_EQ(int(d.size()), RoomDescriptorDims(3));
  EXPECT_NEAR(d[0], 0.75, 1e-6);  // 450 of 600 hit pixels.
  EXPECT_NEAR(d[1], 0.0, 1e-6);
  EXPECT_NEAR(d[2], 0.25, 1e-6);
  EXPECT_NEAR(d[3 + 3], 0.0, 1e-3);        // L std: one grey.
  EXPECT_NEAR(d[3 + 6], 0.0, 1e-6);        // No texture.
  EXPECT_NEAR(d[3 + 7], 2.0, 1e-6);        // Mean depth.
  EXPECT_NEAR(d[3 + 8], 0.0, 1e-6);        // Depth std.
  EXPECT_NEAR(d[3 + 9], 600.0 / 800.0, 1e-6);  // Hit fraction.
  EXPECT_NEAR(d[3 + 10], 5.0 / 15.0, 1e-6);    // Rows 5..9 of the upper half hit.
}

TEST(RoomTypeProbabilities, TooFewObjectPixelsMeansOther) {
  const RenderedView view = GreyView();
  const std::vector<bool> is_object = {false, false, true};
  EXPECT_NEAR(ObjectPixelFraction(view, Classes(), is_object), 0.25, 1e-12);
  // A k-NN trained on two descriptors of types 0 and 1.
  std::vector<float> rows(size_t(2 * RoomDescriptorDims(3)), 0.0f);
  rows[0] = 1.0f;
  Result<KnnClassifier> knn = KnnClassifier::Train(rows, RoomDescriptorDims(3), {0, 1}, kNumRoomTypeClasses, KnnOptions{});
  ASSERT_TRUE(knn.ok()) << knn.status().message();
  const std::vector<float> d = RoomViewDescriptor(view, Classes(), 3);
  std::vector<double> p = RoomTypeProbabilities(*knn, d, 0.01, 0.02);
  EXPECT_EQ(p[kOtherRoomTypeIndex], 1.0);
  p = RoomTypeProbabilities(*knn, d, 0.25, 0.02);
  EXPECT_LT(p[kOtherRoomTypeIndex], 0.5);
  double sum = 0;
  for (double v : p) sum += v;
  EXPECT_NEAR(sum, 1.0, 1e-12);
}

}  // namespace
}  // namespace semvox
