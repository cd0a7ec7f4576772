#include "apps/config.h"
#include "pipeline/semantic_options.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

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
  EXPECT_EQ(ResolveViewSelection(ClassifyViewSelection::kAuto, cloud), ClassifyViewSelection::kCover);
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
  EXPECT_NE(st.message().find("mapping.voxel_size_m = 3 is out of range [0.005, 1]"), std::string::npos) << st.message();
  st = ParseConfig("mapping:\n  enclosure_directions: 4.5\n", "c.yaml", &c);
  EXPECT_NE(st.message().find("must be an integer"), std::string::npos) << st.message();
  st = ParseConfig("input:\n  up: w\n", "c.yaml", &c);
  EXPECT_NE(st.message().find("Allowed: auto, z, y, -y, x, -x, -z"), std::string::npos) << st.message();
  st = ParseConfig("rendering:\n  a: 1\n", "c.yaml", &c);
  EXPECT_NE(st.message().find("unknown section 'rendering'"), std::string::npos) << st.message();
  st = ParseConfig("occupancy:\n  band_min_above_floor_m: 2\n", "c.yaml", &c);
  EXPECT_NE(st.message().find("band_max_above_floor_m"), std::string::npos) << st.message();
  st = ParseConfig("mapping: [1, 2\n", "c.yaml", &c);
  EXPECT_NE(st.message().find("invalid YAML"), std::string::npos) << st.message();
}

// Every key users can set is described once, in its stage's options table: meaning, range or words, and a
// default inside them.
TEST(Config, EveryKeyHasADocARangeAndADefaultInside) {
  const PipelineConfig defaults;
  std::set<std::string> seen;
  ASSERT_GT(ConfigKeys().size(), 100u);
  for (const ConfigKey& k : ConfigKeys()) {
    const OptionSpec& spec = k.option.spec;
    const std::string full = k.section + "." + spec.key;
    EXPECT_TRUE(seen.insert(full).second) << full << " is listed twice";
    EXPECT_FALSE(spec.doc.empty()) << full;
    if (spec.is_number()) {
      EXPECT_LT(spec.min, spec.max) << full;
      const double v = k.option.get_number(defaults);
      EXPECT_TRUE(spec.Contains(v)) << full << " = " << v << " is outside " << spec.Range();
    } else {
      EXPECT_GE(spec.choices.size(), 2u) << full;
      EXPECT_FALSE(k.option.get_word(defaults).empty()) << full << ": the default is none of " << spec.Range();
    }
  }
}

// A value outside the range in the file is refused with the section, the key and the range.
TEST(Config, OutOfRangeValuesNameTheKeyAndTheRange) {
  for (const ConfigKey& k : ConfigKeys()) {
    const OptionSpec& spec = k.option.spec;
    if (!spec.is_number()) continue;
    const std::string full = k.section + "." + spec.key;
    for (const double v : {spec.max + std::max(1.0, std::abs(spec.max)), spec.min - std::max(1.0, std::abs(spec.min))}) {
      PipelineConfig c;
      const std::string text = FormatOptionNumber(v, spec.integer);
      const Status st = ParseConfig(k.section + ":\n  " + spec.key + ": " + text + "\n", "c.yaml", &c);
      EXPECT_EQ(st.code(), StatusCode::kInvalidInput) << full << " = " << text;
      EXPECT_NE(st.message().find(full + " = " + text + " is out of range " + spec.Range()), std::string::npos)
          << st.message();
    }
  }
}

// Check() of every stage covers every key of its table: a field set out of range is named.
TEST(Config, CheckNamesEveryFieldOutOfRange) {
  int checked = 0;
  for (const ConfigKey& k : ConfigKeys()) {
    const OptionSpec& spec = k.option.spec;
    if (!spec.is_number()) continue;
    PipelineConfig c;
    const double v = spec.max + std::max(1.0, std::abs(spec.max));
    k.option.set_number(c, v);
    if (k.option.get_number(c) != v) continue;  // A 0 / 1 switch holds no other value.
    const Status st = CheckConfig(c);
    EXPECT_EQ(st.code(), StatusCode::kInvalidInput) << k.section << "." << spec.key;
    EXPECT_NE(st.message().find(k.section + "." + spec.key + " = "), std::string::npos) << st.message();
    EXPECT_NE(st.message().find("out of range " + spec.Range()), std::string::npos) << st.message();
    ++checked;
  }
  EXPECT_GT(checked, 90);
}

TEST(Config, StageCheckNamesTheFieldItsValueAndTheRange) {
  VoxelizeOptions v;
  std::string error;
  EXPECT_TRUE(v.Check(&error)) << error;
  v.voxel_size_m = 0;
  EXPECT_FALSE(v.Check(&error));
  EXPECT_EQ(error, "voxel_size_m = 0 is out of range [0.005, 1]");
  RoomTypeCrfOptions r;
  r.cell_size_m = 0.01;
  EXPECT_FALSE(r.Check(&error));
  EXPECT_EQ(error, "cell_size_m = 0.01 is out of range [0.05, 5]");
  SemanticStageOptions s;
  s.crf.planes.min_voxels = 1;
  EXPECT_FALSE(s.Check(&error));
  EXPECT_EQ(error, "min_voxels = 1 is out of range [3, 1000000]");
  // Rules between fields stay, named by field.
  OccupancyOptions o;
  o.band_min_above_floor_m = 2;
  EXPECT_FALSE(o.Check(&error));
  EXPECT_NE(error.find("band_max_above_floor_m"), std::string::npos) << error;
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
