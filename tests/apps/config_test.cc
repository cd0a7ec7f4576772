#include "apps/config.h"
#include "apps/semantic_stage.h"

#include <gtest/gtest.h>

namespace semvox {
namespace {

TEST(Config, AppliesKnownKeys) {
  PipelineConfig c;
  ASSERT_TRUE(ParseConfig("input:\n  up: y\n  scale: 0.001\nmapping:\n  voxel_size_m: 0.02\n", "c.yaml", &c).ok());
  EXPECT_EQ(c.load.up, UpAxis::kY);
  EXPECT_DOUBLE_EQ(c.load.scale, 0.001);
  EXPECT_DOUBLE_EQ(c.voxelize.voxel_size_m, 0.02);
}

TEST(Config, VoxelCrfModelChoice) {
  PipelineConfig c;
  EXPECT_EQ(c.semantic.crf_model, VoxelCrfModelChoice::kAuto);
  ASSERT_TRUE(ParseConfig("semantic:\n  voxel_crf_model: cloud\n", "c.yaml", &c).ok());
  EXPECT_EQ(c.semantic.crf_model, VoxelCrfModelChoice::kCloud);
  const Status st = ParseConfig("semantic:\n  voxel_crf_model: clouds\n", "c.yaml", &c);
  EXPECT_NE(st.message().find("Allowed: auto, mesh, cloud"), std::string::npos) << st.message();
}

// Classification views: `auto` is the cover for a mesh; for a point cloud every view is classified (the
// room-type evidence needs them) and only the cover's views go to the support / clutter stage.
TEST(Config, ViewSelectionAutoResolvesByInputKind) {
  PipelineConfig c;
  EXPECT_EQ(c.semantic.view_selection, ClassifyViewSelection::kAuto);
  ASSERT_TRUE(ParseConfig("semantic:\n  view_selection: all_objects_on_cover\n", "c.yaml", &c).ok());
  EXPECT_EQ(c.semantic.view_selection, ClassifyViewSelection::kAllObjectsOnCover);
  EXPECT_STREQ(ClassifyViewSelectionName(c.semantic.view_selection), "all_objects_on_cover");
  Scene mesh;
  for (int i = 0; i < 3; ++i) mesh.mesh.vertices.push_back(Eigen::Vector3f(float(i & 1), float(i >> 1), 0.0f));
  mesh.mesh.faces = {Eigen::Vector3i(0, 1, 2)};
  Scene cloud;
  cloud.mesh.vertices = mesh.mesh.vertices;
  EXPECT_EQ(ResolveViewSelection(ClassifyViewSelection::kAuto, mesh), ClassifyViewSelection::kCover);
  EXPECT_EQ(ResolveViewSelection(ClassifyViewSelection::kAuto, cloud), ClassifyViewSelection::kAllObjectsOnCover);
  EXPECT_EQ(ResolveViewSelection(ClassifyViewSelection::kAll, cloud), ClassifyViewSelection::kAll);
  const Status st = ParseConfig("semantic:\n  view_selection: some\n", "c.yaml", &c);
  EXPECT_NE(st.message().find("all_objects_on_cover"), std::string::npos) << st.message();
}

// `auto` gives the mesh weights only to meshes coloured like the generator's (one colour per surface).
TEST(Config, FlatColouredMeshIsTheGeneratorsStyle) {
  Mesh m;
  for (int i = 0; i < 4; ++i) m.vertices.push_back(Eigen::Vector3f(float(i & 1), float(i >> 1), 0.0f));
  m.faces = {Eigen::Vector3i(0, 1, 2), Eigen::Vector3i(1, 3, 2)};
  EXPECT_FALSE(FlatColouredMesh(m));  // no colours
  m.vertex_colors.assign(4, Rgb8{120, 90, 60});
  EXPECT_TRUE(FlatColouredMesh(m));   // one flat colour
  m.vertex_colors[3] = Rgb8{121, 90, 60};
  EXPECT_TRUE(FlatColouredMesh(m));   // half the faces flat
  m.vertex_colors[0] = Rgb8{119, 90, 60};
  EXPECT_FALSE(FlatColouredMesh(m));  // colour per vertex, as scanned
  EXPECT_FALSE(FlatColouredMesh(Mesh{}));
}

TEST(Config, ErrorsNameTheKeyAndTheRange) {
  PipelineConfig c;
  Status st = ParseConfig("mapping:\n  voxel_sise_m: 0.02\n", "c.yaml", &c);
  EXPECT_EQ(st.code(), StatusCode::kInvalidInput);
  EXPECT_NE(st.message().find("unknown key 'mapping.voxel_sise_m'"), std::string::npos) << st.message();
  st = ParseConfig("mapping:\n  voxel_size_m: 3\n", "c.yaml", &c);
  EXPECT_NE(st.message().find("mapping.voxel_size_m = 3. Allowed range: [0.005, 1]"), std::string::npos) << st.message();
  st = ParseConfig("mapping:\n  enclosure_directions: 4.5\n", "c.yaml", &c);
  EXPECT_NE(st.message().find("must be an integer"), std::string::npos) << st.message();
  st = ParseConfig("input:\n  up: x\n", "c.yaml", &c);
  EXPECT_NE(st.message().find("Allowed: auto, z, y"), std::string::npos) << st.message();
  st = ParseConfig("rendering:\n  a: 1\n", "c.yaml", &c);
  EXPECT_NE(st.message().find("unknown section 'rendering'"), std::string::npos) << st.message();
  st = ParseConfig("occupancy:\n  band_min_above_floor_m: 2\n", "c.yaml", &c);
  EXPECT_NE(st.message().find("band_max_above_floor_m"), std::string::npos) << st.message();
  st = ParseConfig("mapping: [1, 2\n", "c.yaml", &c);
  EXPECT_NE(st.message().find("invalid YAML"), std::string::npos) << st.message();
}

TEST(Config, DumpParsesBackToTheSameConfiguration) {
  PipelineConfig a;
  a.voxelize.voxel_size_m = 0.03;
  a.load.up = UpAxis::kZ;
  PipelineConfig b;
  ASSERT_TRUE(ParseConfig(DumpConfig(a), "dump.yaml", &b).ok());
  EXPECT_EQ(DumpConfig(a), DumpConfig(b));
}

}  // namespace
}  // namespace semvox
