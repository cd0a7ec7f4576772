#include "rooms/floor_plan.h"

#include <gtest/gtest.h>

#include "mapping/occupancy_map.h"
#include "rooms/room_segmentation.h"
#include "tests/rooms/rooms_test_util.h"

namespace semvox {
namespace {

using testing::GreyMap;
using testing::VoxelRooms;

TEST(FloorPlanFromImage, SmallCompactIslandsAreClutterWallPiecesAreNot) {
  GreyMap map(100, 100);
  map.Fill(0.5, 0.5, 4.5, 4.5, 255);
  map.Fill(1.0, 1.0, 1.3, 1.3, 0);   // A chair: 0.3 m x 0.3 m.
  map.Fill(2.0, 0.5, 2.05, 2.5, 0);  // A thin wall piece attached to the outer wall.
  map.Fill(3.0, 2.0, 3.05, 4.0, 0);  // A loose thin wall piece 2 m long: too long for furniture.
  const FloorPlan plan = FloorPlanFromImage(map.image, 0.05, FloorPlanOptions());
  EXPECT_EQ(plan.at(22, 22), FloorCell::kClutter);
  EXPECT_EQ(plan.at(40, 20), FloorCell::kWall);
  EXPECT_EQ(plan.at(60, 60), FloorCell::kWall);
  EXPECT_EQ(plan.at(0, 0), FloorCell::kWall);
  EXPECT_EQ(plan.at(15, 60), FloorCell::kFree);
  EXPECT_EQ(plan.Count(FloorCell::kClutter), 36u);
}

TEST(FloorPlanFromImage, ThresholdFollowsTheBenchmark) {
  GreyMap map(10, 10);
  map.image.at(3, 3) = 251;
  map.image.at(4, 4) = 250;
  const FloorPlan plan = FloorPlanFromImage(map.image, 0.05, FloorPlanOptions());
  EXPECT_EQ(plan.at(3, 3), FloorCell::kFree);
  EXPECT_EQ(plan.at(4, 4), FloorCell::kWall);
}

// Two 3 m x 3 m rooms; the wall between them (x cells 60-61) has a 0.9 m door with a lintel from
// 2.0 m to the 2.5 m ceiling; a 1 m high cabinet stands in the left room; a lamp hangs from the
// ceiling to 2.1 m in the middle of the right room.
struct TwoVoxelRooms {
  VoxelRooms v{124, 64};
  TwoVoxelRooms() {
    const double top = v.ceiling_m;
    v.Box(1, 1, 123, 2, 0, top);       // Outer walls.
    v.Box(1, 62, 123, 63, 0, top);
    v.Box(1, 1, 2, 63, 0, top);
    v.Box(122, 1, 123, 63, 0, top);
    v.Box(60, 1, 62, 63, 0.05, top);   // Inner wall...
    v.Box(60, 20, 62, 38, 0.05, 2.0, VoxelState::kFree);  // ...with its door (0.9 m) under a lintel.
    v.Box(10, 10, 20, 20, 0.05, 1.0);  // Cabinet.
    v.Box(90, 30, 94, 34, 2.1, top);   // Lamp hanging from the ceiling.
  }
};

TEST(FloorPlanFromVoxels, FindsWallsClutterDoorsAndCeilingHeight) {
  TwoVoxelRooms rooms;
  const VoxelGrid& g = rooms.v.grid;
  const double floor_z = 0.05, ceiling_z = 2.5;
  const OccupancyMap occ = ComputeOccupancy(g, floor_z, OccupancyOptions());
  const FloorPlan plan = FloorPlanFromVoxels(g, floor_z, ceiling_z, occ, FloorPlanOptions());
  ASSERT_EQ(plan.width(), 124);
  ASSERT_EQ(plan.height(), 64);
  auto cell = [&](int ix, int iy) { return plan.at(ix, plan.height() - 1 - iy); };  // Grid to image rows.
  EXPECT_EQ(cell(60, 5), FloorCell::kWall);
  EXPECT_EQ(cell(1, 30), FloorCell::kWall);
  EXPECT_EQ(cell(15, 15), FloorCell::kClutter);
  EXPECT_EQ(cell(30, 30), FloorCell::kFree);
  EXPECT_EQ(cell(92, 32), FloorCell::kFree) << "a lamp in the middle of a room is not a lintel";
  for (int iy = 21; iy < 37; ++iy) {
    EXPECT_EQ(cell(60, iy), FloorCell::kDoor) << iy;
    EXPECT_EQ(cell(61, iy), FloorCell::kDoor) << iy;
  }
  EXPECT_EQ(plan.Count(FloorCell::kDoor), 36u);
  EXPECT_EQ(plan.ceiling_step_cells, 0u) << "a lamp and a lintel are not ceiling zones";
  EXPECT_NEAR(plan.ceiling_height_m.at(30, plan.height() - 1 - 30), ceiling_z - floor_z, 0.06);
  // Segmented: the two rooms, split at the door.
  const RoomSegmentation seg = SegmentRooms(plan, RoomSegmentationOptions());
  EXPECT_EQ(seg.num_rooms, 2);
  EXPECT_NE(seg.room_ids.at(30, 30), seg.room_ids.at(90, 30));
  // The cabinet belongs to the left room's extent but has no id in room_ids.
  EXPECT_EQ(seg.room_ids.at(15, plan.height() - 1 - 15), 0);
  EXPECT_EQ(seg.room_extent_ids.at(15, plan.height() - 1 - 15), seg.room_ids.at(30, 30));
}

// One 6 m x 3 m space without an inner wall; the right half has a ceiling lowered from 2.5 m to 2.2 m.
// The ceiling step is a room border; the lowered ceiling near the walls is not mistaken for lintels.
TEST(FloorPlanFromVoxels, CeilingStepSeparatesRoomsLoweredCeilingIsNoDoor) {
  VoxelRooms v(124, 64);
  const double top = v.ceiling_m;
  v.Box(1, 1, 123, 2, 0, top);
  v.Box(1, 62, 123, 63, 0, top);
  v.Box(1, 1, 2, 63, 0, top);
  v.Box(122, 1, 123, 63, 0, top);
  v.Box(62, 2, 122, 62, 2.2, top);  // Lowered ceiling over the right half.
  const double floor_z = 0.05, ceiling_z = 2.5;
  const OccupancyMap occ = ComputeOccupancy(v.grid, floor_z, OccupancyOptions());
  FloorPlan plan = FloorPlanFromVoxels(v.grid, floor_z, ceiling_z, occ, FloorPlanOptions());
  EXPECT_GT(plan.ceiling_step_cells, 50u);
  EXPECT_EQ(plan.Count(FloorCell::kDoor), plan.ceiling_step_cells) << "no lintel doors under a lowered ceiling";
  const int y = plan.height() - 1 - 30;
  EXPECT_NEAR(plan.ceiling_height_m.at(100, y), 2.2 - floor_z, 0.06);
  RoomSegmentation seg = SegmentRooms(plan, RoomSegmentationOptions());
  EXPECT_EQ(seg.num_rooms, 2);
  EXPECT_NE(seg.room_ids.at(30, y), seg.room_ids.at(100, y));
  // With the cue off it is one room.
  FloorPlanOptions off;
  off.ceiling_step_m = 0;
  plan = FloorPlanFromVoxels(v.grid, floor_z, ceiling_z, occ, off);
  EXPECT_EQ(SegmentRooms(plan, RoomSegmentationOptions()).num_rooms, 1);
}

TEST(FloorPlanOptions, CheckNamesTheField) {
  FloorPlanOptions o;
  std::string error;
  EXPECT_TRUE(o.Check(&error));
  o.door_max_width_m = 0.2;
  EXPECT_FALSE(o.Check(&error));
  EXPECT_NE(error.find("door_max_width_m = 0.2"), std::string::npos) << error;
}

}  // namespace
}  // namespace semvox
