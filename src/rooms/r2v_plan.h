// Real floor plans in the R2V format (Liu et al., "Raster-to-Vector", ICCV 2017; ../shared/data/r2v), read and
// rasterised in metres (library semvox_rooms).
//
//   ReadR2vPlan(path) --> R2vPlan (items: walls, doors, fixtures, room labels; metres per plan unit)
//   RasteriseR2vRooms(plan) --> R2vRooms (room-id raster flood-filled from the labels, type per room,
//                                          rooms joined by each door)
//
// A plan line is `x0 y0 x1 y1 category a b`: walls and doors are segments, fixtures and room labels boxes.
// Plans carry no scale: swing doors are taken as 0.7 m wide and toilets as 0.72 m long (the median of each, the
// geometric mean of the two), else the median opening as 0.8 m. Rooms are flood-filled from their label
// boxes' centres with walls and doors as barriers; a region reaching the raster's border is the outside of a
// plan that is not closed and is no room. Two labels in one region that disagree leave it untyped.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "core/image.h"
#include "core/status.h"
#include "rooms/room_shape.h"

namespace semvox {

struct R2vItem {
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  std::string category;
  int kind = 0;  // The first number after the category (doors: 1 and 2 swing doors, 3 double or sliding, ...).
};

// The rulers of a plan (ReadR2vPlan): a swing door's width and a toilet's length, metres.
inline constexpr double kR2vSwingDoorWidthM = 0.7;
inline constexpr double kR2vToiletLengthM = 0.72;

struct R2vPlan {
  std::vector<R2vItem> items;
  double metres_per_unit = 0;  // From the swing doors and toilets (ReadR2vPlan).
  int doors = 0;
};

// Errors (one line naming the file): unreadable, no line in the R2V format, no door (no scale).
Result<R2vPlan> ReadR2vPlan(const std::string& path);

// room_types.tsv id of an R2V room label (bathroom, restroom, bedroom, corridor, kitchen, washing_room,
// living_room, stairs, closet, PS, balcony), 0 for other labels.
int R2vRoomTypeId(const std::string& category);
// True for the categories that label a room (typed or not: entrance, special too).
bool IsR2vRoomLabel(const std::string& category);

struct R2vRooms {
  double resolution_m = 0.05;
  // Plan metres (units x metres_per_unit) of pixel (0, 0)'s lower corner: pixel (c, r) covers
  // [origin_m + c res, origin_m + (c + 1) res) on both axes (the raster keeps a 5-pixel margin).
  double origin_m = 0;
  ImageU16 ids;                               // Room id per pixel, 0 outside rooms, walls and doors.
  std::vector<int> type_id;                   // Per id (index 0 unused): room_types.tsv id, 0 untyped.
  std::vector<std::vector<int>> connections;  // Per id: the rooms a door of the plan joins it to.
};

R2vRooms RasteriseR2vRooms(const R2vPlan& plan, double resolution_m = 0.05);

// plan_*.txt of `dir` in sorted order (empty when there are none).
std::vector<std::string> ListR2vPlans(const std::string& dir);

// The split of the real plans: the first kR2vTrainingPlans sorted plans (0-299) train every model that reads
// R2V plans; the rest (300-399) are for validation only.
inline constexpr int kR2vTrainingPlans = 300;

// The typed rooms of the plans (unreadable plans and plans without doors are skipped and counted in
// `skipped`), with their shapes and pixel areas.
struct R2vRoomSample {
  RoomShapeSample sample;
  int plan = 0;  // Index into `files`.
};
std::vector<R2vRoomSample> R2vRoomShapes(const std::vector<std::string>& files, int* skipped = nullptr);

// What `semvox train --room-shapes` reports: the model alone (uniform type prior: the argmax of its ratios)
// on the typed rooms of the validation plans.
struct RoomShapeTrainingReport {
  int train_plans = 0, val_plans = 0, skipped_plans = 0, train_rooms = 0, val_rooms = 0;
  double val_room_accuracy = 0;   // Rooms whose argmax is their type.
  double val_area_accuracy = 0;   // The same weighted by area (as a pixel accuracy).
  double val_class_average = 0;   // Mean over the types present of the area-weighted recall.
  std::array<std::array<double, kRoomShapeTypes>, kRoomShapeTypes> confusion_m2{};  // [true][predicted], m².
  // The shape with the adjacency term's room-level mean field (AdjacencyMessages) at these weights.
  std::vector<double> adjacency_weights = {0.25, 0.5, 1.0, 2.0};
  std::vector<double> adjacency_area_accuracy, adjacency_class_average;
  std::string ToText() const;
};

// Trains on the first `train_plans` sorted plans of `dir` and validates on the rest (the split of the
// real-layouts work: plans 0-299 train, 300-399 validation).
// `features`: indices into RoomShape::Vector() (RoomShapeFeatureNames()); the adjacency is learnt from the
// same plans' doors.
Result<RoomShapeModel> TrainRoomShapesFromR2v(const std::string& dir, int train_plans, RoomShapeTrainingReport* report,
                                              const std::vector<int>& features = {0, 1, 2, 3, 4, 5});

}  // namespace semvox
