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

// A view unlike every training view says less about its room: at or under the familiar distance it counts fully,
// halfway to twice that distance half, from twice on not at all; the sum stays.
TEST(RoomTypeProbabilities, UnfamiliarViewSaysLessAboutItsRoom) {
  const std::vector<double> p0 = {0.7, 0.2, 0.1, 0.0};
  std::vector<double> p = p0;
  EXPECT_EQ(DiscountUnfamiliarRoomView(0.8, &p), 0.0);
  EXPECT_EQ(p, p0);
  EXPECT_EQ(DiscountUnfamiliarRoomView(1.0, &p), 0.0);
  EXPECT_EQ(DiscountUnfamiliarRoomView(std::nan(""), &p), 0.0);
  EXPECT_EQ(p, p0);
  EXPECT_NEAR(DiscountUnfamiliarRoomView(1.5, &p), 0.5, 1e-12);
  EXPECT_NEAR(p[0], 0.5 * 0.7 + 0.5 * 0.25, 1e-12);
  EXPECT_NEAR(p[3], 0.5 * 0.25, 1e-12);
  EXPECT_NEAR(p[0] + p[1] + p[2] + p[3], 1.0, 1e-12);
  for (double u : {2.0, 7.0}) {
    p = p0;
    EXPECT_EQ(DiscountUnfamiliarRoomView(u, &p), 1.0) << u;
    for (double v : p) EXPECT_NEAR(v, 0.25, 1e-12) << u;
  }

  // The unfamiliarity comes from the same search as the probabilities: a view on a training descriptor is
  // familiar, one far from both is not; a view with too few object pixels is not measured.
  const RenderedView view = GreyView();
  const int dims = RoomDescriptorDims(3);
  const std::vector<float> d = RoomViewDescriptor(view, Classes(), 3);
  std::vector<float> rows;
  for (int r = 0; r < 4; ++r)
    for (int k = 0; k < dims; ++k) rows.push_back(d[size_t(k)] + 0.01f * float(r) * float(k % 3));
  KnnOptions options;
  options.k = 2;
  Result<KnnClassifier> knn = KnnClassifier::Train(rows, dims, {0, 0, 1, 1}, kNumRoomTypeClasses, options);
  ASSERT_TRUE(knn.ok()) << knn.status().message();
  const double familiar = knn->TrainingNeighbourDistanceQuantile(KnnClassifier::kFamiliarQuantile);
  ASSERT_GT(familiar, 0.0);
  double u = -1;
  p = RoomTypeProbabilities(*knn, d, 0.25, 0.02, familiar, &u);
  EXPECT_LE(u, 1.0);
  EXPECT_EQ(p, RoomTypeProbabilities(*knn, d, 0.25, 0.02));
  std::vector<float> far = d;
  for (float& v : far) v += 5.0f;
  RoomTypeProbabilities(*knn, far, 0.25, 0.02, familiar, &u);
  EXPECT_GT(u, 2.0);
  p = RoomTypeProbabilities(*knn, d, 0.01, 0.02, familiar, &u);
  EXPECT_TRUE(std::isnan(u));
  EXPECT_EQ(p[kOtherRoomTypeIndex], 1.0);
  RoomTypeProbabilities(*knn, d, 0.25, 0.02, 0.0, &u);  // No familiar distance: not measured.
  EXPECT_TRUE(std::isnan(u));
}

}  // namespace
}  // namespace semvox
