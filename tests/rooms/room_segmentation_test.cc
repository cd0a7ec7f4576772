#include "rooms/room_segmentation.h"

#include <gtest/gtest.h>

#include <random>
#include <set>
#include <string>

#include "rooms/room_score.h"
#include "tests/rooms/rooms_test_util.h"

namespace semvox {
namespace {

using testing::GreyMap;
using testing::TwoRoomsWithDoor;

const RoomSegmentationMethod kMethods[] = {RoomSegmentationMethod::kDistanceWatershed,
                                           RoomSegmentationMethod::kMorphological};

RoomSegmentationOptions WithMethod(RoomSegmentationMethod m) {
  RoomSegmentationOptions o;
  o.method = m;
  return o;
}

// Every free or door cell has exactly one id in [1, num_rooms]; nothing else has one; every id is used.
void ExpectEveryFloorCellInOneRoom(const FloorPlan& plan, const RoomSegmentation& rooms) {
  std::set<int> used;
  for (int y = 0; y < plan.height(); ++y)
    for (int x = 0; x < plan.width(); ++x) {
      const int id = rooms.room_ids.at(x, y);
      if (plan.IsFloor(x, y)) {
        ASSERT_GE(id, 1) << "floor cell (" << x << ", " << y << ") has no room";
        ASSERT_LE(id, rooms.num_rooms);
        used.insert(id);
      } else {
        ASSERT_EQ(id, 0) << "non-floor cell (" << x << ", " << y << ") has room " << id;
      }
    }
  EXPECT_EQ(int(used.size()), rooms.num_rooms);
}

TEST(SegmentRooms, TwoRoomsJoinedByADoorGiveTwoRooms) {
  const GreyMap map = TwoRoomsWithDoor();
  const FloorPlan plan = FloorPlanFromImage(map.image, 0.05, FloorPlanOptions());
  for (RoomSegmentationMethod m : kMethods) {
    const RoomSegmentation rooms = SegmentRooms(plan, WithMethod(m));
    EXPECT_EQ(rooms.num_rooms, 2) << RoomSegmentationMethodName(m);
    ExpectEveryFloorCellInOneRoom(plan, rooms);
    // The two rooms are the two sides of the wall.
    EXPECT_NE(rooms.room_ids.at(40, 40), rooms.room_ids.at(150, 40)) << RoomSegmentationMethodName(m);
    EXPECT_EQ(rooms.room_ids.at(20, 20), rooms.room_ids.at(80, 60)) << RoomSegmentationMethodName(m);
  }
}

TEST(SegmentRooms, OneRoomStaysOneRoom) {
  GreyMap map(120, 100);
  map.Fill(0.5, 0.5, 5.5, 4.5, 255);
  const FloorPlan plan = FloorPlanFromImage(map.image, 0.05, FloorPlanOptions());
  for (RoomSegmentationMethod m : kMethods) {
    const RoomSegmentation rooms = SegmentRooms(plan, WithMethod(m));
    EXPECT_EQ(rooms.num_rooms, 1) << RoomSegmentationMethodName(m);
    ExpectEveryFloorCellInOneRoom(plan, rooms);
  }
}

// A wide opening between two rooms is not a door: one room. The same opening with door cells across it
// (a lintel seen in 3D) separates them.
TEST(SegmentRooms, DoorCellsFromTheVoxelMapSeparateRooms) {
  GreyMap map(200, 90);
  map.Fill(0.5, 0.5, 9.5, 2.0, 255);  // A 1.5 m wide, 9 m long hall: no constriction anywhere.
  FloorPlan plan = FloorPlanFromImage(map.image, 0.05, FloorPlanOptions());
  const RoomSegmentationOptions o;
  EXPECT_EQ(SegmentRooms(plan, o).num_rooms, 1);
  for (int y = 0; y < plan.height(); ++y)
    for (int x = 98; x < 100; ++x)
      if (plan.at(x, y) == FloorCell::kFree) plan.cells.at(x, y) = uint8_t(FloorCell::kDoor);
  for (RoomSegmentationMethod m : kMethods) {
    const RoomSegmentation rooms = SegmentRooms(plan, WithMethod(m));
    EXPECT_EQ(rooms.num_rooms, 2) << RoomSegmentationMethodName(m);
    ExpectEveryFloorCellInOneRoom(plan, rooms);
    EXPECT_NE(rooms.room_ids.at(40, 25), rooms.room_ids.at(160, 25));
  }
}

// A closet 0.5 m deep (inscribed radius 0.25 m, under min_room_radius_m) opening along its whole 1.5 m
// width into a 4 m room: the opening lies on the straight continuation of the room's wall, so a wall-gap
// line runs through it. Without door cells it is an alcove of the room. With door cells across it (a
// lintel seen in 3D) it is a room of its own, however the line and the narrow radius would decide; with
// door_min_room_radius_m at min_room_radius_m (no exception for narrow rooms behind a door) it merges again.
TEST(SegmentRooms, ClosetBehindADoorOpeningIsARoomThoughNarrow) {
  GreyMap map(130, 90);                // 6.5 m x 4.5 m.
  map.Fill(0.5, 0.5, 4.5, 4.0, 255);   // The room.
  map.Fill(4.6, 1.0, 5.1, 2.5, 255);   // The closet, 0.5 m x 1.5 m, behind a 0.1 m wall at x = 4.5 m ...
  map.Fill(4.5, 1.0, 4.6, 2.5, 255);   // ... which is open over the closet's whole width.
  FloorPlan plan = FloorPlanFromImage(map.image, 0.05, FloorPlanOptions());
  const RoomSegmentationOptions o;
  ASSERT_GT(o.wall_gap_max_m, 1.5);
  EXPECT_EQ(SegmentRooms(plan, o).num_rooms, 1) << "an open alcove belongs to the room";
  for (int y = 20; y < 50; ++y)
    for (int x = 90; x < 92; ++x)
      if (plan.at(x, y) == FloorCell::kFree) plan.cells.at(x, y) = uint8_t(FloorCell::kDoor);
  const RoomSegmentation rooms = SegmentRooms(plan, o);
  EXPECT_EQ(rooms.num_rooms, 2);
  ExpectEveryFloorCellInOneRoom(plan, rooms);
  EXPECT_NE(rooms.room_ids.at(40, 40), rooms.room_ids.at(98, 35));
  RoomSegmentationOptions old_rule = o;
  old_rule.door_min_room_radius_m = old_rule.min_room_radius_m;
  EXPECT_EQ(SegmentRooms(plan, old_rule).num_rooms, 1);
}

// Unseen pockets (unknown cells) that one room and walls enclose join that room's extent with its type; the
// segmentation's floor ids stay as they were. A pocket between two rooms, one reaching the map's border, a
// strip two cells wide, one larger than the limit and every pocket with the limit at 0 stay outside every room.
TEST(JoinEnclosedUnknown, PocketEnclosedByOneRoomJoinsItWithItsType) {
  FloorPlan plan = FloorPlanFromImage(TwoRoomsWithDoor().image, 0.05, FloorPlanOptions());
  auto unknown = [&](int x0, int y0, int x1, int y1) {  // Pixels [x0, x1) x [y0, y1).
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) plan.cells.at(x, y) = uint8_t(FloorCell::kUnknown);
  };
  unknown(10, 10, 22, 18);    // A: 0.24 m2 (96 cells) in the first room's corner, against two walls.
  unknown(86, 35, 94, 41);    // B: across the door, touching both rooms.
  unknown(158, 10, 190, 42);  // D: 2.56 m2 (1024 cells) in the second room's corner.
  unknown(0, 60, 31, 66);     // C: from the map's border through the wall into the first room.
  unknown(120, 68, 150, 70);  // E: a strip two cells wide along the second room's wall, as a wall's inside.
  ASSERT_DOUBLE_EQ(RoomSegmentationOptions().max_enclosed_unknown_m2, 2.0);
  for (RoomSegmentationMethod m : kMethods) {
    const std::string name = RoomSegmentationMethodName(m);
    const RoomSegmentation rooms = SegmentRooms(plan, WithMethod(m));
    ASSERT_EQ(rooms.num_rooms, 2) << name;
    ExpectEveryFloorCellInOneRoom(plan, rooms);
    const int first = rooms.room_ids.at(40, 40), second = rooms.room_ids.at(120, 50);
    ASSERT_NE(first, second) << name;
    EXPECT_EQ(rooms.room_extent_ids.at(15, 15), 0) << name << ": the segmentation leaves pockets out";
    ImageU16 extent = rooms.room_extent_ids, types(plan.width(), plan.height(), 1, 0);
    for (size_t i = 0; i < types.data.size(); ++i) types.data[i] = uint16_t(extent.data[i] ? 5 + extent.data[i] : 0);
    EXPECT_EQ(JoinEnclosedUnknown(plan, 2.0, &extent, &types), 96u) << name;
    for (int y = 10; y < 18; ++y)
      for (int x = 10; x < 22; ++x) {
        EXPECT_EQ(extent.at(x, y), first) << name << " A (" << x << ", " << y << ")";
        EXPECT_EQ(types.at(x, y), 5 + first) << name << " A";
      }
    EXPECT_EQ(extent.at(90, 38), 0) << name << " B";
    EXPECT_EQ(extent.at(170, 20), 0) << name << " D";
    EXPECT_EQ(extent.at(20, 62), 0) << name << " C";
    EXPECT_EQ(types.at(20, 62), 0) << name << " C";
    EXPECT_EQ(extent.at(130, 69), 0) << name << " E";
    ImageU16 larger = rooms.room_extent_ids;
    EXPECT_EQ(JoinEnclosedUnknown(plan, 2.56, &larger), 96u + 1024u) << name;
    EXPECT_EQ(larger.at(170, 20), second) << name << " D";
    EXPECT_EQ(larger.at(90, 38), 0) << name << " B";
    ImageU16 off = rooms.room_extent_ids;
    EXPECT_EQ(JoinEnclosedUnknown(plan, 0, &off), 0u) << name;
    EXPECT_EQ(off.data, rooms.room_extent_ids.data) << name;
  }
}

// Property: on random furnished floor plans (rooms on a grid with random doors, random furniture and
// specks), every floor cell ends in exactly one room, whatever the method.
TEST(SegmentRooms, EveryFloorCellInExactlyOneRoomOnRandomPlans) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  for (int trial = 0; trial < 6; ++trial) {
    GreyMap map(260, 200);
    map.Fill(0.5, 0.5, 12.5, 9.5, 255);
    // Walls every ~4 m with doors at random places.
    for (double x = 4.5; x < 12; x += 4) {
      map.Fill(x, 0.5, x + 0.1, 9.5, 0);
      const double d = 1 + 6 * u(rng);
      map.Fill(x, d, x + 0.1, d + 0.9, 255);
    }
    map.Fill(0.5, 5.0, 12.5, 5.1, 0);
    for (double x = 1.5; x < 12; x += 4) map.Fill(x, 5.0, x + 0.9, 5.1, 255);
    for (int k = 0; k < 25; ++k) {  // Furniture and specks.
      const double x = 0.5 + 12 * u(rng), y = 0.5 + 9 * u(rng), s = 0.05 + 0.6 * u(rng);
      map.Fill(x, y, x + s, y + s * (0.5 + u(rng)), 0);
    }
    const FloorPlan plan = FloorPlanFromImage(map.image, 0.05, FloorPlanOptions());
    for (RoomSegmentationMethod m : kMethods) {
      RoomSegmentationOptions o = WithMethod(m);
      o.max_speck_distance_m = 100;  // Every speck joins a room.
      const RoomSegmentation rooms = SegmentRooms(plan, o);
      ExpectEveryFloorCellInOneRoom(plan, rooms);
      EXPECT_GE(rooms.num_rooms, 2);
    }
  }
}

