#include "rooms/room_export.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>

#include "io/image_io.h"
#include "tests/rooms/rooms_test_util.h"
#include "tests/test_util.h"

namespace semvox {
namespace {

double RingArea(const nlohmann::json& ring) {
  double a = 0;
  for (size_t i = 0; i + 1 < ring.size(); ++i)
    a += ring[i][0].get<double>() * ring[i + 1][1].get<double>() - ring[i + 1][0].get<double>() * ring[i][1].get<double>();
  return 0.5 * a;
}

// A plan on a canonical grid turned against the input frame (mapping/scene_frame.h): polygon vertices are
// mapped into the input frame; areas and orientation survive the rigid transform.
TEST(RoomsToGeoJson, MapsPolygonsIntoTheInputFrame) {
  const testing::GreyMap map = testing::TwoRoomsWithDoor();
  const FloorPlan plan = FloorPlanFromImage(map.image, 0.05, FloorPlanOptions());
  const RoomSegmentation rooms = SegmentRooms(plan, RoomSegmentationOptions());
  const std::vector<RoomDescription> described = DescribeRooms(plan, rooms);
  Eigen::Isometry3d input_from_world = Eigen::Isometry3d::Identity();
  input_from_world.rotate(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()));
  input_from_world.pretranslate(Eigen::Vector3d(1.5, -2.0, 0.7));
  const nlohmann::json plain = nlohmann::json::parse(RoomsToGeoJson(described));
  const nlohmann::json moved = nlohmann::json::parse(RoomsToGeoJson(described, input_from_world));
  ASSERT_EQ(plain["features"].size(), moved["features"].size());
  for (size_t f = 0; f < plain["features"].size(); ++f) {
    const auto& a = plain["features"][f]["geometry"]["coordinates"][0];
    const auto& b = moved["features"][f]["geometry"]["coordinates"][0];
    ASSERT_EQ(a.size(), b.size());
    for (size_t i = 0; i < a.size(); ++i) {
      const Eigen::Vector3d q = input_from_world * Eigen::Vector3d(a[i][0].get<double>(), a[i][1].get<double>(), 0.0);
      EXPECT_NEAR(b[i][0].get<double>(), q.x(), 2e-4);
      EXPECT_NEAR(b[i][1].get<double>(), q.y(), 2e-4);
    }
    EXPECT_NEAR(RingArea(a), RingArea(b), 1e-3);
  }
}

TEST(WriteRoomOutputs, WritesIdsGeoJsonAndSvg) {
  testing::ScratchDir dir("rooms_export");
  const testing::GreyMap map = testing::TwoRoomsWithDoor();
  FloorPlan plan = FloorPlanFromImage(map.image, 0.05, FloorPlanOptions());
  plan.origin_x = 10.0;  // A map frame away from the origin.
  plan.origin_y = -2.0;
  const RoomSegmentation rooms = SegmentRooms(plan, RoomSegmentationOptions());
  ASSERT_EQ(rooms.num_rooms, 2);
  ASSERT_TRUE(WriteRoomOutputs(dir.path().string(), plan, rooms).ok());

  // rooms.png: 16-bit, same size, same ids.
  Result<ImageU16> png = ReadImageU16(dir.File("rooms.png"));
  ASSERT_TRUE(png.ok()) << png.status().message();
  EXPECT_EQ(png->width, plan.width());
  EXPECT_EQ(png->height, plan.height());
  EXPECT_EQ(png->data, rooms.room_ids.data);

  // rooms.geojson: one feature per room, unknown types, polygon area close to area_m2, in the map frame.
  const nlohmann::json gj = nlohmann::json::parse(testing::ReadText(dir.File("rooms.geojson")));
  EXPECT_EQ(gj["type"], "FeatureCollection");
  ASSERT_EQ(gj["features"].size(), 2u);
  for (const auto& f : gj["features"]) {
    const auto& p = f["properties"];
    EXPECT_EQ(p["type"], "unknown");
    EXPECT_EQ(p["type_id"], 0);
    EXPECT_TRUE(p["type_probabilities"].is_object());
    EXPECT_TRUE(p["type_probabilities"].empty());
    EXPECT_TRUE(p["ceiling_height_m"].is_null()) << "a 2D map has no ceiling";
    ASSERT_EQ(f["geometry"]["type"], "Polygon");
    const auto& outer = f["geometry"]["coordinates"][0];
    EXPECT_EQ(outer.front(), outer.back()) << "closed ring";
    const double area = RingArea(outer);
    EXPECT_GT(area, 0) << "outer rings are counter-clockwise";
    // The outline runs through border cell centres: half a cell inside the true edge.
    EXPECT_NEAR(area, p["area_m2"].get<double>(), 0.025 * 18.0);
    EXPECT_GT(p["area_m2"].get<double>(), 11.5);  // 3.95 m x 3 m and 4.95 m x 3 m, plus the doorway.
    EXPECT_LT(p["area_m2"].get<double>(), 15.0);
    for (const auto& pt : outer) {
      EXPECT_GE(pt[0].get<double>(), 10.0 + 0.5 - 1e-9);
      EXPECT_LE(pt[0].get<double>(), 10.0 + 9.5 + 1e-9);
      EXPECT_GE(pt[1].get<double>(), -2.0 + 1.0 - 1e-9);  // Image rows 10..70 of 90 -> y in [1, 4] - 2.
      EXPECT_LE(pt[1].get<double>(), -2.0 + 4.0 + 1e-9);
    }
  }
  const std::string svg = testing::ReadText(dir.File("rooms.svg"));
  EXPECT_NE(svg.find("<svg"), std::string::npos);
  EXPECT_NE(svg.find("1 unknown"), std::string::npos);
  EXPECT_NE(svg.find("2: unknown"), std::string::npos) << "legend";
}

TEST(WriteRoomOutputs, UnwritableDirectoryIsAnErrorAndLeavesNoFile) {
  const testing::GreyMap map = testing::TwoRoomsWithDoor();
  const FloorPlan plan = FloorPlanFromImage(map.image, 0.05, FloorPlanOptions());
  const RoomSegmentation rooms = SegmentRooms(plan, RoomSegmentationOptions());
  const Status st = WriteRoomOutputs("/nonexistent_dir_for_semvox/rooms", plan, rooms);
  EXPECT_FALSE(st.ok());
  EXPECT_NE(st.message().find("rooms.png"), std::string::npos) << st.message();
}

}  // namespace
}  // namespace semvox
