// Observations (Table 1 of the MST-CRF paper) on a hand-built view of a fronto-parallel wall at 3 m with
// a box face at 2 m in front of its right part and nothing above row 20.
#include "perception/observations.h"

#include <gtest/gtest.h>

#include <cmath>

#include "tests/perception/test_views.h"

namespace semvox {
namespace {

constexpr int kW = 160, kH = 120;
constexpr int kSkyRows = 20;     // Rows [0, 20) see nothing.
constexpr int kBoxColumn = 100;  // Columns [100, 160) see the box face at 2 m.
constexpr int kWallSplitColumn = 40;  // Wall colour changes at this column (a vertical world line).
constexpr int kWallSplitRow = 80;     // ... and, left of it, at this row (a horizontal world line).
constexpr double kCameraZ = 1.5;

enum Region { kSky, kWallA, kWallB, kWallC, kBox };
Region RegionOf(int x, int y) {
  if (y < kSkyRows) return kSky;
  if (x >= kBoxColumn) return kBox;
  if (x >= kWallSplitColumn) return kWallC;
  return y < kWallSplitRow ? kWallA : kWallB;
}

RenderedView WallAndBoxView() {
  return testing::MakeView(kW, kH, WorldFromCameraYawPitch({0, 0, kCameraZ}, 0, 0), [](int x, int y) {
    testing::PixelSample s;
    const Region r = RegionOf(x, y);
    if (r == kSky) return s;
    s.depth = r == kBox ? 2.0f : 3.0f;
    s.normal = {-1, 0, 0};
    const Rgb8 colours[] = {{0, 0, 0}, {180, 180, 180}, {90, 140, 60}, {60, 60, 200}, {220, 40, 30}};
    s.color = colours[r];
    return s;
  });
}

struct Fixture {
  RenderedView view = WallAndBoxView();
  Superpixels sp;
  ViewObservations obs;
  std::vector<int> region;  // Region of each superpixel, -1 when it mixes regions.
  Fixture() {
    SuperpixelOptions so;
    so.region_size_px = 10;
    sp = ComputeSuperpixels(view.rgb, so).value();
    Result<ViewObservations> r = ComputeObservations(view, sp, ObservationOptions{});
    EXPECT_TRUE(r.ok()) << r.status().message();
    obs = std::move(r).value();
    region.assign(size_t(sp.count), -2);
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x) {
        int& g = region[size_t(sp.label.at(x, y))];
        const int here = RegionOf(x, y);
        g = g == -2 ? here : (g == here ? g : -1);
      }
  }
};

TEST(Observations, PureSuperpixelsOfEachRegionGetTheAnalyticValues) {
  Fixture f;
  ASSERT_EQ(int(f.obs.superpixels.size()), f.sp.count);
  int checked_sky = 0, checked_wall = 0, checked_box = 0;
  for (int s = 0; s < f.sp.count; ++s) {
    const SuperpixelObservation& o = f.obs.superpixels[size_t(s)];
    EXPECT_NEAR(o.z[kObsVerticalPosition], o.centroid_px.y() / kH, 1e-6);
    if (f.region[size_t(s)] == kSky) {
      ++checked_sky;
      EXPECT_FALSE(o.has_depth);
      for (int d = kImageObservationDims; d < kObservationDims; ++d) EXPECT_EQ(o.z[size_t(d)], 0.0f) << "dim " << d;
      EXPECT_NEAR(o.z[kObsLabMeanL], 0.0, 1e-3);
      continue;
    }
    if (f.region[size_t(s)] < 0) continue;
    const bool box = f.region[size_t(s)] == kBox;
    ASSERT_TRUE(o.has_depth);
    const double depth = box ? 2.0 : 3.0;
    (box ? checked_box : checked_wall)++;
    EXPECT_NEAR(o.z[kObsDepth], depth, 1e-5);
    // Height of the centroid: z = camera z - depth * (row - cy) / fy (rows grow downwards).
    EXPECT_NEAR(o.z[kObsHeight], kCameraZ - depth * (o.centroid_px.y() - f.view.camera.cy) / f.view.camera.fy, 1e-4);
    EXPECT_NEAR(o.centroid_world.x(), depth, 1e-5);
    EXPECT_NEAR(o.z[kObsPlanarity], 0.0, 1e-4);
    EXPECT_NEAR(o.z[kObsOrientation], 1.0, 1e-4);  // A wall: the normal is horizontal.
    EXPECT_NEAR(std::abs(o.normal_world.x()), 1.0, 1e-4);
    EXPECT_LT(o.normal_world.x(), 0);  // Turned towards the camera.
    EXPECT_GE(o.z[kObsNeighbourPlanarity], 0.0f);
    EXPECT_NEAR(o.z[kObsLabStdL], 0.0, 1e-2);  // One colour.
    if (!box) {
      // Never in front of a neighbour: the box is nearer, the wall and sky are not compared.
      EXPECT_EQ(o.z[kObsInFrontMean], 0.0f);
      EXPECT_EQ(o.z[kObsInFrontStd], 0.0f);
    }
  }
  EXPECT_GT(checked_sky, 5);
  EXPECT_GT(checked_wall, 20);
  EXPECT_GT(checked_box, 10);
}

TEST(Observations, BoxSuperpixelsBesideTheWallAreInFrontByOneMetre) {
  Fixture f;
  int checked = 0;
  for (const auto& [i, j] : f.obs.image_adjacency) {
    for (auto [box, wall] : {std::pair{i, j}, std::pair{j, i}}) {
      if (f.region[size_t(box)] != kBox || f.region[size_t(wall)] < kWallA || f.region[size_t(wall)] > kWallC) continue;
      const SuperpixelObservation& o = f.obs.superpixels[size_t(box)];
      // Neighbours are the wall (diff 1 m) and other box superpixels (diff 0): the mean is in (0, 1].
      EXPECT_GT(o.z[kObsInFrontMean], 0.0f);
      EXPECT_LE(o.z[kObsInFrontMean], 1.0f + 1e-5f);
      EXPECT_GE(o.z[kObsInFrontStd], 0.0f);
      ++checked;
    }
  }
  EXPECT_GT(checked, 3);
}

TEST(VanishingMembership, WorldVerticalAndHorizontalEdgesPointAtTheirAxes) {
  const RenderedView view = WallAndBoxView();
  const Image<int8_t> m = VanishingMembership(view, RgbToLab(view.rgb), ObservationOptions{});
  // Away from corners, the vertical wall-colour line (x = 40) points at the vanishing point of world Z, the
  // horizontal one (y = 80) at that of world Y (the camera looks along +X with no pitch).
  for (int y = kSkyRows + 3; y < kH - 3; ++y) {
    if (std::abs(y - kWallSplitRow) < 3) continue;
    EXPECT_EQ(m.at(kWallSplitColumn, y), 2) << "row " << y;
    EXPECT_EQ(m.at(kWallSplitColumn - 1, y), 2) << "row " << y;
    EXPECT_EQ(m.at(kWallSplitColumn + 5, y), -1) << "row " << y;  // Flat colour: no edge.
  }
  for (int x = 3; x < kWallSplitColumn - 3; ++x) {
    EXPECT_EQ(m.at(x, kWallSplitRow), 1) << "column " << x;
    EXPECT_EQ(m.at(x, kWallSplitRow - 1), 1) << "column " << x;
  }
}

TEST(Observations, VanishingEntropyIsZeroAlongOneDirectionAndPositiveWhereTwoMeet) {
  Fixture f;
  const Image<int8_t> m = VanishingMembership(f.view, RgbToLab(f.view.rgb), ObservationOptions{});
  // Recount each superpixel's boundary histogram from the membership image and check Eq. 5 against it.
  std::vector<std::array<int, 4>> hist(size_t(f.sp.count));
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const int s = f.sp.label.at(x, y);
      const bool boundary = (x > 0 && f.sp.label.at(x - 1, y) != s) || (x + 1 < kW && f.sp.label.at(x + 1, y) != s) ||
                            (y > 0 && f.sp.label.at(x, y - 1) != s) || (y + 1 < kH && f.sp.label.at(x, y + 1) != s);
      if (boundary && m.at(x, y) >= 0) ++hist[size_t(s)][size_t(m.at(x, y))];
    }
  int single = 0, mixed = 0;
  for (int s = 0; s < f.sp.count; ++s) {
    const float h = f.obs.superpixels[size_t(s)].z[kObsVanishingEntropy];
    EXPECT_NEAR(h, HistogramEntropy(hist[size_t(s)]), 1e-6);
    int bins = 0;
    for (int c : hist[size_t(s)]) bins += c > 0;
    if (bins == 1) {
      ++single;
      EXPECT_EQ(h, 0.0f);
    }
    if (bins >= 2) {
      ++mixed;
      EXPECT_GT(h, 0.0f);
    }
  }
  EXPECT_GT(single, 5);
  EXPECT_GT(mixed, 0);
}