TEST(SegmentRooms, EmptyPlanHasNoRooms) {
  GreyMap map(30, 20);
  const FloorPlan plan = FloorPlanFromImage(map.image, 0.05, FloorPlanOptions());
  for (RoomSegmentationMethod m : kMethods) EXPECT_EQ(SegmentRooms(plan, WithMethod(m)).num_rooms, 0);
}

TEST(RoomSegmentationOptions, CheckNamesTheField) {
  RoomSegmentationOptions o;
  std::string error;
  EXPECT_TRUE(o.Check(&error));
  o.saddle_ratio = 0;
  EXPECT_FALSE(o.Check(&error));
  EXPECT_NE(error.find("saddle_ratio = 0"), std::string::npos) << error;
  o = RoomSegmentationOptions();
  o.min_seed_area_m2 = -1;
  EXPECT_FALSE(o.Check(&error));
  EXPECT_NE(error.find("min_seed_area_m2 = -1"), std::string::npos) << error;
}

TEST(RoomSegmentationMethod, NamesRoundTrip) {
  for (const std::string& name : RoomSegmentationMethodNames()) {
    RoomSegmentationMethod m;
    ASSERT_TRUE(ParseRoomSegmentationMethod(name, &m));
    EXPECT_EQ(name, RoomSegmentationMethodName(m));
  }
  RoomSegmentationMethod m;
  EXPECT_FALSE(ParseRoomSegmentationMethod("voronoi?", &m));
}

}  // namespace
}  // namespace semvox
