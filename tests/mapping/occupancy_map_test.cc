#include "mapping/occupancy_map.h"

#include <gtest/gtest.h>

#include "mapping/octomap_io.h"
#include "tests/test_util.h"

namespace semvox {
namespace {

// A 4 x 3 x 25 grid at 0.1 m whose first voxel has its lower corner at (1.0, 2.0, 0.0).
VoxelGrid SmallGrid() {
  const double r = 0.1;
  VoxelGrid g(r, {int(CoordToKeyIndex(1.05, r)), int(CoordToKeyIndex(2.05, r)), int(CoordToKeyIndex(0.05, r))}, {4, 3, 25});
  g.set_state(g.Index(0, 0, 5), VoxelState::kOccupied);  // In the band.
  g.set_state(g.Index(1, 0, 5), VoxelState::kFree);
  g.set_state(g.Index(2, 0, 0), VoxelState::kOccupied);  // Below the band (floor): ignored.
  g.set_state(g.Index(2, 0, 5), VoxelState::kFree);
  g.set_state(g.Index(3, 2, 20), VoxelState::kOccupied);  // z = 2.05, above the band: ignored.
  return g;
}

TEST(Occupancy, FollowsMapServerConventions) {
  const VoxelGrid g = SmallGrid();
  const OccupancyMap m = ComputeOccupancy(g, 0.0, OccupancyOptions());
  ASSERT_EQ(m.image.width, 4);
  ASSERT_EQ(m.image.height, 3);
  EXPECT_NEAR(m.origin_x, 1.0, 1e-9);
  EXPECT_NEAR(m.origin_y, 2.0, 1e-9);
  // Grid row y = 0 is the bottom image row.
  EXPECT_EQ(m.image.at(0, 2), kPgmOccupied);
  EXPECT_EQ(m.image.at(1, 2), kPgmFree);
  EXPECT_EQ(m.image.at(2, 2), kPgmFree);
  EXPECT_EQ(m.image.at(3, 0), kPgmUnknown);
  // map_server: p = (255 - v) / 255; occupied above 0.65, free below 0.196, unknown in between.
  auto p = [](uint8_t v) { return (255.0 - v) / 255.0; };
  EXPECT_GT(p(kPgmOccupied), 0.65);
  EXPECT_LT(p(kPgmFree), 0.196);
  EXPECT_GT(p(kPgmUnknown), 0.196);
  EXPECT_LT(p(kPgmUnknown), 0.65);
}

TEST(Occupancy, RoundTripsThroughPgmAndYaml) {
  testing::ScratchDir dir("occ");
  const OccupancyMap m = ComputeOccupancy(SmallGrid(), 0.0, OccupancyOptions());
  ASSERT_TRUE(WriteOccupancyMap(m, dir.path().string(), "occupancy").ok());
  const std::string yaml = testing::ReadText(dir.File("occupancy.yaml"));
  EXPECT_NE(yaml.find("image: occupancy.pgm"), std::string::npos);
  EXPECT_NE(yaml.find("negate: 0"), std::string::npos);
  EXPECT_NE(yaml.find("occupied_thresh: 0.65"), std::string::npos);
  EXPECT_NE(yaml.find("free_thresh: 0.196"), std::string::npos);
  EXPECT_NE(yaml.find("origin: [1, 2, 0.0]"), std::string::npos) << yaml;
  Result<OccupancyMap> back = ReadOccupancyMap(dir.File("occupancy.yaml"));
  ASSERT_TRUE(back.ok()) << back.status().message();
  EXPECT_EQ(back->image.data, m.image.data);
  EXPECT_DOUBLE_EQ(back->resolution, 0.1);
  EXPECT_NEAR(back->origin_x, 1.0, 1e-9);
  EXPECT_EQ(back->origin_yaw, 0.0);
}

// A grid on a canonical frame turned against the input frame (mapping/scene_frame.h): the yaw is
// map_server's third origin value.
TEST(Occupancy, OriginCarriesTheYaw) {
  testing::ScratchDir dir("occ_yaw");
  OccupancyMap m = ComputeOccupancy(SmallGrid(), 0.0, OccupancyOptions());
  m.origin_yaw = 0.3316125579;  // 19 degrees.
  ASSERT_TRUE(WriteOccupancyMap(m, dir.path().string(), "occupancy").ok());
  const std::string yaml = testing::ReadText(dir.File("occupancy.yaml"));
  EXPECT_NE(yaml.find("origin: [1, 2, 0.3316125579]"), std::string::npos) << yaml;
  Result<OccupancyMap> back = ReadOccupancyMap(dir.File("occupancy.yaml"));
  ASSERT_TRUE(back.ok()) << back.status().message();
  EXPECT_NEAR(back->origin_yaw, 0.3316125579, 1e-12);
}

TEST(OctomapFile, HoldsExactlyTheFreeAndOccupiedVoxels) {
  testing::ScratchDir dir("bt");
  const VoxelGrid g = SmallGrid();
  ASSERT_TRUE(WriteOctomapBinary(g, dir.File("map.bt")).ok());
  double res = 0;
  auto leaves = ReadOctomapLeaves(dir.File("map.bt"), &res);
  ASSERT_TRUE(leaves.ok());
  EXPECT_DOUBLE_EQ(res, 0.1);
  std::vector<std::pair<VoxelKey, bool>> expected;
  for (size_t i = 0; i < g.size(); ++i) {
    if (g.state(i) == VoxelState::kUnknown) continue;
    const auto c = g.Cell(i);
    expected.push_back({g.KeyOf(c[0], c[1], c[2]), g.state(i) == VoxelState::kOccupied});
  }
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(leaves.value(), expected);
}

}  // namespace
}  // namespace semvox
