// End to end on the bundled demo apartment: voxelise, floor plan, rooms. The apartment has three rooms
// (living room with kitchen [0,5]x[0,6] m, bedroom [5,8]x[2.5,6], bathroom [5,8]x[0,2.5]) joined by
// 0.85 m doors with lintels. Floors stated here: exactly 3 rooms, recall >= 0.95, precision >= 0.95 for
// both methods, and both doors found from their lintels.
#include <gtest/gtest.h>

#include "mapping/occupancy_map.h"
#include "mapping/voxelizer.h"
#include "rooms/floor_plan.h"
#include "rooms/room_score.h"
#include "rooms/room_segmentation.h"
#include "scenegen/demo_scene.h"

namespace semvox {
namespace {

struct DemoPlan {
  FloorPlan plan;
  ImageU16 truth;  // Ground-truth room per cell of the room space (free, door, clutter).
};

const DemoPlan& Demo() {
  static const DemoPlan* demo = [] {
    Scene scene;
    scene.format = "ply";
    scene.mesh = BuildDemoApartment();
    Result<VoxelMap> map = Voxelize(scene, VoxelizeOptions());
    EXPECT_TRUE(map.ok()) << map.status().message();
    auto* d = new DemoPlan;
    const OccupancyMap occ = ComputeOccupancy(map->grid, map->floor_z, OccupancyOptions());
    d->plan = FloorPlanFromVoxels(map->grid, map->floor_z, map->ceiling_z, occ, FloorPlanOptions());
    d->truth = ImageU16(d->plan.width(), d->plan.height(), 1, 0);
    const double r = d->plan.resolution_m;
    for (int y = 0; y < d->plan.height(); ++y)
      for (int x = 0; x < d->plan.width(); ++x) {
        const FloorCell c = d->plan.at(x, y);
        if (c != FloorCell::kFree && c != FloorCell::kDoor && c != FloorCell::kClutter) continue;
        const double wx = d->plan.origin_x + (x + 0.5) * r, wy = d->plan.origin_y + (d->plan.height() - y - 0.5) * r;
        if (wx < 0 || wx > 8 || wy < 0 || wy > 6) continue;
        d->truth.at(x, y) = wx < 5 ? 1 : wy > 2.5 ? 2 : 3;
      }
    return d;
  }();
  return *demo;
}

TEST(DemoApartmentRooms, DoorsAreFoundFromTheirLintels) {
  const FloorPlan& plan = Demo().plan;
  // Two doors of 0.85 m through a 0.15 m wall at 5 cm: about 17 x 3 cells each.
  const size_t doors = plan.Count(FloorCell::kDoor);
  EXPECT_GE(doors, 2u * 14 * 2);
  EXPECT_LE(doors, 2u * 20 * 5);
  EXPECT_GT(plan.Count(FloorCell::kWall), 0u);
  EXPECT_GT(plan.Count(FloorCell::kClutter), 0u);
}

TEST(DemoApartmentRooms, GivesItsThreeRooms) {
  for (const std::string& name : RoomSegmentationMethodNames()) {
    RoomSegmentationOptions o;
    ASSERT_TRUE(ParseRoomSegmentationMethod(name, &o.method));
    const RoomSegmentation rooms = SegmentRooms(Demo().plan, o);
    EXPECT_EQ(rooms.num_rooms, 3) << name;
    const RoomScore s = ScoreRooms(rooms.room_extent_ids, Demo().truth);
    EXPECT_GE(s.recall, 0.95) << name;
    EXPECT_GE(s.precision, 0.95) << name;
  }
}

}  // namespace
}  // namespace semvox
