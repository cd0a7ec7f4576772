#include "objects/support_fusion.h"

#include <gtest/gtest.h>

#include "core/ply.h"
#include "objects/support_clutter.h"
#include "tests/perception/test_views.h"
#include "tests/test_util.h"

namespace semvox {
namespace {

// Two hand-made views whose pixels fall in two voxels: the fused probabilities are the per-pixel means,
// the labels their argmax, and support_clutter.ply reads back with core/ply.h with the documented layout.
TEST(SupportClutterFusion, WritesAValidPlyWithMeanProbabilities) {
  auto make = [](float p_support) {
    RenderedView v = testing::MakeView(4, 2, Eigen::Isometry3d::Identity(), [](int, int) {
      testing::PixelSample s;
      s.depth = 1.f;
      return s;
    });
    for (int y = 0; y < 2; ++y)
      for (int x = 0; x < 4; ++x) v.voxel_key.at(x, y) = VoxelKey{uint16_t(32768 + (x < 2 ? 0 : 1)), 32768, 32770};
    v.primitive.at(3, 1) = -1;  // A miss: not fused.
    std::vector<float> p;
    for (int i = 0; i < 8; ++i) {
      const bool left = i % 4 < 2;
      p.insert(p.end(), left ? std::initializer_list<float>{p_support, 0.1f, 0.9f - p_support} : std::initializer_list<float>{0.1f, 0.7f, 0.2f});
    }
    return std::make_pair(v, p);
  };
  SupportClutterFusion fusion;
  for (float ps : {0.8f, 0.4f}) {
    auto [view, p] = make(ps);
    ASSERT_TRUE(fusion.AddView(view, p).ok());
  }
  EXPECT_FALSE(fusion.AddView(make(0.5f).first, std::vector<float>(5)).ok());
  testing::ScratchDir dir("support_fusion");
  const std::string path = dir.File("support_clutter.ply");
  ASSERT_TRUE(fusion.WritePly(path).ok());
  Result<PlyData> ply = ReadPly(path);
  ASSERT_TRUE(ply.ok()) << ply.status().message();
  const PlyElement* vertex = ply->Find("vertex");
  ASSERT_NE(vertex, nullptr);
  ASSERT_EQ(vertex->count, 2u);
  const char* names[] = {"x", "y", "z", "label", "p_support", "p_clutter", "p_other"};
  const PlyType types[] = {PlyType::kFloat32, PlyType::kFloat32, PlyType::kFloat32, PlyType::kUInt8,
                           PlyType::kFloat32, PlyType::kFloat32, PlyType::kFloat32};
  ASSERT_EQ(vertex->properties.size(), 7u);
  for (int k = 0; k < 7; ++k) {
    EXPECT_EQ(vertex->properties[size_t(k)].name, names[k]);
    EXPECT_EQ(vertex->properties[size_t(k)].type, types[k]);
  }
  // Voxel 0 (key x 32768): mean p_support (0.8 + 0.4) / 2 = 0.6 -> support (label 1); centre x = 0.025.
  EXPECT_NEAR(vertex->Find("x")->values[0], 0.025, 1e-6);
  EXPECT_NEAR(vertex->Find("z")->values[0], 0.125, 1e-6);
  EXPECT_EQ(vertex->Find("label")->values[0], 1);
  EXPECT_NEAR(vertex->Find("p_support")->values[0], 0.6, 1e-6);
  EXPECT_NEAR(vertex->Find("p_other")->values[0], 0.3, 1e-6);
  // Voxel 1: clutter (label 2) from 3 pixels per view.
  EXPECT_EQ(vertex->Find("label")->values[1], 2);
  EXPECT_NEAR(vertex->Find("p_clutter")->values[1], 0.7, 1e-6);
  EXPECT_EQ(fusion.Voxels()[1].observations, 6);
  // Top view on a grid holding both voxels: column (0, 0) green (support), (1, 0) red (clutter).
  VoxelGrid grid(0.05, {32768, 32768, 32768}, {2, 1, 4});
  const ImageRgb8 top = fusion.TopView(grid);
  EXPECT_EQ(top.at(0, 0, 1), 170);
  EXPECT_EQ(top.at(1, 0, 0), 220);
}

}  // namespace
}  // namespace semvox
