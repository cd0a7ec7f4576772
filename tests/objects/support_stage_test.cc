#include "objects/support_stage.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/ply.h"
#include "io/image_io.h"
#include "objects/support_truth.h"
#include "tests/test_util.h"

namespace semvox {
namespace {

// The stage as `semvox run` calls it: the committed models, the views of generated apartment 101, then
// support_clutter.ply (readable, labels in {0, 1, 2}, probabilities summing to one, some support voxels),
// the top view on a grid and object_proposals.json.
TEST(SupportClutterStage, WritesItsThreeOutputsForGeneratedViews) {
  Result<std::unique_ptr<SupportClutterStage>> stage =
      SupportClutterStage::Create(SupportStageOptions{}, std::string(SEMVOX_SOURCE_DIR) + "/models");
  ASSERT_TRUE(stage.ok()) << stage.status().message();
  int views = 0;
  ASSERT_TRUE(ForEachSupportView(101, TrainingViewsOptions{}, SupportTruthOptions{}, [&](const SupportView& v) {
    if (views >= 8) return Status::Ok();
    ++views;
    return (*stage)->AddView(*v.view);
  }).ok());
  testing::ScratchDir dir("support_stage");
  const std::vector<SupportVoxel> voxels = (*stage)->fusion().Voxels();
  ASSERT_FALSE(voxels.empty());
  std::array<int, 3> min_key{65535, 65535, 65535}, max_key{0, 0, 0};
  for (const SupportVoxel& v : voxels) {
    const int k[3] = {v.key.x, v.key.y, v.key.z};
    for (int a = 0; a < 3; ++a) min_key[size_t(a)] = std::min(min_key[size_t(a)], k[a]), max_key[size_t(a)] = std::max(max_key[size_t(a)], k[a]);
  }
  const VoxelGrid grid(0.05, min_key, {max_key[0] - min_key[0] + 1, max_key[1] - min_key[1] + 1, max_key[2] - min_key[2] + 1});
  ASSERT_TRUE((*stage)->Write(dir.path().string(), grid).ok());
  Result<PlyData> ply = ReadPly(dir.File("support_clutter.ply"));
  ASSERT_TRUE(ply.ok()) << ply.status().message();
  const PlyElement* vertex = ply->Find("vertex");
  ASSERT_NE(vertex, nullptr);
  EXPECT_EQ(vertex->count, voxels.size());
  int support = 0;
  for (size_t i = 0; i < vertex->count; ++i) {
    const double label = vertex->Find("label")->values[i];
    EXPECT_TRUE(label == 0 || label == 1 || label == 2);
    support += label == 1;
    EXPECT_NEAR(vertex->Find("p_support")->values[i] + vertex->Find("p_clutter")->values[i] + vertex->Find("p_other")->values[i], 1.0, 1e-5);
  }
  EXPECT_GT(support, 0);
  Result<ImageRgb8> top = ReadImageRgb8(dir.File("support_clutter_topview.png"));
  ASSERT_TRUE(top.ok());
  EXPECT_EQ(top->width, grid.dims()[0]);
  const nlohmann::json j = nlohmann::json::parse(testing::ReadText(dir.File("object_proposals.json")));
  EXPECT_EQ(j["count"].get<size_t>(), j["proposals"].size());
  for (const auto& p : j["proposals"]) {
    EXPECT_GE(p["score"].get<double>(), 0.0);
    EXPECT_EQ(p["centre"].size(), 3u);
  }
  const SupportStageSummary s = (*stage)->summary();
  EXPECT_EQ(s.views, views);
  EXPECT_EQ(s.voxels, voxels.size());
  std::printf("%s\n", s.BriefReport().c_str());
}

}  // namespace
}  // namespace semvox
