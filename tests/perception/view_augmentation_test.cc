// Domain randomisation of training views (perception/view_augmentation.h, training_data.h's styles).
#include "perception/view_augmentation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>

#include "perception/training_data.h"

namespace semvox {
namespace {

// A 64x48 view of two fronto-parallel surfaces with the same flat colour (left half surface 1, right half
// surface 2), 2 m away, and a band of empty pixels at the top.
RenderedView TwoSurfaceView(Image<int32_t>* surface) {
  RenderedView v;
  v.camera = PinholeCamera::FromHorizontalFov(64, 48, 60);
  v.world_from_camera = WorldFromCameraYawPitch(Eigen::Vector3d(0, 0, 1.5), 0, 0);
  v.rgb = ImageRgb8(64, 48, 3, 0);
  v.depth = ImageF32(64, 48, 1, 0.0f);
  v.normal = ImageF32(64, 48, 3, 0.0f);
  v.primitive = Image<int32_t>(64, 48, 1, -1);
  *surface = Image<int32_t>(64, 48, 1, -1);
  for (int y = 8; y < 48; ++y)
    for (int x = 0; x < 64; ++x) {
      for (int c = 0; c < 3; ++c) v.rgb.at(x, y, c) = 120;
      v.depth.at(x, y) = 2.0f;
      v.normal.at(x, y, 0) = -1.0f;  // Facing the camera, which looks along +x.
      v.primitive.at(x, y) = x < 32 ? 1 : 2;
      surface->at(x, y) = x < 32 ? 1 : 2;
    }
  return v;
}

TEST(ViewAugmentation, DeterministicAndKeepsGeometryIds) {
  Image<int32_t> surface;
  RenderedView a = TwoSurfaceView(&surface), b = a;
  const Image<int32_t> primitive = a.primitive;
  ASSERT_TRUE(AugmentView(surface, 7, 11, ViewAugmentationOptions{}, &a).ok());
  ASSERT_TRUE(AugmentView(surface, 7, 11, ViewAugmentationOptions{}, &b).ok());
  EXPECT_EQ(a.rgb.data, b.rgb.data);
  EXPECT_EQ(a.depth.data, b.depth.data);
  EXPECT_EQ(a.primitive.data, primitive.data);
  // Empty pixels stay empty and black.
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 64; ++x) {
      EXPECT_EQ(a.depth.at(x, y), 0.0f);
      EXPECT_EQ(a.rgb.at(x, y, 0) + a.rgb.at(x, y, 1) + a.rgb.at(x, y, 2), 0);
    }
  // Depth noise at 2 m: sigma at most 1.2 mm + 1.9 mm/m² * 4 m² = 8.8 mm; flying pixels need an edge (none
  // between the two surfaces at equal depth), so every depth stays within 5 sigma.
  for (int y = 8; y < 48; ++y)
    for (int x = 0; x < 64; ++x) EXPECT_NEAR(a.depth.at(x, y), 2.0f, 0.045f);
}

// Mean colour of one half of the view.
Eigen::Vector3d MeanColour(const RenderedView& v, bool left) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  int n = 0;
  for (int y = 8; y < 48; ++y)
    for (int x = left ? 0 : 32; x < (left ? 32 : 64); ++x, ++n)
      for (int c = 0; c < 3; ++c) sum[c] += v.rgb.at(x, y, c);
  return sum / n;
}

TEST(ViewAugmentation, ColourNoLongerFollowsTheInputColour) {
  // Recoloured always: two surfaces of the same input colour (grey 120) get different colours in most
  // scenes, and over 20 scenes the colours spread over the colour cube.
  ViewAugmentationOptions o;
  o.recolour_probability = 1.0;
  o.texture_probability = 0.0;
  o.max_colour_noise = 0.0;
  o.max_blur_sigma_px = 0.0;
  int differ = 0;
  std::set<std::array<int, 3>> colours;
  for (uint64_t scene = 0; scene < 20; ++scene) {
    Image<int32_t> surface;
    RenderedView v = TwoSurfaceView(&surface);
    ASSERT_TRUE(AugmentView(surface, scene, 100 + scene, o, &v).ok());
    const Eigen::Vector3d l = MeanColour(v, true), r = MeanColour(v, false);
    differ += (l - r).norm() > 10;
    colours.insert({int(l[0]) / 16, int(l[1]) / 16, int(l[2]) / 16});
  }
  EXPECT_GE(differ, 15);            // Of 20 scenes.
  EXPECT_GE(colours.size(), 10u);   // Input colour 120 grey everywhere; outputs spread over the colour cube.
}

TEST(ViewAugmentation, RejectsBadOptionsAndSizes) {
  Image<int32_t> surface;
  RenderedView v = TwoSurfaceView(&surface);
  ViewAugmentationOptions o;
  o.recolour_probability = 1.5;
  EXPECT_FALSE(AugmentView(surface, 1, 1, o, &v).ok());
  Image<int32_t> small(8, 8, 1, -1);
  EXPECT_FALSE(AugmentView(small, 1, 1, ViewAugmentationOptions{}, &v).ok());
}

TEST(TrainingViews, RandomisedStyleIsDeterministicAndDiffersFromFlat) {
  TrainingViewsOptions flat, randomised;
  flat.style = TrainingStyle::kFlat;
  randomised.style = TrainingStyle::kRandomised;
  auto collect = [](const TrainingViewsOptions& o, std::vector<std::vector<uint8_t>>* rgb, std::vector<int>* labelled) {
    return ForEachApartmentView(102, o, [&](const LabelledView& v) {
      rgb->push_back(v.view->rgb.data);
      int n = 0;
      for (int32_t id : v.nyu40->data) n += id > 0;
      labelled->push_back(n);
      return Status::Ok();
    });
  };
  std::vector<std::vector<uint8_t>> f, r1, r2;
  std::vector<int> lf, l1, l2;
  ASSERT_TRUE(collect(flat, &f, &lf).ok());
  ASSERT_TRUE(collect(randomised, &r1, &l1).ok());
  ASSERT_TRUE(collect(randomised, &r2, &l2).ok());
  ASSERT_FALSE(r1.empty());
  EXPECT_EQ(r1, r2);
  EXPECT_EQ(l1, l2);
  EXPECT_NE(f, r1);
  for (int n : l1) EXPECT_GT(n, 0);  // Every kept view has labelled pixels.
}

}  // namespace
}  // namespace semvox
