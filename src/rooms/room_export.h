// Room outputs of `semvox run` and `semvox rooms`, on the occupancy grid and in the input's frame:
//   rooms.png      16-bit room ids (0 = no room), same size as occupancy.pgm;
//   rooms.geojson  a FeatureCollection, one Polygon (MultiPolygon if a room has several parts) per room in
//                  metres, with properties id, type, type_id, type_probabilities, area_m2, ceiling_height_m;
//   rooms.svg      the floor plan with each room filled, its id and type at its centre, and a legend.
// Room types come from the room-type CRF (rooms/room_type_crf.h, written by pipeline/room_types_stage.h); without
// it every room is "unknown" (id 0) with empty type_probabilities. Typed rooms also carry `probability`,
// `second_type`, `second_type_id` and `second_probability`.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "core/status.h"
#include "rooms/floor_plan.h"
#include "rooms/room_segmentation.h"

namespace semvox {

struct RoomPolygon {
  std::vector<Eigen::Vector2d> outer;               // Counter-clockwise, metres, closed implicitly.
  std::vector<std::vector<Eigen::Vector2d>> holes;  // Clockwise.
};

struct RoomDescription {
  int id = 0;                         // As in rooms.png.
  int type_id = 0;                    // Room type (core/labels.h RoomTypes()); 0 = unknown.
  std::vector<double> type_probabilities;  // Empty, or one per room type id (index = id, 0 = unknown).
  double type_probability = 0;        // Probability of type_id.
  int second_type_id = 0;             // Runner-up type (0 = none) and its probability.
  double second_type_probability = 0;
  double area_m2 = 0;                 // Floor area including the furniture inside, m².
  double ceiling_height_m = 0;        // Median ceiling height above the floor, metres; 0 = unknown.
  Eigen::Vector2d label_point{0, 0};  // A point well inside the room (deepest cell), metres.
  std::vector<RoomPolygon> polygons;  // Outline through the centres of the room's border cells.
};

// Geometry and statistics of every room of `rooms` (ids 1..num_rooms).
std::vector<RoomDescription> DescribeRooms(const FloorPlan& plan, const RoomSegmentation& rooms);

// Polygon vertices (x, y, 0) of the canonical frame are mapped by `input_from_world` and written as their x, y.
std::string RoomsToGeoJson(const std::vector<RoomDescription>& rooms, const Eigen::Isometry3d& input_from_world = Eigen::Isometry3d::Identity());
std::string RoomsToSvg(const FloorPlan& plan, const RoomSegmentation& rooms, const std::vector<RoomDescription>& described);

// 16-bit PNG, written atomically.
Status WriteRoomIdsPng(const std::string& path, const ImageU16& ids);

// Writes rooms.png, and unless `png_only` rooms.geojson and rooms.svg, into `dir`.
Status WriteRoomOutputs(const std::string& dir, const FloorPlan& plan, const RoomSegmentation& rooms,
                        bool png_only = false, const Eigen::Isometry3d& input_from_world = Eigen::Isometry3d::Identity());
// Same, with rooms already described (and typed).
Status WriteRoomOutputs(const std::string& dir, const FloorPlan& plan, const RoomSegmentation& rooms,
                        const std::vector<RoomDescription>& described, const Eigen::Isometry3d& input_from_world = Eigen::Isometry3d::Identity());

}  // namespace semvox