TEST(Observations, AdjacencyIsSortedUniqueAndSymmetricWithTheLabelImage) {
  Fixture f;
  for (size_t k = 0; k < f.obs.image_adjacency.size(); ++k) {
    const auto& [i, j] = f.obs.image_adjacency[k];
    EXPECT_LT(i, j);
    if (k > 0) {
      EXPECT_LT(f.obs.image_adjacency[k - 1], f.obs.image_adjacency[k]);
    }
  }
  // Pixel (kBoxColumn - 1, 60) and (kBoxColumn, 60) are in adjacent superpixels.
  const int a = f.sp.label.at(kBoxColumn - 1, 60), b = f.sp.label.at(kBoxColumn, 60);
  ASSERT_NE(a, b);
  EXPECT_TRUE(std::binary_search(f.obs.image_adjacency.begin(), f.obs.image_adjacency.end(),
                                 std::pair{std::min(a, b), std::max(a, b)}));
}

TEST(HistogramEntropy, Eq5OnHandComputedHistograms) {
  EXPECT_DOUBLE_EQ(HistogramEntropy({0, 0, 0, 0}), 0.0);
  EXPECT_DOUBLE_EQ(HistogramEntropy({7, 0, 0, 0}), 0.0);
  EXPECT_NEAR(HistogramEntropy({3, 3, 0, 0}), std::log(2.0), 1e-12);
  EXPECT_NEAR(HistogramEntropy({1, 1, 1, 1}), std::log(4.0), 1e-12);
  // p = (1/2, 1/4, 1/4, 0): H = 1.5 log 2.
  EXPECT_NEAR(HistogramEntropy({2, 1, 1, 0}), 1.5 * std::log(2.0), 1e-12);
}

TEST(Observations, RejectsMismatchedSizes) {
  RenderedView view = WallAndBoxView();
  Superpixels sp;
  sp.label = Image<int32_t>(10, 10, 1, 0);
  sp.count = 1;
  Result<ViewObservations> r = ComputeObservations(view, sp, {});
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().code(), StatusCode::kInvalidInput);
}

}  // namespace
}  // namespace semvox
